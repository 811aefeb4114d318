# Same scenario and seed: the same grids and report figures with 1 and 2 threads.
. "$(dirname "$0")/lib.sh"
small_scenario > s.toml
expect_exit 0 "run 1 thread" -- "$CAVESIM" run s.toml --out a --threads 1 -q
expect_exit 0 "run 2 threads" -- "$CAVESIM" run s.toml --out b --threads 2 -q
same_report_figures a/report.json b/report.json && pass "report figures identical" || fail "report figures differ"
for f in state.vdb stage1.vdb cave.ply cave.obj skeleton.json; do
  [ -e "a/$f" ] || continue
  cmp -s "a/$f" "b/$f" && pass "$f identical" || fail "$f differs between 1 and 2 threads"
done
# A decorated run (speleothems): the decorated meshes too, and report.json records their bytes.
{ small_scenario; cat <<'TOML'
[speleothems]
enabled = true
years = 500
voxel_size = 0.25
roughness = 0.3
roughness_scale = 1.5
frames = 2
TOML
} > d.toml
expect_exit 0 "decorated run 1 thread" -- "$CAVESIM" run d.toml --out c --threads 1 -q
expect_exit 0 "decorated run 2 threads" -- "$CAVESIM" run d.toml --out d --threads 2 -q
for f in cave_decorated.obj cave_decorated.ply cave_decorated.glb; do
  cmp -s "c/$f" "d/$f" && pass "$f identical" || fail "$f differs between 1 and 2 threads"
done
python3 - c d <<'PY' && pass "report.json fingerprints the decorated meshes" || fail "decorated meshes not fingerprinted"
import json, os, sys
for run in sys.argv[1:3]:
    files = json.load(open(os.path.join(run, "report.json")))["files"]
    for f in ("cave_decorated.obj", "cave_decorated.ply", "cave_decorated.glb"):
        data = open(os.path.join(run, f), "rb").read()
        h = 1469598103934665603  # core/fnv.h's offset basis (not the standard 14695981039346656037)
        for b in data:
            h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
        assert files[f] == {"bytes": len(data), "fnv1a64": "%016x" % h}, (run, f, files.get(f))
PY
finish
