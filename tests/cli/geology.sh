# Geology and recharge end to end: a sinking stream into a joint set (tests/cli/data/geo_stream.toml,
# shortened) runs, reports its fracture network and recharge, draws images/fractures.png, gives the
# same files with 1 and 2 threads, and the effective scenario reproduces the run.
. "$(dirname "$0")/lib.sh"
sed -e 's/^iterations = 160/iterations = 40/' -e 's/^image_width = 512/image_width = 256/' \
  "$SRC/tests/cli/data/geo_stream.toml" > stream.toml
expect_exit 0 "run with 1 thread" -- "$CAVESIM" run stream.toml --out one --threads 1 --quiet
expect_exit 0 "run with 2 threads" -- "$CAVESIM" run stream.toml --out two --threads 2 --quiet
[ -s one/images/fractures.png ] && pass "fractures.png written" || fail "no fractures.png"
python3 - one/report.json <<'PY' && pass "report.json fracture_network and recharge" || fail "report.json content"
import json, sys
r = json.load(open(sys.argv[1]))
fam = r["fracture_network"]["families"][0]
assert fam["count"] == 20, fam
assert abs(fam["mean_dip_direction_deg"] - 45) < 10 and abs(fam["mean_dip_deg"] - 80) < 10, fam
assert fam["p32_per_m"] > 0
assert r["recharge"]["sources"] == 8 and r["recharge"]["entries"][0]["kind"] == "stream", r["recharge"]
assert r["network"]["sources_total"] == 8
PY
grep -q "## Fracture network" one/report.md && pass "report.md table" || fail "report.md lacks the fracture table"
same=1
for f in $(cd one && find . -type f ! -name 'report.*' | sort); do
  cmp -s "one/$f" "two/$f" || { fail "differs with thread count: $f"; same=0; }
done
[ $same = 1 ] && pass "same files with 1 and 2 threads"
expect_exit 0 "the effective scenario reruns" -- "$CAVESIM" run one/scenario.toml --out again --threads 2 --quiet
cmp -s one/state.cavesim again/state.cavesim && pass "effective scenario reproduces the grids" || fail "state differs"
finish
