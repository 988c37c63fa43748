// Where the shared real test data lives (../shared/assets): $CAGEWRAP_SHARED_ASSETS, else the folder
// CMake was configured with. Tests that need it GTEST_SKIP() with a message when neither exists.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace cagewrap::test {

inline std::optional<std::string> shared_assets_dir() {
  std::string dir;
  if (const char* env = std::getenv("CAGEWRAP_SHARED_ASSETS"); env && *env)
    dir = env;
  else
    dir = CAGEWRAP_SHARED_ASSETS_DEFAULT;
  std::error_code ec;
  if (dir.empty() || !std::filesystem::is_directory(dir, ec)) return std::nullopt;
  return dir;
}

// A file in the shared assets, or nullopt when the folder or the file is absent.
inline std::optional<std::string> shared_asset(const std::string& name) {
  auto dir = shared_assets_dir();
  if (!dir) return std::nullopt;
  std::string path = *dir + "/" + name;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  return path;
}

}  // namespace cagewrap::test

using cagewrap::test::shared_assets_dir;

// Declares `const std::string var` = the assets folder, or skips the test with a message.
#define CAGEWRAP_REQUIRE_ASSETS(var)                                                                 \
  auto var##_opt = cagewrap::test::shared_assets_dir();                                              \
  if (!var##_opt) GTEST_SKIP() << "shared assets not found (set CAGEWRAP_SHARED_ASSETS); skipping"; \
  const std::string var = *var##_opt
