#!/usr/bin/env bash
# Output hashes of three reference runs, to show a refactoring changed no
# result (issue 11: "output hashes unchanged"):
#   1. RFTA (defaults, seed 1) on bunny_fixed at n = 20: the mesh file;
#   2. the 2D Fig. 5 run (experiments/rfta_2d.yaml): every saved curve and
#      the results' metric columns (wall-time columns dropped);
#   3. the Table 1 check (experiments/rfta_table1.yaml, paper preset) on
#      three bench meshes (bunny_fixed, knot1, joint) at n = 10: the tables' metric cells and meshes.
# Usage: scripts/output_hashes.sh [BUILD_DIR] [WORK_DIR]; needs ../shared.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
work="${2:-$(mktemp -d)}"
arcs="$build/app/arcs"
shared="${ARCS_SHARED_DIR:-$here/../shared}"
export ARCS_SHARED_DIR="$shared"
mkdir -p "$work"
# Metric columns only: drop timing and memory columns, host, revision and the like.
strip_csv() {
  python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
if not rows: sys.exit(0)
# Wall times (*_s) and memory (*_mb) vary from run to run; so do the host facts.
drop = lambda k: k.endswith("_s") or k.endswith("_mb") or k in ("host", "git_revision", "threads", "shard", "started", "finished", "pid")
keys = [k for k in rows[0] if not drop(k)]
rows.sort(key=lambda r: r.get("case_id", ""))
for r in rows: print(",".join(r[k] for k in keys))
PY
}
# 1. RFTA bunny n = 20.
"$arcs" sdf "$shared/data/bench/bunny_fixed.obj" "$work/bunny20.npy" --n 20 >/dev/null
"$arcs" reconstruct "$work/bunny20.npy" "$work/bunny20_rfta.ply" --method rfta --threads 2 >/dev/null
echo "rfta_bunny_n20_mesh $(sha256sum < "$work/bunny20_rfta.ply" | cut -c1-16)"
# 2. 2D Fig. 5.
"$arcs" run "$here/experiments/rfta_2d.yaml" --out "$work/fig5" --save-outputs --quiet --threads 2 >/dev/null
echo "fig5_2d_outputs $(cd "$work/fig5/outputs" && find . -type f | sort | xargs sha256sum | sha256sum | cut -c1-16)"
echo "fig5_2d_metrics $(strip_csv "$work"/fig5/results*.csv | sha256sum | cut -c1-16)"
# 3. Table 1 check.
files='["'"$shared"'/data/bench/bunny_fixed.obj","'"$shared"'/data/bench/knot1.obj","'"$shared"'/data/bench/joint.obj"]'
"$arcs" run "$here/experiments/rfta_table1.yaml" --out "$work/table1" --save-outputs --quiet --threads 2 \
  --set 'inputs.grid.sdf_grid.n=[10]' --set "datasets.bench.files=$files" >/dev/null
echo "table1_outputs $(cd "$work/table1/outputs" && find . -type f -name '*.ply' | sort | xargs sha256sum | sha256sum | cut -c1-16)"
echo "table1_metrics $(strip_csv "$work"/table1/results*.csv | sha256sum | cut -c1-16)"
