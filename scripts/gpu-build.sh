#!/usr/bin/env bash
# Builds the eitbench tool against a CUDA LibTorch: the PyTorch wheel's CMake package (python3 -c
# "import torch; print(torch.utils.cmake_prefix_path)"). The CPU build, its tests and CI do not
# use this script. Where SuiteSparse, TBB or OpenCV are not installed, it takes them from the
# folder scripts/gpu-deps.sh packed (default .gpu/); without Gmsh it reads that folder's meshes,
# without OpenCV's imgcodecs it draws no figures (`eitbench report` on a full build does), and
# without Ceres it has no shape fit.
# Usage: scripts/gpu-build.sh [BUILD_DIR] (default build-gpu); then `source BUILD_DIR/env.sh`.
# Environment: PYTHON (python3), CXX_STANDARD (17), WITH_GMSH / WITH_FIGURES / WITH_CERES
# (ON|OFF; default: whether found), EITBENCH_GPU_DEPS (.gpu), EXTRA_CMAKE_ARGS.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build-gpu}")
carried=$(realpath -m "${EITBENCH_GPU_DEPS:-$root/.gpu}")
python=${PYTHON:-python3}

torch_prefix=$("$python" -c 'import torch; print(torch.utils.cmake_prefix_path)') || {
  echo "gpu-build.sh: no PyTorch for $python (set PYTHON=...)" >&2
  exit 1
}
prefix="$torch_prefix"
libs=""
if [ -d "$carried/deps/usr" ]; then
  prefix="$carried/deps/usr;$prefix"
  libs="$carried/deps/usr/lib/x86_64-linux-gnu"
  # Reference BLAS/LAPACK for CHOLMOD only where the machine has none.
  if ! ldconfig -p | grep -q 'liblapack.so.3 '; then
    libs="$libs:$carried/fallback/usr/lib/x86_64-linux-gnu:$carried/fallback/usr/lib/x86_64-linux-gnu/lapack:$carried/fallback/usr/lib/x86_64-linux-gnu/blas"
  fi
fi
has_header() { echo "#include <$1>" | c++ -E -x c++ - -I/usr/include/opencv4 >/dev/null 2>&1; }
gmsh=OFF figures=OFF ceres=OFF
has_header gmsh.h && gmsh=ON
has_header opencv2/imgcodecs.hpp && figures=ON
has_header ceres/ceres.h && ceres=ON
# To try the other way:
gmsh=${WITH_GMSH:-$gmsh} figures=${WITH_FIGURES:-$figures} ceres=${WITH_CERES:-$ceres}

echo "gpu-build.sh: LibTorch from $torch_prefix; Gmsh $gmsh, figures $figures, Ceres $ceres"
# One unit a file: 16 cores compile the files side by side faster than in batches, and the CUDA
# paths (learned/src/cuda_support.cpp) have never been compiled in a batch.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DEITBENCH_UNITY_BUILD=OFF \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_STANDARD="${CXX_STANDARD:-17}" \
  -DEITBENCH_WITH_GMSH=$gmsh -DEITBENCH_WITH_FIGURES=$figures -DEITBENCH_WITH_CERES=$ceres \
  -DEITBENCH_BUILD_TESTS=OFF -DEITBENCH_BUILD_BENCHMARKS=OFF -DEITBENCH_INSTALL=OFF \
  ${libs:+-DCMAKE_EXE_LINKER_FLAGS="-Wl,-rpath-link,$libs"} \
  ${libs:+-DCMAKE_MODULE_LINKER_FLAGS="-Wl,-rpath-link,$libs"} ${EXTRA_CMAKE_ARGS:-}
cmake --build "$build" --target eitbench -j "$(nproc)"

{
  echo "# source this before running $build/eitbench"
  [ -n "$libs" ] && echo "export LD_LIBRARY_PATH=\"$libs\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}\""
  [ "$gmsh" = OFF ] && echo "export EITBENCH_MESH_DIR=\"$carried/meshes\""
  true
} > "$build/env.sh"
# shellcheck disable=SC1091
source "$build/env.sh"
"$build/eitbench" --version
echo "gpu-build.sh: built $build/eitbench; run \`source $build/env.sh\` first"
