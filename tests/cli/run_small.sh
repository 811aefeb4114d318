# A small run writes the contract's files, with the report keys filled in and the water balanced.
. "$(dirname "$0")/lib.sh"
small_scenario > s.toml
expect_exit 0 "run" -- "$CAVESIM" run s.toml --out r -q
for f in scenario.toml state.vdb report.json; do [ -s "r/$f" ] && pass "$f written" || fail "$f missing"; done
expect_exit 0 "effective scenario validates" -- "$CAVESIM" validate r/scenario.toml
python3 - r/report.json <<'PY' && pass "report.json keys" || fail "report.json keys"
import json, sys
r = json.load(open(sys.argv[1]))
for k in ["scenario", "grid", "voxel_size_m", "seed", "threads", "timing_s", "stage1", "stage2"]:
    assert k in r, k
assert r["grid"] == [16, 1, 12]
s2 = r["stage2"]
assert s2["iterations"] == 30 and len(s2["history"]) == 30
assert s2["water_balance_rel_error"] < 1e-9, s2["water_balance_rel_error"]
PY
for f in cave.obj cave.ply skeleton.json skeleton_nodes.dat skeleton_links.dat report.md images/side_xz.png \
  images/pressure.png images/flow.png images/map_section.png images/map_section.svg \
  images/map_extended_elevation.png images/map_extended_elevation.svg; do
  [ -s "r/$f" ] && pass "$f written" || fail "$f missing"
done
# A 2D section: no plan or perspective pictures, and section measures instead of plan indices.
for f in images/perspective.png images/plan.png images/side_yz.png images/map_plan.png; do
  [ ! -e "r/$f" ] && pass "no $f for a section" || fail "$f written for a section"
done
grep -q "^## Section measures" r/report.md && pass "section measures" || fail "no section measures in report.md"
if grep -q "^| areal coverage" r/report.md; then fail "plan indices in a section report"; else pass "no plan indices"; fi
# `cavesim report DIR` rebuilds the report from the run's files: the same measurements.
cp r/report.json before.json
expect_exit 0 "report rebuilds" -- "$CAVESIM" report r
python3 - before.json r/report.json <<'PY' && pass "rebuilt report agrees" || fail "rebuilt report differs"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ("network", "morphometry", "graph_metrics", "stage2"):
    assert a[k] == b[k], k
PY
expect_exit 2 "report of a folder that is no run" -- "$CAVESIM" report .
# A damaged run folder is refused with exit 2 and left as it was: a state.cavesim changed since the run
# (its checksums would catch it too), a report.json that is no report, a report.md that
# cannot be rewritten.
cp -r r damaged && cp damaged/report.json damaged-before.json
python3 - damaged/state.cavesim <<'PY'
import sys
b = bytearray(open(sys.argv[1], "rb").read()); b[len(b) // 2] ^= 0x5A; open(sys.argv[1], "wb").write(b)
PY
expect_exit 2 "report refuses a changed state.cavesim" -- "$CAVESIM" report damaged
stderr_has "changed since the run wrote it"
cmp -s damaged/report.json damaged-before.json && pass "report.json untouched" || fail "report.json rewritten"
mv damaged/report.json damaged/report.json.away
expect_exit 2 "without report.json, scenario.toml's record still catches it" -- "$CAVESIM" report damaged
stderr_has "changed since the run wrote it"
mv damaged/report.json.away damaged/report.json
cp r/state.cavesim damaged/state.cavesim && echo '[1, 2]' > damaged/report.json
expect_exit 2 "report refuses a report.json that is no report" -- "$CAVESIM" report damaged
stderr_has "not a cavesim report"
cp damaged-before.json damaged/report.json && rm damaged/report.md && mkdir damaged/report.md
expect_exit 2 "report refuses an unwritable report.md" -- "$CAVESIM" report damaged
cmp -s damaged/report.json damaged-before.json && pass "nothing rewritten before the refusal" || fail "report.json rewritten"
# The record of state.cavesim: report.json's entry may be unusable (the scenario.toml line is then used);
# with neither, or with a scenario edited to another grid, or with a state.cavesim that is a FIFO, the
# folder is refused; temporary files never write through a symlink lying in the folder.
drop_report_record() {  # report.json's record of state.cavesim made unusable
  python3 - rec/report.json <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); j["files"] = {"state.cavesim": None}; json.dump(j, open(sys.argv[1], "w"))
PY
}
rm -rf rec && cp -r r rec
drop_report_record
expect_exit 0 "report falls back to scenario.toml's record" -- "$CAVESIM" report rec
sed -i '/^# state.cavesim:/d' rec/scenario.toml
drop_report_record
expect_exit 2 "report refuses a state.cavesim without any record" -- "$CAVESIM" report rec
stderr_has "no usable record"
rm -rf rec && cp -r r rec && sed -i 's/^size = \[ 16, 1, 12 \]/size = [ 16, 1, 13 ]/' rec/scenario.toml
grep -q "size = \[ 16, 1, 13 \]" rec/scenario.toml && pass "scenario grid edited" || fail "edit did not apply: $(grep size rec/scenario.toml)"
expect_exit 2 "report refuses a scenario edited to another grid" -- "$CAVESIM" report rec
stderr_has "the scenario was edited"
rm -rf rec && cp -r r rec && rm rec/state.cavesim && mkfifo rec/state.cavesim
expect_exit 2 "report refuses a FIFO state.cavesim" -- timeout 20 "$CAVESIM" report rec
rm -rf rec && cp -r r rec && echo precious > outside.txt && ln -s "$PWD/outside.txt" rec/.report.md.tmp
expect_exit 0 "report with a symlink among its temporary names" -- "$CAVESIM" report rec
[ "$(cat outside.txt)" = precious ] && [ ! -L rec/report.md ] && pass "nothing written through the symlink" || fail "wrote through a symlink"
rm -rf rec && cp -r r rec
python3 - rec/report.json <<'PY'
import sys
open(sys.argv[1], "w").write('{"x": ' + "[" * 100000 + "]" * 100000 + "}")
PY
expect_exit 2 "report refuses a report.json nested 100 000 deep" -- "$CAVESIM" report rec
stderr_has "nested more than 64 levels"
rm -rf rec && cp -r r rec && rm rec/report.json
python3 - rec/scenario.toml <<'PY'
import sys
lines = [l for l in open(sys.argv[1]) if not l.startswith("# state.cavesim:")]
deep = "[" * 200000 + "]" * 200000
lines.append('# state.cavesim: {"bytes": 1, "fnv1a64": "0", "grid": [1, 1, 1], "voxel_size_m": 1, "x": ' + deep + '}\n')
open(sys.argv[1], "w").writelines(lines)
PY
expect_exit 2 "report refuses a deeply nested scenario.toml record" -- "$CAVESIM" report rec
stderr_has "no usable record"
finish
