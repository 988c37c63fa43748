// Running the Khronos glTF validator (npm package gltf-validator, installed by scripts/setup.sh
// into tests/gltf_validate) from a test.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cagewrap::test {

inline bool node_available() {
  return std::system("node --version > /dev/null 2>&1") == 0;
}

// Exit status of validate.js over `files` (0: no errors; 2: the validator is not installed); its
// report (a line "FILE: N errors, ..." per file) goes to `report_file` and into `log`.
inline int run_gltf_validator(const std::vector<std::string>& files, const std::string& report_file,
                              std::string& log) {
  std::string cmd = "node '" + std::string(CAGEWRAP_SOURCE_DIR) + "/tests/gltf_validate/validate.js'";
  for (const auto& f : files) cmd += " '" + f + "'";
  cmd += " > '" + report_file + "' 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(report_file);
  std::stringstream ss;
  ss << in.rdbuf();
  log = ss.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace cagewrap::test
