#!/usr/bin/env bash
# The ASan + UBSan run of the test suite's memory-sensitive subset: the file
# readers (with their mutation fuzzer), the spatial kernels (BVH, winding
# numbers, kNN, topology), geometry (normalisation, marching cubes), SDF
# sampling and voxelization. Built in build-asan/ (separate from build/), -O1,
# every UBSan check fatal (-fno-sanitize-recover). Tests that need the whole
# framework (experiments, CLI) run in the main build only.
# ARCS_SKIP_SANITIZE=1 skips it (test.sh); extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${ARCS_SKIP_SANITIZE:-0}" == 1 ]]; then
  echo "sanitize: skipped (ARCS_SKIP_SANITIZE=1)"
  exit 0
fi
JOBS=${ARCS_BUILD_JOBS:-$(nproc)}
TESTS=(mesh_io_test npy_test points_io_test sdf_io_test reader_fuzz_test
       triangle_bvh_test winding_number_test knn_test topology_test
       normalize_test marching_cubes_test sdf_sampling_test voxelize_test)
FLAGS="-O1 -g -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
start=$(date +%s)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DARCS_BUILD_BENCH=OFF \
  -DARCS_WITH_PCL=OFF -DARCS_WITH_CGAL=OFF -DARCS_WITH_OPEN3D=OFF \
  -DCMAKE_CXX_FLAGS_DEBUG="$FLAGS" -DCMAKE_C_FLAGS_DEBUG="$FLAGS" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" "$@" >/dev/null
cmake --build build-asan -j "$JOBS" --target "${TESTS[@]}"
built=$(date +%s)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=0:halt_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export ARCS_SHARED_DIR=${ARCS_SHARED_DIR:-$(cd .. && pwd)/shared}
failed=()
for t in "${TESTS[@]}"; do
  exe=build-asan/tests/$t
  if ! "$exe" --gtest_brief=1 >"build-asan/$t.log" 2>&1; then
    failed+=("$t")
    tail -40 "build-asan/$t.log"
  fi
done
end=$(date +%s)
echo "sanitize: ${#TESTS[@]} test programs under ASan+UBSan, build $((built - start)) s, run $((end - built)) s"
if ((${#failed[@]})); then
  echo "sanitize: FAILED: ${failed[*]} (logs in build-asan/)"
  exit 1
fi
echo "sanitize: zero findings"
