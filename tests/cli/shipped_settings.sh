# The shipped geological settings (docs/geology.md, "Shipped settings"): all four validate; the
# cheapest, branchwork, runs as shipped (smaller pictures) and is classified branchwork; a short run
# of network_maze reports the share of passage length along its two joint families (the families'
# strikes reach the pattern classification).
. "$(dirname "$0")/lib.sh"
for n in branchwork network_maze anastomotic multilevel; do
  expect_exit 0 "$n validates" -- "$CAVESIM" validate "$SRC/scenarios/$n.toml"
done
sed -e 's/^image_width = 768/image_width = 256/' "$SRC/scenarios/branchwork.toml" > branchwork.toml
expect_exit 0 "branchwork runs" -- "$CAVESIM" run branchwork.toml --out bw --quiet
python3 - bw/report.json <<'PY' && pass "branchwork is classified branchwork" || fail "branchwork class"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["pattern"]["class"] == "branchwork", r["pattern"]
assert r["stage2"]["breakthrough_iteration"] is not None
PY
sed -e 's/^iterations = 160/iterations = 30/' -e 's/^image_width = 768/image_width = 256/' \
  "$SRC/scenarios/network_maze.toml" > maze.toml
expect_exit 0 "network_maze runs (30 iterations)" -- "$CAVESIM" run maze.toml --out maze --quiet
python3 - maze/report.json <<'PY' && pass "network_maze measures its family share" || fail "no family share"
import json, sys
r = json.load(open(sys.argv[1]))
c = r["pattern"]["criteria"]
assert c.get("family_share") is not None and 0 < c["family_share"] <= 1, c
PY
finish
