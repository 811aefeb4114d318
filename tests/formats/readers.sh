#!/usr/bin/env bash
# Writes every export of the hand-made cave (tests/formats/sample.h) and loads each file back
# with a reader other than ours: pyopenvdb, VTK's Python module, Survex's cavern, therion.
# Usage: readers.sh FORMATS_SAMPLE READERS_PY
set -euo pipefail
sample=$1
script=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$sample" "$dir/out" > "$dir/written.txt"
for tool in cavern dump3d therion; do
  command -v "$tool" > /dev/null || { echo "readers.sh: $tool is missing (scripts/test.sh installs it)" >&2; exit 1; }
done
(cd "$dir/out" && cavern --quiet cave.svx > "$dir/cavern.log" 2>&1) || { cat "$dir/cavern.log" >&2; exit 1; }
if grep -qi "warning\|error" "$dir/cavern.log"; then cat "$dir/cavern.log" >&2; exit 1; fi
dump3d "$dir/out/cave.3d" > "$dir/svx.dump"
printf 'source cave.th\nexport model -fmt survex -o th.3d\n' > "$dir/out/thconfig"
(cd "$dir/out" && therion thconfig > "$dir/therion.log" 2>&1) || { cat "$dir/therion.log" >&2; exit 1; }
if grep -qi "warning" "$dir/out/therion.log"; then cat "$dir/out/therion.log" >&2; exit 1; fi
dump3d "$dir/out/th.3d" > "$dir/th.dump"
/usr/bin/python3 "$script" "$dir/out" "$dir/written.txt" "$dir/svx.dump" "$dir/th.dump"
