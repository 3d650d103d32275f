#!/usr/bin/env bash
# Installs the Debian packages arcs needs (idempotent, non-interactive).
# Why each one:
#   cmake g++ make pkg-config  build toolchain
#   ccache                     fast rebuilds (used automatically when present)
#   libeigen3-dev              dense linear algebra, the matrix types of every module
#   libyaml-cpp-dev            experiment files (with line/column marks for errors)
#   libtbb-dev                 parallel loops
#   libnanoflann-dev           kd-tree k-nearest neighbours (header-only; measured in bench/)
#   libgtest-dev               the test suite
#   libcgal-dev                alpha shapes, advancing front, normal estimation (framework/points/cgal/), bench
#   libembree-dev              ray-parity voxelization baseline, bench/spatial_bench comparison
#   libpcl-dev                 screened Poisson reconstruction (pcl::Poisson; optional, ARCS_WITH_PCL)
#   libopen3d-dev              ball pivoting (Open3D's CreateFromPointCloudBallPivoting; optional, ARCS_WITH_OPEN3D)
#   libopenvdb-dev             OpenVDB volumeToMesh as the vdb_mesher baseline (optional, ARCS_WITH_OPENVDB)
#   slurm-wlm munge            a single-node Slurm cluster for `arcs slurm` (scripts/slurm_local.sh, the cluster test)
#   zlib1g-dev                 .npz archives (deflated members, CRC-32; framework/io/npz.cpp)
#   pybind11-dev python3-dev python3-numpy   the Python module `arcs` (python/; optional, ARCS_BUILD_PYTHON)
#   python3-matplotlib python3-numpy  `arcs plot|render|report` (scripts/arcs_plot.py, headless Agg)
#   chromium                   the report test loads the HTML page headless and checks every image
set -euo pipefail

PACKAGES=(cmake g++ make pkg-config ccache libeigen3-dev libyaml-cpp-dev libtbb-dev libnanoflann-dev
          libgtest-dev libcgal-dev libembree-dev libboost-dev libpcl-dev libopen3d-dev
          slurm-wlm munge
          zlib1g-dev pybind11-dev python3-dev python3-numpy libopenvdb-dev
          python3-matplotlib chromium)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_deps: done"
