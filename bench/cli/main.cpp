// eitbench: the command-line tool. Each subcommand lives in its own file; this one dispatches and
// turns errors into messages and exit codes (2 for bad input, 1 for anything else).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <map>

#include "commands.h"
#include "eitbench/bench/io/output_path.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/support/allocator.h"
#include "eitbench/bench/support/blas_kernels.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned/runtime.h"
#include "flag_names.h"
#include "world.h"

namespace {

// LibTorch's version and devices, loading learned/'s module; why not, where it cannot be loaded.
std::string torch_text() {
  try {
    return eitbench::torch_runtime();
  } catch (const std::exception& e) {
    return std::string("LibTorch: ") + e.what();
  }
}

}  // namespace

int main(int argc, char** argv) {
  eitbench::use_the_cpus_blas_kernels(argv);  // may run the program again, before anything else
  eitbench::keep_freed_memory();
  eitbench::cli::join_world(argc, argv);  // under mpirun: this rank's place (docs/scaling.md)
  CLI::App app{
      "eitbench: electrical impedance tomography for tactile sensing, toolkit and benchmark"};
  app.set_version_flag("--version", [] {
    // What this build can do: the optional parts (docs/gpu.md) and where training runs.
    const auto& methods = eitbench::method_names();
    const bool shape = std::find(methods.begin(), methods.end(), "shape") != methods.end();
    return fmt::format(
        "{}\nGmsh meshing: {}; PNG figures: {}; shape fit (Ceres): {}; MPI: {}; "
        "BLAS kernels: {}; {}",
        eitbench::program_version(),
        eitbench::can_generate_disk_mesh() ? "yes" : "no (EITBENCH_MESH_DIR)",
        eitbench::can_draw_figures() ? "yes" : "no", shape ? "yes" : "no",
        eitbench::cli::built_with_mpi() ? "yes" : "no", eitbench::blas_kernels(), torch_text());
  });
  app.require_subcommand(1);
  std::map<CLI::App*, std::function<void()>> actions;
  for (auto add : {eitbench::cli::add_mesh_command, eitbench::cli::add_forward_command,
                   eitbench::cli::add_jacobian_command, eitbench::cli::add_augment_command,
                   eitbench::cli::add_simulate_command, eitbench::cli::add_info_command,
                   eitbench::cli::add_show_command, eitbench::cli::add_import_command,
                   eitbench::cli::add_train_command, eitbench::cli::add_reconstruct_command,
                   eitbench::cli::add_run_command, eitbench::cli::add_report_command,
                   eitbench::cli::add_compare_command, eitbench::cli::add_calibrate_command,
                   eitbench::cli::add_history_command, eitbench::cli::add_merge_command,
                   eitbench::cli::add_ktc_command}) {
    auto action = add(app);
    actions[app.get_subcommands({}).back()] = action;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a flag CLI11 refuses (unknown, out of range, missing) is bad input, 2 like
    // every other, not CLI11's own code (105 for a value out of range).
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    for (auto* sub : app.get_subcommands()) {
      // Every file named on the command line but the outputs (--out, mesh --png, reconstruct
      // --presses-csv) is an input that no output may replace.
      std::vector<std::string> files;
      for (const CLI::Option* option : sub->get_options())
        if (!option->check_lname("out") && !option->check_lname("png") &&
            !option->check_lname("presses-csv"))
          files.insert(files.end(), option->results().begin(), option->results().end());
      eitbench::declare_inputs(files);
      // Under mpirun only the commands that shard their work by rank; any other would run once a
      // rank, each writing the same output (merge would even start a sharded run).
      if (eitbench::cli::world().parallel() && sub->get_name() != "simulate" &&
          sub->get_name() != "run")
        throw eitbench::InputError(sub->get_name(), "",
                                   "does not shard by rank: under mpirun only simulate and run "
                                   "do; run it as one process");
      actions.at(sub)();
    }
  } catch (const eitbench::cli::RegressionFound&) {
    return 1;
  } catch (const eitbench::InputError& e) {
    // A library names the options field; the user typed the flag.
    const auto chosen = app.get_subcommands();
    const std::string command = chosen.empty() ? "" : chosen.front()->get_name();
    fmt::print(stderr, "eitbench: error: {}\n", eitbench::cli::name_the_flag(e, command).what());
    eitbench::cli::abort_world(2);
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "eitbench: error: {}\n", e.what());
    eitbench::cli::abort_world(1);
    return 1;
  } catch (...) {  // a library's own exception type (HDF5's is not a std::exception)
    fmt::print(stderr, "eitbench: error: an unexpected exception that is not a std::exception\n");
    eitbench::cli::abort_world(1);
    return 1;
  }
  return 0;
}
