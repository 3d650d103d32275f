#!/usr/bin/env bash
# The README's first command: installs what arcs needs, builds it, and runs
# the main job (experiments/quickstart.yaml: the paper's SDF protocol, the
# marching-cubes baseline and every metric, on shapes arcs makes itself).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
./build/app/arcs run experiments/quickstart.yaml --out results/quickstart "$@"
