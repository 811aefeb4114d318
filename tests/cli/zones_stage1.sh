# Stage 1 through the command (paper Figure 5): equal pressures split the block in two nearly
# equal zones, a 2 : 1 pressure gives the stronger source clearly the larger zone; protochannels
# are traced in every zone and stage1.vdb and the zones picture are written.
. "$(dirname "$0")/lib.sh"
for s in fig05_equal fig05_ratio2 fig06; do
  expect_exit 0 "$s runs" -- "$CAVESIM" run "$SRC/scenarios/$s.toml" --out "$s" -q
  for f in stage1.vdb images/zones.png report.json; do [ -s "$s/$f" ] && pass "$s/$f" || fail "$s/$f missing"; done
done
python3 - fig05_equal/report.json fig05_ratio2/report.json fig06/report.json <<'PY' && pass "zone sizes" || fail "zone sizes"
import json, sys
eq, r2, f6 = (json.load(open(p))["stage1"] for p in sys.argv[1:4])
a, b = eq["zone_voxels"]
print("equal", a, b, "ratio", r2["zone_voxels"])
assert abs(a - b) / max(a, b) < 0.05
s, w = r2["zone_voxels"]
assert s > 1.8 * w
for st in (eq, r2, f6):
    assert all(z["protochannel_voxels"] > 0 for z in st["per_zone"]), st["per_zone"]
PY
finish
