// Command-line options of the automatic cage, shared by `cagewrap cage` and `cagewrap new
// --auto-cage`, and the report both print.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "core/rig/auto_cage.h"
#include "core/document/document.h"

namespace cagewrap::app {

struct AutoCageOptions {
  AutoCageParams params;
  bool no_fit = false;
  bool one_surface = false;
  std::string wrap = "auto";
};

// Adds the face-count option (named `faces_flag`: "--faces", "--auto-cage") and --quads/--no-quads,
// --joint-detail, --joint-radius, --inflate, --concave-share, --inflate-absolute, --wrap,
// --one-surface, --no-fit. Returns the face-count option.
CLI::Option* add_auto_cage_options(CLI::App& cmd, AutoCageOptions& opts, const std::string& faces_flag);
// Completes the parameters (bind parameters for the quality figure); prints and returns false on a
// bad value.
bool finish_auto_cage_options(AutoCageOptions& opts, const BindParams& bind);
// A progress bar on stderr when it is a terminal.
AutoCageProgress terminal_cage_progress();
void print_cage_report(const AutoCageReport& r, const AutoCageParams& p);
// Builds the automatic cage of `doc`'s character (`character_path` for messages, with a progress
// bar) and puts it into the document, printing the report unless `quiet`; prints the error and
// returns false when the build fails.
bool add_automatic_cage(Document& doc, const AutoCageParams& params, const std::string& character_path, bool quiet);

}  // namespace cagewrap::app
