# The shipped geological settings (docs/geology.md, "Shipped settings"): all four validate; the three
# plan-pattern settings run as shipped (smaller pictures) for seeds 1-3 and each is classified as its
# own pattern for every seed; network_maze reports the share of passage length along its two joint
# families (the families' strikes reach the pattern classification) at 0.6 or more; multilevel
# (seed 1) reaches all three springs and has canyons or keyholes above its lowest tubes.
. "$(dirname "$0")/lib.sh"
for n in branchwork network_maze anastomotic multilevel; do
  expect_exit 0 "$n validates" -- "$CAVESIM" validate "$SRC/scenarios/$n.toml"
done
for n in branchwork network_maze anastomotic; do
  sed -e 's/^image_width = 768/image_width = 256/' "$SRC/scenarios/$n.toml" > $n.toml
  case $n in
    branchwork) want="branchwork" ;;
    network_maze) want="network maze" ;;
    anastomotic) want="anastomotic maze" ;;
  esac
  for seed in 1 2 3; do
    expect_exit 0 "$n runs (seed $seed)" -- "$CAVESIM" run $n.toml --seed $seed --out $n-$seed --quiet
    python3 - $n-$seed/report.json "$want" <<'PY' && pass "$n seed $seed is classified $want" || fail "$n seed $seed class"
import json, sys
r = json.load(open(sys.argv[1]))
p = r["pattern"]
assert p["class"] == sys.argv[2], p
assert r["stage2"]["breakthrough_iteration"] is not None
if sys.argv[2] == "network maze":
    assert p["criteria"]["family_share"] >= 0.6, p["criteria"]
PY
  done
done
# multilevel (seed 1): each of the three phases reaches its own spring, and the cross-section table
# has canyon or keyhole passages above the lowest tubes.
sed -e 's/^image_width = 768/image_width = 256/' "$SRC/scenarios/multilevel.toml" > multilevel.toml
expect_exit 0 "multilevel runs" -- "$CAVESIM" run multilevel.toml --out ml --quiet
python3 - ml/report.json <<'PY' && pass "multilevel: three phases break through, vadose sections above tubes" || fail "multilevel"
import json, sys
r = json.load(open(sys.argv[1]))
phases = r["stage2"]["phases"]
assert len(phases) == 3 and all(p["breakthrough_iteration"] is not None for p in phases), phases
x = r["cross_sections"]["passages"]
tubes = [p["z_m"] for p in x if p["class"] == "tube"]
vadose = [p["z_m"] for p in x if p["class"] in ("canyon", "keyhole")]
assert tubes and vadose and max(vadose) > min(tubes), (tubes, vadose)
PY
finish
