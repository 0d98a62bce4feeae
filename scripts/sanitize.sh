#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer (issue 8), in build-asan/.
# About three times slower than the Release suite. Usage: bash scripts/sanitize.sh [ctest args]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-asan
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEITBENCH_SANITIZE=ON \
  -DEITBENCH_BUILD_BENCHMARKS=OFF > /dev/null
cmake --build "$build" -j2
# Leak checking is off: LibTorch and OpenMP keep their pools alive to exit by design.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$build" --output-on-failure -j2 "$@"
