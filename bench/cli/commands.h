#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace eitbench::cli {
// Each registers its subcommand and returns the action to run when it is chosen.
std::function<void()> add_mesh_command(CLI::App& app);
std::function<void()> add_forward_command(CLI::App& app);
std::function<void()> add_jacobian_command(CLI::App& app);
std::function<void()> add_augment_command(CLI::App& app);
std::function<void()> add_simulate_command(CLI::App& app);
std::function<void()> add_info_command(CLI::App& app);
std::function<void()> add_show_command(CLI::App& app);
std::function<void()> add_import_command(CLI::App& app);
std::function<void()> add_reconstruct_command(CLI::App& app);
std::function<void()> add_run_command(CLI::App& app);
std::function<void()> add_train_command(CLI::App& app);
std::function<void()> add_report_command(CLI::App& app);
std::function<void()> add_compare_command(CLI::App& app);
std::function<void()> add_calibrate_command(CLI::App& app);
std::function<void()> add_history_command(CLI::App& app);
std::function<void()> add_merge_command(CLI::App& app);
std::function<void()> add_ktc_command(CLI::App& app);

// Thrown by compare when it found a regression: exit status 1, the table already printed.
struct RegressionFound {};
}  // namespace eitbench::cli
