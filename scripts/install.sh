#!/usr/bin/env bash
# Installs every Debian 12 package eitbench needs. Run as root; safe to run again (it only calls
# apt when something is missing). The list and its reasons are in docs/building.md.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev          # dense and sparse linear algebra at every module boundary
  libsuitesparse-dev     # CHOLMOD: the forward model's sparse Cholesky
  libceres-dev           # nonlinear least squares: the shape fit
  libgmsh-dev            # meshes the disk's fundamental sector
  libopencv-dev          # figures and bilinear image transforms
  libhdf5-dev            # data sets and Jacobians, readable by h5py and MATLAB
  libopenmpi-dev openmpi-bin   # simulate and run sharded by rank under mpirun (optional)
  zlib1g-dev             # .npz and compressed .mat measurement files
  libtorch-dev           # the learned reconstructor (learned/)
  libopenblas0-openmp    # the fast BLAS: ATLAS is 1.5-3x slower, pthread OpenBLAS fights OpenMP
  nlohmann-json3-dev     # the learned model's metadata and checkpoints
  libcli11-dev libfmt-dev libtbb-dev
  gnuplot-nox            # the line plots (loss curves, data efficiency, touches); no X11
  libgtest-dev libbenchmark-dev
  slurm-wlm              # the tests' single-node cluster: a run as an sbatch array (scaling.md)
  pybind11-dev python3-dev python3-numpy python3-pytest   # the Python package (python/)
  python3-scipy          # its tests: KTC2023's own scoring function on eitbench's files
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install.sh: all ${#packages[@]} packages already installed"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "install.sh: missing packages: ${missing[*]}; run this script as root (or with sudo)" >&2
  exit 1
fi
echo "install.sh: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
# libgmsh-dev, gnuplot-nox and slurm-wlm without their recommends (the Gmsh GUI, gnuplot's
# manuals, Slurm's mail and munge daemons);
# everything else as Debian recommends.
others=() lean=()
for p in "${missing[@]}"; do
  case "$p" in libgmsh-dev | gnuplot-nox | slurm-wlm) lean+=("$p") ;; *) others+=("$p") ;; esac
done
if [ ${#others[@]} -gt 0 ]; then apt-get install -y -q "${others[@]}"; fi
if [ ${#lean[@]} -gt 0 ]; then apt-get install -y -q --no-install-recommends "${lean[@]}"; fi
