#!/usr/bin/env bash
# libFuzzer smoke run (issue 8): builds every parser's fuzz target with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in build-fuzz/, then runs each for SECONDS seconds (default 60) from a
# seed corpus taken from tests/. Prints executions and findings per target; exit 1 on a finding.
# Usage: bash scripts/fuzz.sh [SECONDS] [TARGET ...]   (targets: msh csv npy npz mat dataset model results)
set -euo pipefail
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(msh csv npy npz mat dataset model results)
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
command -v clang++ > /dev/null || { echo "fuzz.sh: needs clang (apt-get install clang)" >&2; exit 1; }
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DEITBENCH_FUZZ=ON -DEITBENCH_BUILD_TESTS=OFF \
  -DEITBENCH_BUILD_BENCHMARKS=OFF > /dev/null
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}"

# The seeds of each target: the lists tests/fuzz/CMakeLists.txt writes, which the CTest smoke job
# uses too. The model target's list ends with a trained model, made here when a normal build can
# train one in a second.
if [[ " ${targets[*]} " == *" model "* ]] && [ -x "$root/build/eitbench" ] && [ ! -f "$build/fuzz_seed_model.pt" ]; then
  "$root/build/eitbench" simulate --preset tiny --density coarse --quiet --out "$build/seed.h5" > /dev/null
  "$root/build/eitbench" train --data "$build/seed.h5" --steps 1 --quiet --out "$build/fuzz_seed_model.pt" > /dev/null
fi

export ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1
status=0
printf '%-8s %12s %10s %s\n' target executions exec/s findings
for t in "${targets[@]}"; do
  corpus=$build/corpus/$t findings=$build/findings/$t
  mkdir -p "$corpus" "$findings"
  while read -r f; do cp -n "$f" "$corpus/" 2> /dev/null || true; done < "$build/fuzz_seeds/$t.txt"
  log=$build/fuzz_$t.log
  # The dataset target's libhdf5 runs in a forked child (bench/io/include/eitbench/bench/io/child_read.h), which inherits
  # libFuzzer's malloc hook: without this, libhdf5's exabyte requests there, which the parent
  # reports as a corrupt file, would be filed as out-of-memory findings.
  # Elsewhere a single allocation of 1 GB, or a peak of 2 GB, from an input of a few kB is a
  # finding: the memory rule (jacobian/include/eitbench/jacobian/read_budget.h) should refuse it.
  extra=(-malloc_limit_mb=1024)
  [ "$t" = dataset ] && extra=(-malloc_limit_mb=1048576)
  if "$build/fuzz_$t" "$corpus" -max_total_time="$seconds" -timeout=10 "${extra[@]}" \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/" > "$log" 2>&1; then
    found=0
  else
    found=1 status=1
  fi
  # The last statistics are the fuzzer's own (a dying child of the dataset target prints some too).
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
  printf '%-8s %12s %10s %s\n' "$t" "$runs" "$rate" \
    "$([ $found = 0 ] && echo none || echo "FOUND: $(ls "$findings" | head -3 | tr '\n' ' ') (see $log)")"
done
exit $status
