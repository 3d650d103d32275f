#!/usr/bin/env bash
# The README's second command: installs what is missing, builds, and runs the
# test suite with ctest. Tests that need ../shared/data skip without it.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
cd build
ctest --output-on-failure -j "${ARCS_TEST_JOBS:-$(nproc)}" "$@"
# The ASan + UBSan subset (readers + fuzzer, spatial/geometry/SDF/voxel
# kernels) in build-asan/; ARCS_SKIP_SANITIZE=1 skips it.
cd ..
./scripts/sanitize.sh
