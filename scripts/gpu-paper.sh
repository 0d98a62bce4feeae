#!/usr/bin/env bash
# The paper preset on a lent GPU, spread over sessions of limited device time (docs/gpu.md,
# "Across sessions"). One call: build if needed, put back the stages an earlier session finished,
# run until SECONDS after the call began or until the run ends, and pack what a next session
# needs: the stages/ folder (a few MB: the model-based methods, each learned model's scores, each
# sweep point) and, once the run has ended, its results. Model files and the data set stay
# behind: the data set is simulated again from its seed, and the learned models resume from their
# records.
# Usage: scripts/gpu-paper.sh RUN BACK [SECONDS]
#   RUN      the run folder on this machine (made if missing)
#   BACK     where the files to take away are written: stages.tar.gz, run.log, and, when the
#            run has ended, results.tar.gz (results.json, results.csv, report.md, figure data)
#   SECONDS  the whole call's wall-clock limit, build included (default 540), so that it ends,
#            packed, inside the device call's own limit
# Environment: STAGES (an earlier stages.tar.gz to resume from; it must come from the same
# sources, GPU and THREADS, or FORCE=1), BUILD (build-gpu; made by scripts/gpu-build.sh when it
# has no eitbench), PRESET (paper), THREADS (16: part of every record's provenance), METHODS (the
# model-based methods; default tikhonov noser laplace greit), RUN_FLAGS (more flags for run).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 2 ] || { sed -n '9,18p' "$0" >&2; exit 2; }
run_dir=$(realpath -m "$1")
back=$(realpath -m "$2")
limit=${3:-540}
build=$(realpath -m "${BUILD:-$root/build-gpu}")
preset=${PRESET:-paper}
threads=${THREADS:-16}
methods=${METHODS:-tikhonov noser laplace greit}
mkdir -p "$back"

# What the records were made with, beyond their own provenance (which names the program's
# version, not its sources, and the device as "cuda", not which GPU): kept in the tarball and
# checked before a later session resumes from it.
identity() {
  (cd "$root" && find CMakeLists.txt cmake augment bench jacobian learned solvers -type f \
    | LC_ALL=C sort | xargs sha256sum | sha256sum | cut -c1-16)
  nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 || echo "no GPU"
  echo "preset $preset, threads $threads"
}
identity > "$back/identity.txt"
if [ -n "${STAGES:-}" ]; then
  [ -f "$STAGES" ] || { echo "gpu-paper.sh: STAGES=$STAGES: no such file" >&2; exit 2; }
  mkdir -p "$run_dir"
  if ! tar -xzf "$STAGES" -C "$run_dir" stages identity.txt 2> "$run_dir/stages.err"; then
    why=$(grep -m1 . "$run_dir/stages.err" || true)
    echo "gpu-paper.sh: STAGES=$STAGES: not a stages tarball of this script ($why)" >&2
    exit 2
  fi
  rm -f "$run_dir/stages.err"
  if ! cmp -s "$run_dir/identity.txt" "$back/identity.txt" && [ "${FORCE:-0}" != 1 ]; then
    echo "gpu-paper.sh: STAGES=$STAGES was made with other sources, GPU or threads" >&2
    diff "$run_dir/identity.txt" "$back/identity.txt" >&2 || true
    echo "(FORCE=1 resumes from it all the same)" >&2
    exit 2
  fi
fi
if [ ! -x "$build/eitbench" ]; then
  "$root/scripts/gpu-build.sh" "$build" > "$back/build.log" 2>&1 \
    || { tail -20 "$back/build.log"; exit 1; }
fi
# shellcheck disable=SC1091
[ -f "$build/env.sh" ] && source "$build/env.sh"
left=$((limit - SECONDS - 15))  # 15 s to pack
[ "$left" -gt 0 ] || { echo "gpu-paper.sh: no time left after the build" >&2; exit 1; }
status=0
# shellcheck disable=SC2086
timeout -k 10 --signal=TERM "$left" "$build/eitbench" run --preset "$preset" --out "$run_dir" \
  --resume --threads "$threads" --methods $methods ${RUN_FLAGS:-} > "$back/run.log" 2>&1 \
  || status=$?
cp "$back/identity.txt" "$run_dir/identity.txt"
[ ! -d "$run_dir/stages" ] || tar -czf "$back/stages.tar.gz" -C "$run_dir" stages identity.txt
tr '\r' '\n' < "$back/run.log" | grep -v '^\s*$' | grep -vE '[0-9]+% \(' | tail -40 || true
if [ "$status" = 0 ] && [ -f "$run_dir/results.json" ]; then
  (
    cd "$run_dir"
    shopt -s nullglob
    tar -czf "$back/results.tar.gz" results.json results.csv report.md reconstructions.npy \
      ./*.dat ./*.gp
  )
  echo "gpu-paper.sh: the run has ended; its results are in $back/results.tar.gz"
elif [ "$status" = 124 ] || [ "$status" = 137 ]; then
  echo "gpu-paper.sh: stopped after $left s of running; go on with STAGES=$back/stages.tar.gz"
else
  echo "gpu-paper.sh: eitbench run exited with $status (see $back/run.log)"
  exit "$status"
fi
ls -la "$back"
