# Water table and gravity, base-level phases (docs/model.md, "Water table and gravity").
#  - gravity shows: a vadose section flipped upside down does not give the flipped cave, while the
#    same section without a water table does (the paper's model has no up and down);
#  - a vadose shaft is taller than wide;
#  - phases: the second phase's lower water table grows passages below the first level's;
#  - the same files for --threads 1 and 2.
. "$(dirname "$0")/lib.sh"
section() {  # water table ($1: "none" or a level), source z ($2), sink z range ($3 $4)
  cat <<TOML
name = "flip"
seed = 3
[domain]
size = [40, 1, 30]
[rock]
porosity = 0.05
[[source]]
at = [10, 0, $2]
[[sink]]
box = [[39, 0, $3], [39, 0, $4]]
[stage1]
enabled = false
[stage2]
iterations = 240
p_rate = 0.05
p_rate_channel = 0.001
[output]
images = false
mesh = false
formats = []
TOML
  [ "$1" = none ] || printf '[hydrology]\nwater_table = %s\n' "$1"
}
# Upright: source at the top, sink low on the right. Flipped: z → 29 − z. The table at 0 leaves all
# but the bottom row vadose in both.
section none 28 0 4 > up0.toml
section none 1 25 29 > flip0.toml
section 0 28 0 4 > up.toml
section 0 1 25 29 > flip.toml
for x in up0 flip0 up flip; do expect_exit 0 "$x runs" -- "$CAVESIM" run "$x.toml" --out "$x" -q; done
python3 - <<'PY' && pass "gravity shows: flipped vadose section differs, flipped phreatic one does not" || fail "flip test"
import json
r = {x: json.load(open(x + "/report.json")) for x in ["up0", "flip0", "up", "flip"]}
cave = {x: r[x]["morphometry"]["cave_voxels"] for x in r}
bt = {x: r[x]["stage2"]["breakthrough_iteration"] for x in r}
print("cave voxels", cave, "breakthrough", bt)
# Without a water table the flipped section grows the flipped cave (same size, same breakthrough).
assert cave["up0"] == cave["flip0"] and bt["up0"] == bt["flip0"] is not None
# With it, water falls from the upright source to the sink but cannot climb from the flipped one.
assert bt["up"] is not None and bt["flip"] is None
assert cave["flip"] < cave["up"] / 4
for x in ("up", "flip"):
    assert r[x]["stage2"]["water_balance_rel_error"] < 1e-9
PY
python3 - <<'PY' && pass "a vadose shaft is taller than wide" || fail "vadose shaft shape"
import json
p = json.load(open("up/report.json"))["stage2"]["phases"][0]
box = p["cave_box_above_table"]
height = box["hi"][2] - box["lo"][2] + 1
width = p["cave_above_table_voxels_per_slice"]  # a 2D section: cave voxels across, per level
print("vadose cave: height", height, "voxels, mean width", width, "voxels")
assert height > 3 * width
PY
# Two phases: a falling water table leaves the upper level vadose and grows a lower one.
DATA="$SRC/tests/cli/data"
expect_exit 0 "two-level run, 1 thread" -- "$CAVESIM" run "$DATA/two_level.toml" --out t1 -q --threads 1
expect_exit 0 "two-level run, 2 threads" -- "$CAVESIM" run "$DATA/two_level.toml" --out t2 -q --threads 2
same=1
for f in $(cd t1 && find . -type f ! -name 'report.*' | sort); do cmp -s "t1/$f" "t2/$f" || { same=0; echo "differs: $f"; }; done
[ $same = 1 ] && pass "same files for 1 and 2 threads" || fail "thread count changes the files"
python3 - <<'PY' && pass "phase 2 grows a level below phase 1's" || fail "phases"
import json
a = json.load(open("t1/report.json"))["stage2"]
b = json.load(open("t2/report.json"))["stage2"]
assert a["phases"] == b["phases"]
p1, p2, p3 = a["phases"]
for p in (p1, p2, p3):
    print({k: p[k] for k in ("water_table", "sinks", "breakthrough_iteration", "cave_voxels_added",
                             "cave_voxels_below_table", "cave_voxels_above_table")})
assert (p1["water_table"], p2["water_table"], p1["sinks"], p2["sinks"]) == (24, 8, [1], [2])
assert p1["breakthrough_iteration"] is not None and p2["breakthrough_iteration"] is not None
assert p2["breakthrough_iteration"] > p2["first_iteration"]  # joined to the lower spring in phase 2
# Phase 1's phreatic cave lies at its table; phase 2's below the first level, at its own table.
assert p1["cave_box_below_table"]["lo"][2] >= 20
assert p2["cave_voxels_below_table"] > 100 and p2["cave_box_below_table"]["hi"][2] <= 8
# The first level is left vadose, and shafts join the levels: cave above the table spans both.
assert p2["cave_box_above_table"]["lo"][2] <= 10 and p2["cave_box_above_table"]["hi"][2] >= 30
assert a["water_balance_rel_error"] < 1e-9
PY
# validate counts the phases' iterations (they replace [stage2] iterations), and a level just off
# the block is shown as given.
{ section 5 28 0 4; printf '[[phase]]\niterations = 7\n[[phase]]\niterations = 5\n'; } > phased.toml
expect_exit 0 "validate a phased scenario" -- "$CAVESIM" validate phased.toml
grep -q "stage 2 12 iterations" stdout.txt && pass "validate sums the phases' iterations" ||
  fail "validate summary: $(cat stdout.txt)"
section 29.0000001 28 0 4 > offblock.toml
expect_exit 2 "a water table just above the block" -- "$CAVESIM" validate offblock.toml
stderr_has "water_table' = 29.0000001:"
finish
