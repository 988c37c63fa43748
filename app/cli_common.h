// Helpers shared by the headless subcommands: binding options, loading, reporting.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/binding.h"
#include "core/cage.h"
#include "core/mesh.h"
#include "core/registration.h"

namespace cagewrap::app {

struct BindOptions {
  BindParams params;
  std::string variant = variant_name(BindParams{}.variant);
};
// Adds --local, --epsilon, --max-elements, --scale, --max-distance, --variant to a subcommand.
void add_bind_options(CLI::App& cmd, BindOptions& opts);
// Turns the parsed options into parameters; prints and returns false on a bad value.
bool finish_bind_options(BindOptions& opts);

// Loads a mesh or cage, printing "error: <message>" on failure.
std::optional<PolyMesh> load_mesh_or_report(const std::string& path);
std::optional<Cage> load_cage_or_report(const std::string& path);

int report_error(const Error& e);  // prints to stderr, returns the exit code (1)

// One line per fact: points, elements, set sizes, affected elements and points, quality, seconds.
void print_bind_summary(const Binding& b, const std::string& cage_path);

// A progress bar on stderr when it is a terminal.
BindProgress terminal_progress(const char* label);

}  // namespace cagewrap::app
