# Same scenario and seed: the same grids and report figures with 1 and 2 threads.
. "$(dirname "$0")/lib.sh"
small_scenario > s.toml
expect_exit 0 "run 1 thread" -- "$CAVESIM" run s.toml --out a --threads 1 -q
expect_exit 0 "run 2 threads" -- "$CAVESIM" run s.toml --out b --threads 2 -q
python3 - a/report.json b/report.json <<'PY' && pass "report figures identical" || fail "report figures differ"
import json, sys
def strip(r):
    r.pop("timing_s", None); r.pop("threads", None)
    def walk(x):
        if isinstance(x, dict):
            return {k: walk(v) for k, v in x.items() if not k.startswith("seconds")}
        if isinstance(x, list):
            return [walk(v) for v in x]
        return x
    return walk(r)
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
assert a == b
PY
for f in state.vdb stage1.vdb cave.ply cave.obj skeleton.json; do
  [ -e "a/$f" ] || continue
  cmp -s "a/$f" "b/$f" && pass "$f identical" || fail "$f differs between 1 and 2 threads"
done
finish
