// Headless subcommands of the one `cagewrap` binary. Each lives in its own cmd_*.cpp and registers
// itself on the CLI11 app; main() dispatches.
#pragma once

#include <CLI/CLI.hpp>

namespace cagewrap::app {

// Each returns nothing; the subcommand's callback sets `exit_code`.
void add_bind_command(CLI::App& app, int& exit_code);
void add_deform_command(CLI::App& app, int& exit_code);
void add_bench_command(CLI::App& app, int& exit_code);
// bench --project (app/cmd_bench_stack.cpp): the deformer stack's cost against the sum of its deformers'.
int bench_stack(const std::string& project, const std::string& clip, uint32_t frames, bool json);
void add_info_command(CLI::App& app, int& exit_code);
void add_skin_command(CLI::App& app, int& exit_code);
void add_make_demo_command(CLI::App& app, int& exit_code);
void add_new_command(CLI::App& app, int& exit_code);
void add_cage_command(CLI::App& app, int& exit_code);
void add_cage_edit_command(CLI::App& app, int& exit_code);
void add_pose_command(CLI::App& app, int& exit_code);
void add_export_command(CLI::App& app, int& exit_code);
void add_project_command(CLI::App& app, int& exit_code);
void add_simulate_command(CLI::App& app, int& exit_code);
void add_demo_sim_command(CLI::App& app, int& exit_code);
void add_patch_command(CLI::App& app, int& exit_code);  // parametric drivers (cmd_patch.cpp)
void add_check_command(CLI::App& app, int& exit_code);  // fidelity to the file's skinning (cmd_check.cpp)
void add_probe_command(CLI::App& app, int& exit_code);  // a Lipschitz figure for a binding (cmd_probe.cpp)
void add_actions_command(CLI::App& app, int& exit_code);  // the editor's action table (cmd_actions.cpp)
void add_deformer_command(CLI::App& app, int& exit_code);  // the deformer stack (cmd_deformer.cpp)

}  // namespace cagewrap::app
