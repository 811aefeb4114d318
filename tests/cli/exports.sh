# Every export of a real run (fig10 in 3D, fig08 as a 2D section), loaded back by readers other
# than ours (VTK's Python module for glTF/VTK/STL, pyopenvdb, Survex's cavern, therion) and checked
# against the run's report.json: counts, bounds, units. Also --formats and --mesh-normals handling.
. "$(dirname "$0")/lib.sh"
for tool in cavern dump3d therion; do
  command -v "$tool" > /dev/null || { fail "$tool is missing (scripts/test.sh installs it)"; finish; }
done
check_run() {  # DIR NORMALS
  local dir=$1
  (cd "$dir" && cavern --quiet cave.svx > ../cavern_$dir.log 2>&1) || { fail "$dir: cavern: $(cat cavern_$dir.log)"; return; }
  if grep -qi "warning\|error" cavern_$dir.log; then fail "$dir: cavern warns: $(cat cavern_$dir.log)"; return; fi
  dump3d "$dir/cave.3d" > "$dir.svx.dump"
  printf 'source cave.th\nexport model -fmt survex -o th.3d\n' > "$dir/thconfig"
  (cd "$dir" && therion thconfig > ../therion_$dir.log 2>&1) || { fail "$dir: therion: $(cat therion_$dir.log)"; return; }
  if grep -qi "warning" "$dir/therion.log"; then fail "$dir: therion warns: $(cat "$dir/therion.log")"; return; fi
  dump3d "$dir/th.3d" > "$dir.th.dump"
  if /usr/bin/python3 "$SRC/tests/cli/exports_check.py" "$dir" "$2" "$dir.svx.dump" "$dir.th.dump"; then
    pass "$dir: every export read back and agrees with report.json"
  else
    fail "$dir: exports disagree with report.json"
  fi
}
expect_exit 0 "fig10 with every format, inward normals" -- \
  "$CAVESIM" run "$SRC/scenarios/fig10.toml" --out fig10 --formats all --mesh-normals inward -q
check_run fig10 inward
shared_run fig08
check_run fig08 outward

# The default set, none, and a scenario's own list; bad values are refused before any work.
small_scenario > s.toml
expect_exit 0 "default formats" -- "$CAVESIM" run s.toml --out d -q
got=$(cd d && ls cave.glb state.vti skeleton.vtp cave.svx history.csv branches.csv 2>&1 | wc -l)
[ "$got" -eq 6 ] && [ ! -e d/cave.stl ] && [ ! -e d/cave.vdb ] && pass "default set glb,vtk,svx,csv" || fail "default set: $(ls d)"
expect_exit 0 "--formats none" -- "$CAVESIM" run s.toml --out n --formats none -q
[ ! -e n/cave.glb ] && [ ! -e n/state.vti ] && [ -s n/state.vdb ] && pass "none writes no export" || fail "none: $(ls n)"
sed 's/^image_width = 256/image_width = 256\nformats = ["stl", "csv"]\nmesh = false/' s.toml > own.toml
expect_exit 0 "scenario's own formats, mesh off" -- "$CAVESIM" run own.toml --out o -q
[ -s o/history.csv ] && [ ! -e o/cave.stl ] && [ ! -e o/cave.glb ] && pass "[output] formats used; no mesh format without mesh" || fail "own: $(ls o)"
expect_exit 2 "unknown format refused" -- "$CAVESIM" run s.toml --out x --formats glb,obj -q
stderr_has 'unknown format "obj"'
[ ! -e x ] && pass "nothing written for a bad --formats" || fail "x written"
expect_exit 2 "a format listed twice refused" -- "$CAVESIM" run s.toml --out x --formats glb,glb -q
stderr_has 'formats "glb,glb": "glb" is listed twice'
[ ! -e x ] && pass "nothing written for a repeated --formats entry" || fail "x written"
expect_exit 2 "bad --mesh-normals refused" -- "$CAVESIM" run s.toml --out y --mesh-normals sideways -q
sed 's/^image_width = 256/image_width = 256\nformats = ["glb", "ply"]/' s.toml > bad.toml
expect_exit 2 "unknown format in the scenario refused" -- "$CAVESIM" validate bad.toml
stderr_has "formats"
sed 's/^image_width = 256/image_width = 256\nformats = ["glb", "glb"]/' s.toml > twice.toml
expect_exit 2 "a format listed twice in the scenario refused" -- "$CAVESIM" validate twice.toml
stderr_has "twice.toml:21: key 'output.formats' = [\"glb\", \"glb\"]: must be an array of distinct formats"
finish
