#pragma once
// What both microbenchmark programs do unless told otherwise: each benchmark runs 9 times (the
// fewest repetitions eitbench compare decides on, as Google Benchmark's compare.py advises), the
// console shows the aggregates, and every repetition goes to a Google Benchmark JSON file, the
// input of `eitbench compare` and `eitbench history add`. A flag given on the command line wins.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <vector>

namespace eitbench::micro {

// argv with the defaults added for the flags it lacks; the strings live as long as the program.
inline std::vector<char*> with_regression_defaults(int argc, char** argv,
                                                   const std::string& json_file) {
  static std::vector<std::string> added;
  auto given = [&](const std::string& flag) {
    for (int k = 1; k < argc; ++k)
      if (std::string(argv[k]).rfind(flag, 0) == 0) return true;
    return false;
  };
  std::vector<char*> out(argv, argv + argc);
  added.reserve(4);  // pointers into it are handed out: no reallocation
  auto add = [&](const std::string& flag) { out.push_back(added.emplace_back(flag).data()); };
  if (!given("--benchmark_repetitions")) add("--benchmark_repetitions=9");
  if (!given("--benchmark_display_aggregates_only") && !given("--benchmark_report_aggregates_only"))
    add("--benchmark_display_aggregates_only=true");
  if (!given("--benchmark_out=") && !given("--benchmark_list_tests")) {
    add("--benchmark_out=" + json_file);
    if (!given("--benchmark_out_format")) add("--benchmark_out_format=json");
    std::fprintf(stderr, "every repetition goes to %s (--benchmark_out=FILE to choose)\n",
                 json_file.c_str());
  }
  out.push_back(nullptr);
  return out;
}

// Google Benchmark's main with those defaults; the exit status.
inline int run_microbenchmarks(int argc, char** argv, const std::string& json_file) {
  std::vector<char*> args = with_regression_defaults(argc, argv, json_file);
  int count = static_cast<int>(args.size()) - 1;
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace eitbench::micro
