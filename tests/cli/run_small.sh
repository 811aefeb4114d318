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
finish
