// Helpers shared by the headless subcommands: binding options, loading, reporting.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/deform/binding.h"
#include "core/deform/patch_surface.h"
#include "core/cage/cage.h"
#include "core/geometry/mesh.h"
#include "core/document/project_io.h"
#include "core/deform/registration.h"
#include "core/rig/rig.h"

namespace cagewrap::app {

struct BindOptions {
  BindParams params;
  std::string variant = variant_name(BindParams{}.variant);
  // set by add_bind_options: tells which options the command line gave
  CLI::Option* local_option = nullptr;
  CLI::Option* epsilon_option = nullptr;
  CLI::Option* max_elements_option = nullptr;
  CLI::Option* scale_option = nullptr;
  CLI::Option* max_distance_option = nullptr;
  CLI::Option* variant_option = nullptr;
};
// Adds --local, --epsilon, --max-elements, --scale, --max-distance, --variant to a subcommand.
void add_bind_options(CLI::App& cmd, BindOptions& opts);
// Turns the parsed options into parameters; prints and returns false on a bad value.
bool finish_bind_options(BindOptions& opts);
// The bind options given on the command line (after finish_bind_options) whose value differs from
// `bound`, the parameters a loaded binding was made with, as "--variant extended (the binding's:
// clamped)", joined by ", "; empty when there are none.
std::string bind_options_differing(const BindOptions& opts, const BindParams& bound);
// Whether any bind option was given, and `base` with those given laid over it (printing the error and
// returning nullopt when the result is not valid): `deformer set` changes one deformer's parameters.
bool any_bind_option(const BindOptions& opts);
std::optional<BindParams> bind_options_over(const BindOptions& opts, const BindParams& base);

// Loads a mesh or cage, printing "error: <message>" on failure.
std::optional<PolyMesh> load_mesh_or_report(const std::string& path);
std::optional<Cage> load_cage_or_report(const std::string& path);
// A parametric driver (.cwpatch .gltf .glb) at rest, sculpted as `posed_path` says (the same grids moved;
// "" = no sculpt), with `density` samples per knot span (1..1024), driving the skin; null (printed) when
// a file cannot be read or does not fit.
std::shared_ptr<const PatchDriver> load_driver_or_report(const std::string& path, const std::string& posed_path, uint32_t density);
// A posed copy of `cage` (loaded from `cage_path`): the same vertex and face counts, or a message naming both files.
std::optional<PolyMesh> load_posed_cage_or_report(const std::string& path, const Cage& cage, const std::string& cage_path);
// Loads a project, printing "error: <message>" on failure and "warning: <message>" for each warning.
std::optional<ProjectLoad> load_project_or_report(const std::string& path);

// --keep-units on a command that reads a character: FBX, Collada, ... in the file's own units and up axis.
void add_keep_units_flag(CLI::App& cmd, bool& keep);

int report_error(const Error& e);  // prints to stderr, returns the exit code (1)
// Whether `path` names a positions output (.obj or .bin); prints the error when not.
bool positions_output_or_report(const std::string& path);

// One line per fact: points, elements (and the `num_polygons` cage polygons they triangulate), set
// sizes, affected elements and points, quality, seconds.
void print_bind_summary(const Binding& b, const std::string& cage_path, size_t num_polygons);

// A progress bar on stderr when it is a terminal.
BindProgress terminal_progress(const char* label);

// The rig of a loaded project (`project`: its path, for messages): from the project's cached
// binding when it is still valid (core/document/binding_cache.h; a note on stderr), else bound with a
// progress bar (saying why the cache was not used). Prints the error (no cage yet, a failed bind)
// and returns nullopt.
std::optional<Rig> rig_of_project(const Document& doc, const std::string& project);
// Save options that cache every binding of `rig` (the document's cage's and each layer's that is not muted).
SaveOptions save_options_caching(const Rig& rig, const Document& doc);

}  // namespace cagewrap::app
