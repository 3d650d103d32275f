#!/usr/bin/env bash
# The README's first command: installs what arcs needs, builds it, and runs
# the main job (experiments/quickstart.yaml: the paper's SDF protocol, the
# marching-cubes baseline and every metric, on shapes arcs makes itself).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
./build/app/arcs run experiments/quickstart.yaml --out results/quickstart "$@"
# Reach for the Arcs on an SDF arcs makes itself (a trefoil knot, 30^3 grid).
./build/app/arcs sdf shape:knot results/knot_sdf30.npy --n 30
./build/app/arcs reconstruct results/knot_sdf30.npy results/knot_rfta.ply
./build/app/arcs eval results/knot_rfta.ply shape:knot --samples 200000
