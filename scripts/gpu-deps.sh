#!/usr/bin/env bash
# Packs what a CUDA machine without SuiteSparse, TBB, OpenCV or Gmsh (the lent GPU image: Ubuntu
# 24.04 with the PyTorch wheel) needs to build and run eitbench, into one folder to carry there:
#   deps/     Debian 12's CHOLMOD, TBB and OpenCV core/imgproc, headers and libraries, unpacked
#   meshes/   the disk meshes of the presets, written by this build's Gmsh (EITBENCH_MESH_DIR)
# Run on the Debian 12 machine after the build (it needs build/eitbench and apt-get download);
# then scripts/gpu-build.sh on the CUDA machine. Usage: scripts/gpu-deps.sh [OUT] (default .gpu).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-$root/.gpu}")
tool=${EITBENCH:-$root/build/eitbench}
[ -x "$tool" ] || { echo "gpu-deps.sh: $tool not found: build first (README)" >&2; exit 1; }

packages=(
  libcholmod3 libamd2 libcamd2 libccolamd2 libcolamd2 libsuitesparseconfig5 libmetis5
  libsuitesparse-dev                           # cholmod.h and friends (static libraries dropped)
  libtbb12 libtbbmalloc2 libtbbbind-2-5 libtbb-dev  # TBB; its CMake package checks every library
  libopencv-core406 libopencv-imgproc406 libopencv-core-dev libopencv-imgproc-dev
  libglx0 libglvnd0                            # libopencv_core links libGLX
)
# Used only where the machine has none: reference BLAS/LAPACK for CHOLMOD.
fallback=(libblas3 liblapack3 libgfortran5)

rm -rf "$out/deps" "$out/fallback" "$out/meshes"
mkdir -p "$out/deps" "$out/fallback" "$out/meshes"
download=$(mktemp -d)
trap 'rm -rf "$download"' EXIT
(cd "$download" && apt-get download -q -o APT::Sandbox::User=root "${packages[@]}" "${fallback[@]}" >/dev/null)
for p in "${packages[@]}"; do dpkg -x "$download/${p}"_*.deb "$out/deps"; done
for p in "${fallback[@]}"; do dpkg -x "$download/${p}"_*.deb "$out/fallback"; done
# What a build never reads: static libraries, documentation.
find "$out/deps" "$out/fallback" -name '*.a' -delete
rm -rf "$out"/deps/usr/share "$out"/fallback/usr/share

# The presets' meshes: reconstruction (medium), simulation (fine), the test set's (coarse).
for density in coarse medium fine; do
  "$tool" mesh --electrodes 16 --density "$density" --cache "$out/meshes" | tail -1
done
echo "gpu-deps.sh: $(du -sh "$out" | cut -f1) in $out; carry it, then run scripts/gpu-build.sh"
