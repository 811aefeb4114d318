#!/usr/bin/env bash
# Rebuilds the pictures of the shipped geological settings in docs/geology.md ("Shipped settings"):
# runs each of scenarios/{branchwork,network_maze,anastomotic,multilevel}.toml with seed 1 and copies
# its plan (multilevel: its x-z side view) to docs/images/geology_<name>.png.
# usage: scripts/geology_pictures.sh [CAVESIM [OUTROOT]]   (from the repository root)
set -euo pipefail
BIN=${1:-build/cavesim}
OUT=${2:-out/geology}
for n in branchwork network_maze anastomotic multilevel; do
  "$BIN" run "scenarios/$n.toml" --out "$OUT/$n" --seed 1 --force --quiet
  pic=plan.png
  [ "$n" = multilevel ] && pic=side_xz.png
  cp "$OUT/$n/images/$pic" "docs/images/geology_$n.png"
done
