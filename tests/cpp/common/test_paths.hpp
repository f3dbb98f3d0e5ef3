// Locations used by tests: bundled models, the CLI binary, and a per-test temporary folder.
#pragma once

#include <filesystem>
#include <string>

namespace curvedslicer::testing {

/// resources/models/<name>
std::filesystem::path modelPath(const std::string& name);

/// The built `curvedslicer` command-line binary.
std::filesystem::path cliPath();

/// A fresh, empty folder for the currently running test (removed and re-created on each call
/// with the same `tag`). Lives under the build tree's temp folder.
std::filesystem::path freshTempDir(const std::string& tag = "");

}  // namespace curvedslicer::testing
