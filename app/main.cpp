// cagewrap: no arguments opens the editor; subcommands work headless for pipelines and tests.
#include <cstdio>

#include "app/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"cagewrap: skin characters with surface-oriented free-form deformation cages"};
  app.set_version_flag("--version", std::string("cagewrap ") + CAGEWRAP_VERSION);
  int exit_code = 0;
  cagewrap::app::add_bind_command(app, exit_code);
  cagewrap::app::add_deform_command(app, exit_code);
  cagewrap::app::add_bench_command(app, exit_code);
  cagewrap::app::add_info_command(app, exit_code);
  cagewrap::app::add_skin_command(app, exit_code);
  cagewrap::app::add_make_demo_command(app, exit_code);
  cagewrap::app::add_cage_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (app.get_subcommands().empty()) {
    // The editor arrives with the editor issue; until then, show what the command line offers.
    std::fputs(app.help().c_str(), stdout);
  }
  return exit_code;
}
