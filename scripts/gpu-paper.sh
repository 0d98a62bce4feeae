#!/usr/bin/env bash
# The paper preset on a lent GPU, spread over sessions of limited device time (docs/gpu.md,
# "Across sessions"). One call: build if needed, put back the stages an earlier session finished,
# run until SECONDS have passed or the run ends, and pack what a next session needs: the stages/
# folder (a few MB: the model-based methods, each learned model's scores, each sweep point) and,
# once the run has ended, its results. Model files and the data set stay behind: the data set is
# simulated again from its seed, and the learned models resume from their records.
# Usage: scripts/gpu-paper.sh RUN BACK [SECONDS]
#   RUN      the run folder on this machine (made if missing)
#   BACK     where the files to take away are written: stages.tar.gz, run.log, and, when the
#            run has ended, results.tar.gz (results.json, results.csv, report.md, figure data)
#   SECONDS  the run's wall-clock limit (default 480), so the call ends inside its own limit
# Environment: STAGES (an earlier stages.tar.gz to resume from), BUILD (build-gpu; made by
# scripts/gpu-build.sh when it has no eitbench), PRESET (paper), THREADS (16: part of every
# record's provenance, so keep it the same in every session), METHODS (the model-based methods;
# default tikhonov noser laplace greit), RUN_FLAGS (more flags for eitbench run).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 2 ] || { sed -n '8,18p' "$0" >&2; exit 2; }
run_dir=$(realpath -m "$1")
back=$(realpath -m "$2")
seconds=${3:-480}
build=$(realpath -m "${BUILD:-$root/build-gpu}")
preset=${PRESET:-paper}
threads=${THREADS:-16}
methods=${METHODS:-tikhonov noser laplace greit}
mkdir -p "$back"
if [ ! -x "$build/eitbench" ]; then
  "$root/scripts/gpu-build.sh" "$build" > "$back/build.log" 2>&1 \
    || { tail -20 "$back/build.log"; exit 1; }
fi
# shellcheck disable=SC1091
[ -f "$build/env.sh" ] && source "$build/env.sh"
if [ -n "${STAGES:-}" ]; then
  [ -f "$STAGES" ] || { echo "gpu-paper.sh: STAGES=$STAGES: no such file" >&2; exit 2; }
  mkdir -p "$run_dir"
  tar -xzf "$STAGES" -C "$run_dir"  # stages/: what is there already is replaced by the same
fi
status=0
# shellcheck disable=SC2086
timeout --signal=TERM "$seconds" "$build/eitbench" run --preset "$preset" --out "$run_dir" \
  --resume --threads "$threads" --methods $methods ${RUN_FLAGS:-} > "$back/run.log" 2>&1 \
  || status=$?
tr '\r' '\n' < "$back/run.log" | grep -v '^\s*$' | grep -vE '[0-9]+% \(' | tail -40
[ -d "$run_dir/stages" ] && tar -czf "$back/stages.tar.gz" -C "$run_dir" stages
if [ "$status" = 0 ] && [ -f "$run_dir/results.json" ]; then
  (cd "$run_dir" && tar -czf "$back/results.tar.gz" results.json results.csv report.md \
    reconstructions.npy ./*.dat ./*.gp 2>/dev/null || true)
  echo "gpu-paper.sh: the run has ended; its results are in $back/results.tar.gz"
elif [ "$status" = 124 ]; then
  echo "gpu-paper.sh: stopped after $seconds s; go on with STAGES=$back/stages.tar.gz"
else
  echo "gpu-paper.sh: eitbench run exited with $status (see $back/run.log)"
  exit "$status"
fi
ls -la "$back"
