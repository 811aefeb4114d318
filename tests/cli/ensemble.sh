# `cavesim ensemble` on one machine: members and summary written; members byte-identical whatever
# the threads and members at once; a rerun resumes (finished members kept, missing or changed ones
# rerun); a failing member is recorded and the others go on; bad requests exit 2.
. "$(dirname "$0")/lib.sh"
tiny_ensemble_scenario > t.toml

expect_exit 0 "ensemble of 3, 2 threads" -- "$CAVESIM" ensemble t.toml --members 3 --out e1 -j 2
for f in ensemble.json ensemble.md probability.vdb probability.vti images/probability_plan.png \
  members/m0000/state.vdb members/m0001.json members/m0002/report.json; do
  [ -s "e1/$f" ] && pass "$f written" || fail "$f missing"
done
expect_exit 0 "the same ensemble, 1 thread, 1 member at once" -- \
  "$CAVESIM" ensemble t.toml --members 3 --out e2 -j 1 --parallel 1
same_members e1 e2 3 && pass "members identical (checksums and files)" || fail "members differ"
python3 - e1/ensemble.json <<'PY' && pass "ensemble.json contents" || fail "ensemble.json contents"
import json, sys
e = json.load(open(sys.argv[1]))
assert e["members"] == 3 and e["ok"] == 3 and e["failed"] == 0, e
seeds = [r["seed"] for r in e["member_records"]]
assert len(set(seeds)) == 3, seeds
assert 0 <= e["breakthrough"]["members"] <= 3
assert "morphometry.porosity" in e["metrics"] or len(e["metrics"]) > 0, e["metrics"].keys()
p = e["probability"]
assert p["grid"] == [12, 12, 6] and p["files"][0] == "probability.vdb"
PY
python3 - e1 <<'PY' && pass "probability grid = fraction of members with cave" || fail "probability grid"
import sys, struct, re, json
d = sys.argv[1]
x = open(d + "/probability.vti", "rb").read()
raw = x[x.index(b"<AppendedData encoding=\"raw\">"):]
raw = raw[raw.index(b"_") + 1:]
n = struct.unpack("<Q", raw[:8])[0] // 4
p = struct.unpack("<%df" % n, raw[8:8 + 4 * n])
assert n == 12 * 12 * 6
vals = set(round(v * 3) for v in p)
assert vals <= {0, 1, 2, 3}, vals
assert max(p) > 0
PY

# Resume: an unchanged rerun keeps every member; a removed or damaged member is rerun, identical.
expect_exit 0 "rerun resumes" -- "$CAVESIM" ensemble t.toml --members 3 --out e1 -j 2
stderr_has "3 member(s) already finished, kept"
grep -q "m000[0-2]: ok" stderr.txt && fail "a finished member was rerun" || pass "no member rerun"
rm -rf e1/members/m0001 && printf 'x' >> e1/members/m0002/state.vdb
expect_exit 0 "rerun after a member was removed and one damaged" -- "$CAVESIM" ensemble t.toml --members 3 --out e1 -j 2
stderr_has "1 member(s) already finished, kept"
stderr_has "m0001: ok"
stderr_has "m0002: ok"
same_members e1 e2 3 && pass "rerun members identical" || fail "rerun members differ"

# A member that fails (its zone exceeds a drawn max_graph_voxels) is recorded; the others go on.
expect_exit 1 "ensemble with failing members exits 1" -- \
  "$CAVESIM" ensemble t.toml --members 6 --out e3 -j 2 --vary stage1.max_graph_voxels=1:1700
python3 - e3/ensemble.json <<'PY' && pass "failed members recorded, the others ok" || fail "failure records"
import json, sys
e = json.load(open(sys.argv[1]))
assert e["failed"] >= 1 and e["ok"] >= 1 and e["ok"] + e["failed"] == 6, (e["ok"], e["failed"])
for r in e["member_records"]:
    v = r["values"]["stage1.max_graph_voxels"]
    assert (r["status"] == "ok") == (v >= 864), r
    if r["status"] == "failed":
        assert "max_graph_voxels" in r["error"], r["error"]
PY

# Bad requests: nothing runs, exit 2.
expect_exit 2 "unknown --vary key" -- "$CAVESIM" ensemble t.toml --members 2 --out e4 --vary stage2.nope=1:2
stderr_has "stage2.nope"
expect_exit 2 "--vary outside the key's range" -- "$CAVESIM" ensemble t.toml --members 2 --out e4 --vary stage2.w0=-1:2
expect_exit 2 "--vary of the grid" -- "$CAVESIM" ensemble t.toml --members 2 --out e4 --vary domain.voxel_size=1:2
# Draws that break a rule across keys (p_rate_channel at most p_rate; a snapshot the run reaches)
# were "internal error" member failures; now the command refuses them before writing anything.
expect_exit 2 "--vary drawing p_rate_channel above p_rate" -- "$CAVESIM" ensemble t.toml --members 2 --out e4 --vary stage2.p_rate_channel=0.4:0.6
stderr_has "member 1: t.toml: key 'stage2.p_rate_channel' = 0.5693764497354293: must not exceed stage2.p_rate (0.5)"
# A speleothem step asking for more than 10⁶ steps is refused for drawn members too.
{ cat t.toml; printf '[speleothems]\nenabled = true\nyears = 5000\n'; } > tsp.toml
expect_exit 2 "--vary drawing a speleothem step far too small" -- "$CAVESIM" ensemble tsp.toml --members 2 --out e4 --vary speleothems.time_step=1e-6:1e-5
stderr_has "more than 1000000; use a step of at least 0.005 years"
sed -e 's/^iterations = 40/iterations = 40\nsnapshots = [30]/' -e 's/^images = false/images = true/' t.toml > snap.toml
expect_exit 2 "--vary of iterations below a snapshot" -- "$CAVESIM" ensemble snap.toml --members 3 --out e4 --vary stage2.iterations=10:50
stderr_has "key 'stage2.snapshots' = 30: a snapshot is taken after one of the run's stage-2 iterations, 1 to"
mkdir -p busy && echo hi > busy/file
expect_exit 2 "a non-empty folder that is no ensemble" -- "$CAVESIM" ensemble t.toml --members 2 --out busy
[ ! -e e4 ] && pass "nothing written for bad requests" || fail "e4 written"
finish
