#include "common/test_paths.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

namespace curvedslicer::testing {

namespace fs = std::filesystem;

fs::path modelPath(const std::string& name) {
  return fs::path(CURVEDSLICER_MODELS_DIR) / name;
}

fs::path cliPath() {
  return fs::path(CURVEDSLICER_CLI);
}

fs::path freshTempDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "global";
  if (!tag.empty()) name += "." + tag;
  // Each build tree has its own scratch folder (CURVEDSLICER_TEST_TMP_DIR, set by CMake), so
  // test runs of two checkouts on one machine do not wipe each other's folders.
  const fs::path base = fs::path(CURVEDSLICER_TEST_TMP_DIR);
  const fs::path dir = base / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace curvedslicer::testing
