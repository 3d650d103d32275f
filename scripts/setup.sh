#!/usr/bin/env bash
# The README's first command: installs what arcs needs, builds it, and runs
# the main job (experiments/quickstart.yaml: Reach for the Arcs against marching
# cubes on the paper's SDF protocol and metrics, on shapes arcs makes itself),
# then draws its figures and renders and writes results/quickstart/report.html.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
start=$(date +%s)
./build/app/arcs run experiments/quickstart.yaml --out results/quickstart "$@"
# Figures (PNG, PDF), renders of every case (reference | MC | RFTA) and one HTML page.
./build/app/arcs report results/quickstart
# Reach for the Arcs from the command line on an SDF arcs makes itself (a trefoil knot, 30^3 grid;
# at 20^3 today's RFTA gives genus 11 for 1, issue 10).
./build/app/arcs sdf shape:knot results/knot_sdf30.npy --n 30
./build/app/arcs reconstruct results/knot_sdf30.npy results/knot_rfta.ply
./build/app/arcs eval results/knot_rfta.ply shape:knot --samples 200000
echo "main job: $(( $(date +%s) - start )) s; open results/quickstart/report.html" \
     "(figures in results/quickstart/figures/, renders in results/quickstart/renders/)"
