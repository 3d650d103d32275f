#!/usr/bin/env bash
# Issue 15, criterion 1: every file of $ARCS_SHARED_DIR/data/bad through
# `arcs sdf` (n = 20), `arcs voxelize` (64^3), `arcs eval` (the file against
# itself) and `arcs reconstruct` (RFTA of the n = 20 SDF), each under a 60 s
# timeout at 2 threads. Prints one Markdown row per file: per command the exit
# status (0 ok, 1 clear error, 124 timeout, >128 signal), seconds, and for
# errors the first line of the message. Any signal, timeout or "nan" in an
# output fails the script.
# usage: scripts/check_bad_files.sh [ARCS_EXE] [BAD_DIR]
set -uo pipefail
cd "$(dirname "$0")/.."
ARCS=${1:-build/app/arcs}
BAD=${2:-${ARCS_SHARED_DIR:-../shared}/data/bad}
LIMIT=${ARCS_BAD_TIMEOUT:-60}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bad=0
run() {  # name, command...: sets rc, secs, msg
  local name=$1; shift
  local t0=$(date +%s.%N)
  timeout "$LIMIT" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err"
  rc=$?
  secs=$(echo "$(date +%s.%N) - $t0" | bc)
  msg=$(grep -m1 "error" "$tmp/$name.err" | cut -c1-110 | sed 's/|/\\|/g')
  if ((rc == 124 || rc > 128)); then bad=1; msg="TIMEOUT/SIGNAL $msg"; fi
  if grep -qi "\bnan\b" "$tmp/$name.out" "$tmp/$name.err"; then bad=1; msg="NaN! $msg"; fi
}
echo "| file | sdf | voxelize | eval | reconstruct (rfta) | notes |"
echo "|---|---|---|---|---|---|"
for f in "$BAD"/*; do
  b=$(basename "$f")
  [[ "$b" == MANIFEST.tsv ]] && continue
  run sdf "$ARCS" sdf "$f" "$tmp/s.npy" --n 20
  sdf="$rc ($(printf %.1f "$secs") s)"; note=""
  [[ $rc != 0 ]] && note="sdf: $msg"
  sign=$(grep -m1 "^sign:" "$tmp/sdf.err" |
         sed -E 's/^sign: ([^ ]+) rule, [0-9]+ unbalanced edges, ([0-9]+) of ([0-9]+) samples inside.*/\1, \2 of \3/')
  run vox "$ARCS" voxelize "$f" "$tmp/v.npy" --resolution 64 --threads 2
  vox="$rc ($(printf %.1f "$secs") s)"
  [[ $rc != 0 ]] && note="$note voxelize: $msg"
  occ=$(grep -o "[0-9]* occupied" "$tmp/vox.out" | cut -d' ' -f1)
  run eval "$ARCS" eval "$f" "$f" --samples 100000
  ev="$rc ($(printf %.1f "$secs") s)"
  [[ $rc != 0 ]] && note="$note eval: $msg"
  if [[ -f "$tmp/s.npy" ]]; then
    run rec "$ARCS" reconstruct "$tmp/s.npy" "$tmp/r.ply" --threads 2
    rec="$rc ($(printf %.1f "$secs") s)"
    [[ $rc != 0 ]] && note="$note reconstruct: $msg"
  else
    rec="- (no SDF)"
  fi
  rm -f "$tmp/s.npy" "$tmp/v.npy" "$tmp/r.ply"
  echo "| $b | $sdf ${sign:+[$sign inside]} | $vox ${occ:+[$occ occ.]} | $ev | $rec | $note |"
done
exit $bad
