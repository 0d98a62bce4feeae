#!/usr/bin/env bash
# Training speed and accuracy of eitbench's GPU paths, and plain PyTorch's on the same GPU in the
# same go (docs/gpu.md, "Speed"). Each variant trains the paper model (batch 512) with D16 on the
# quick set for the same steps under the same cosine schedule, so their validation MSE shows what
# TF32 and bf16 cost in accuracy, and their rounds' samples/s what each path gains.
# Usage: scripts/gpu-speed.sh [OUT] (default gpu-speed), after scripts/gpu-build.sh.
# Environment: BUILD (build-gpu), STEPS (2560: 10 rounds of 256 steps), VARIANTS (all, or names
# from the list below, space-separated), TORCH_REF (1: also scripts/torch_ref.py; 0: not),
# PYTHON (python3).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-gpu-speed}")
build=$(realpath -m "${BUILD:-$root/build-gpu}")
steps=${STEPS:-2560}
python=${PYTHON:-python3}
[ -x "$build/eitbench" ] || { echo "gpu-speed.sh: no $build/eitbench: run scripts/gpu-build.sh" >&2; exit 1; }
# shellcheck disable=SC1091
[ -f "$build/env.sh" ] && source "$build/env.sh"
mkdir -p "$out"
data="$out/quick.h5"
[ -f "$data" ] || "$build/eitbench" simulate --preset quick --threads "$(nproc)" --out "$data" >/dev/null

# name: the train flags that differ. "host" is the batch made on the host and uploaded each step.
declare -A flags=(
  [host-fp32]="--resident off --cuda-graphs off --precision fp32"
  [resident-fp32]="--resident on --cuda-graphs off --precision fp32"
  [resident-tf32]="--resident on --cuda-graphs off --precision tf32"
  [graph-fp32]="--resident on --cuda-graphs on --precision fp32"
  [graph-tf32]="--resident on --cuda-graphs on --precision tf32"
  [graph-bf16]="--resident on --cuda-graphs on --precision bf16"
  [nearest-graph-tf32]="--resident on --cuda-graphs on --precision tf32 --decoder nearest"
  [graph-tf32-nhwc]="--resident on --cuda-graphs on --precision tf32 --channels-last on"
  [graph-bf16-nhwc]="--resident on --cuda-graphs on --precision bf16 --channels-last on"
)
order="host-fp32 resident-fp32 resident-tf32 graph-fp32 graph-tf32 graph-bf16 nearest-graph-tf32"
order="$order graph-tf32-nhwc graph-bf16-nhwc"
variants=${VARIANTS:-$order}

summary="$out/summary.md"
{
  echo "| variant | flags | samples/s (median round) | wall s | best validation MSE |"
  echo "|---|---|---|---|---|"
} > "$summary"
for v in $variants; do
  [ -n "${flags[$v]+x}" ] || { echo "gpu-speed.sh: unknown variant $v (known: $order)" >&2; exit 2; }
  t0=$(date +%s%N)
  # shellcheck disable=SC2086
  "$build/eitbench" train --data "$data" --model paper --augment d16 --device cuda \
    --steps "$steps" --patience 0 --validate-every 131072 --out "$out/$v.pt" ${flags[$v]} \
    > "$out/$v.log" 2>&1 || { echo "gpu-speed.sh: $v failed:"; tail -5 "$out/$v.log"; continue; }
  wall=$(( ($(date +%s%N) - t0) / 1000000 ))
  # The round lines: "... validation 0.0123 (best), lr ..., 123456 samples/s"; the first round
  # (cuDNN's search, the graph's capture) is left out of the median.
  rounds=$(tr '\r' '\n' < "$out/$v.log" | grep ' round ' | grep -oE 'validation [0-9][0-9.e+-]*.*samples/s' || true)
  best=$(echo "$rounds" | awk '{print $2}' | sort -g | head -1)
  median=$(echo "$rounds" | tail -n +2 | awk '{print $(NF-1)}' | sort -n \
    | awk '{r[NR] = $1} END {printf "%.0f\n", NR ? (NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2) : 0}')
  printf '| %s | `%s` | %.0f | %d.%03d | %s |\n' "$v" "${flags[$v]}" "$median" \
    $((wall / 1000)) $((wall % 1000)) "$best" >> "$summary"
  tail -1 "$summary"
done

if [ "${TORCH_REF:-1}" = 1 ]; then
  echo "plain PyTorch, the same network with nearest upsampling, batch 512 (scripts/torch_ref.py):"
  for mode in tuned compiled; do
    "$python" "$root/scripts/torch_ref.py" cuda 4 "$mode" paper:512 2>&1 | grep -v '^infer' \
      | tee -a "$out/torch_ref.log" || echo "gpu-speed.sh: torch_ref.py $mode failed" >&2
  done
fi
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader > "$out/gpu.txt" || true
echo "gpu-speed.sh: $summary"
cat "$summary"
