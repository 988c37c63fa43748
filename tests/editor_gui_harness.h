// Running the real editor under Xvfb for the GUI tests: whether it can run here, and the command
// line (with its own config folder, so a test never reads or writes the user's preferences).
#pragma once

#include <cstdlib>
#include <string>

namespace cagewrap::test {

// False (with the reason) when the editor was not built or xvfb-run is missing.
inline bool gui_available(std::string& why) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    why = "xvfb-run not installed";
    return false;
  }
  if (!CAGEWRAP_TESTS_HAVE_EDITOR) {
    why = "cagewrap was built without the editor (CAGEWRAP_GUI=OFF)";
    return false;
  }
  return true;
}

// The shell command that runs the editor on a 1280 x 720 virtual screen with `args`, its
// preferences in `config_dir`, and stdout and stderr in `log`.
inline std::string editor_command(const std::string& args, const std::string& config_dir,
                                  const std::string& log) {
  return "CAGEWRAP_CONFIG_DIR='" + config_dir + "' xvfb-run -a -s '-screen 0 1280x720x24' " +
         std::string(CAGEWRAP_BINARY) + " " + args + " > '" + log + "' 2>&1";
}

}  // namespace cagewrap::test
