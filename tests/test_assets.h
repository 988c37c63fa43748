// Where the real test data lives (../shared/assets): the CAGEWRAP_SHARED_ASSETS environment variable,
// else the folder CMake was configured with. Tests skip with a message when it is absent.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

inline std::optional<std::string> shared_assets_dir() {
  const char* env = std::getenv("CAGEWRAP_SHARED_ASSETS");
  std::string dir = env && *env ? env : CAGEWRAP_SHARED_ASSETS_DEFAULT;
  if (std::filesystem::is_directory(dir)) return dir;
  return std::nullopt;
}

#define CAGEWRAP_REQUIRE_ASSETS(var)                                                                 \
  auto var##_opt = shared_assets_dir();                                                              \
  if (!var##_opt) GTEST_SKIP() << "shared assets not found (set CAGEWRAP_SHARED_ASSETS); skipping"; \
  const std::string var = *var##_opt
