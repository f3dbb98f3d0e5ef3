#include "common/test_paths.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

namespace curvedslicer::testing {

namespace fs = std::filesystem;

fs::path modelPath(const std::string& name) { return fs::path(CURVEDSLICER_MODELS_DIR) / name; }

fs::path cliPath() { return fs::path(CURVEDSLICER_CLI); }

fs::path freshTempDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "global";
  if (!tag.empty()) name += "." + tag;
  const fs::path dir = fs::temp_directory_path() /
                       ("curvedslicer-test-" + std::to_string(::getuid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace curvedslicer::testing
