# Every kind of bad input: exit code 2, one clear message, no output directory created.
. "$(dirname "$0")/lib.sh"
small_scenario > good.toml

sed 's/^porosity = 0.05/porosty = 0.05/' good.toml > misspelt.toml
expect_exit 2 "misspelt key" -- "$CAVESIM" run misspelt.toml --out o1
stderr_has "misspelt.toml:6: unknown key 'rock.porosty'"
[ ! -e o1 ] && pass "no output dir for a bad scenario" || fail "o1 was created"

sed 's/^iterations = 30/iterations = "many"/' good.toml > wrongtype.toml
expect_exit 2 "wrong type" -- "$CAVESIM" run wrongtype.toml --out o2
stderr_has "stage2.iterations"
stderr_has "whole number"

sed 's/^p_rate = 0.05/p_rate = -3/' good.toml > range.toml
expect_exit 2 "out of range" -- "$CAVESIM" validate range.toml
stderr_has "stage2.p_rate' = -3"

sed 's/^at = \[4, 0, 11\]/at = [4, 0, 12]/' good.toml > outside.toml
expect_exit 2 "source outside" -- "$CAVESIM" run outside.toml --out o3
stderr_has "inside the domain"

sed 's/^at = \[4, 0, 11\]/at = [15, 0, 3]/' good.toml > overlap.toml
expect_exit 2 "source overlaps sink" -- "$CAVESIM" validate overlap.toml
stderr_has "overlaps"

# The shipped Figure 12 with its old aim point, inside the sink box: stage 1 keeps rock around sinks.
sed 's/^aim = .*/aim = [[69, 25, 4], [30, 25, 5]]/' "$SRC/scenarios/fig12.toml" > aim_in_sink.toml
expect_exit 2 "aim point inside a sink" -- "$CAVESIM" run aim_in_sink.toml --out o7
stderr_has "aim_in_sink.toml: key 'stage1.aim' point 1 = [69, 25, 4] lies inside [[sink]] entry 1"
stderr_has "'stage1.sink_gap' = 2"
[ ! -e o7 ] && pass "no output dir for an aim point in a sink" || fail "o7 was created"

grep -v -e '^\[\[sink\]\]' -e '^box' good.toml > nosink.toml
expect_exit 2 "stage 2 without sinks" -- "$CAVESIM" run nosink.toml --out o4
stderr_has "stage 2 needs at least one [[sink]]"

# Water table and phases (the small scenario is 12 voxels tall, with one sink).
# refused_after_good NAME WHAT TEXT: good.toml with TEXT (printf format) appended, as NAME.toml, is refused by
# `run` with exit 2 (the output folder o8 is checked at the end).
refused_after_good() {
  { cat good.toml; printf "$3"; } > "$1.toml"
  expect_exit 2 "$2" -- "$CAVESIM" run "$1.toml" --out o8
}
refused_after_good table_high "water table above the block" '[hydrology]\nwater_table = 12\n'
stderr_has "table_high.toml:22: key 'hydrology.water_table' = 12: a water table must lie in the block, 0 to nz - 1 = 11"
printf 'phase = []\n' | cat - good.toml > phase_empty.toml
expect_exit 2 "empty phase list" -- "$CAVESIM" run phase_empty.toml --out o8
stderr_has "phase_empty.toml:1: key 'phase' = []: an empty list"
refused_after_good phase_zero "phase with zero iterations" '[[phase]]\niterations = 0\n'
stderr_has "phase.iterations' = 0"
refused_after_good phase_sink "phase sink out of range" '[[phase]]\niterations = 10\nsinks = [2]\n'
stderr_has "key 'phase.sinks' (entry 1) names sink 2: the run has 1 sinks, numbered 1 to 1 (1 [[sink]] entries in file order, then 0 [site] springs)"
# Phase sources are numbered over the [[source]] entries, then the [[recharge]] inputs: a phase that
# lists sources could once only name [[source]] entries, and silently switched the recharge off.
refused_after_good phase_recharge "phase source beyond the recharge inputs" \
  '[[recharge]]\nkind = "stream"\npoints = [[8, 0, 11], [12, 0, 11]]\n[[phase]]\niterations = 10\nsources = [4]\n'
stderr_has "key 'phase.sources' (entry 1) names source 4: the run has 3 sources, numbered 1 to 3 (1 [[source]] entries in file order, then 2 [[recharge]] inputs, then 0 [site] sinkholes)"
refused_after_good phase_table "phase water table below the block" '[[phase]]\niterations = 10\nwater_table = -3\n'
stderr_has "phase.water_table' = -3"
refused_after_good phase_high "phase water table above the block" '[[phase]]\niterations = 10\nwater_table = 30\n'
stderr_has "phase_high.toml:23: key 'phase.water_table' (entry 1) = 30: a water table must lie in the block"
refused_after_good table_site "water table from a site without one" '[hydrology]\nfrom_site = true\n'
stderr_has "table_site.toml:22: key 'hydrology.from_site' = true needs a surface in 'site.water_table'"
# Keys the run would ignore: the table's shape with no water table, a water table or phases with stage 2 off.
refused_after_good table_dip "dip without a water table" '[hydrology]\ndip = 10\n'
stderr_has "table_dip.toml:22: key 'hydrology.dip' = 10: shapes the water table, and there is none"
refused_after_good table_lateral "vadose_lateral without a water table" '[hydrology]\nvadose_lateral = 0.5\n'
stderr_has "key 'hydrology.vadose_lateral' = 0.5: shapes the water table, and there is none"
sed 's/^iterations = 30/enabled = false/' good.toml > stage2_off.toml
{ cat stage2_off.toml; printf '[hydrology]\nwater_table = 5\n'; } > table_off.toml
expect_exit 2 "water table with stage 2 off" -- "$CAVESIM" run table_off.toml --out o8
stderr_has "table_off.toml:22: key 'hydrology.water_table' = 5: the water table acts on stage 2, which is off (stage2.enabled = false)"
{ cat stage2_off.toml; printf '[[phase]]\niterations = 10\n'; } > phase_off.toml
expect_exit 2 "phases with stage 2 off" -- "$CAVESIM" run phase_off.toml --out o8
stderr_has "phase_off.toml:21: table [[phase]]: base-level phases are stage-2 iterations, and stage 2 is off"
# A key at its default changes nothing and stays allowed (the example scenario lists every key).
{ cat good.toml; printf '[hydrology]\ndip = 0.0\n'; } > table_default.toml
expect_exit 0 "a shape key at its default" -- "$CAVESIM" validate table_default.toml
[ ! -e o8 ] && pass "no output dir for bad hydrology" || fail "o8 was created"
sed 's/^sources = \[4\]/sources = [3]/' phase_recharge.toml > phase_recharge_ok.toml
expect_exit 0 "a phase that names a recharge input" -- "$CAVESIM" run phase_recharge_ok.toml --out o17 -q
python3 - <<'PY' && pass "only the named recharge input injects" || fail "phase sources over recharge inputs"
import json
s = json.load(open("o17/report.json"))["stage2"]
w = s["source_water_injected"]
assert s["phases"][0]["sources"] == [3], s["phases"][0]["sources"]
assert w[0] == 0 and w[1] == 0 and w[2] > 0, w
PY

printf 'name = "x"\n[domain\n' > malformed.toml
expect_exit 2 "malformed TOML" -- "$CAVESIM" validate malformed.toml
stderr_has "malformed.toml:2"

expect_exit 2 "missing file" -- "$CAVESIM" run does-not-exist.toml --out o5
stderr_has "does-not-exist.toml"

expect_exit 2 "bad option value" -- "$CAVESIM" run good.toml --threads 0 --out o6
expect_exit 2 "unknown option" -- "$CAVESIM" run good.toml --frobnicate
expect_exit 2 "no subcommand" -- "$CAVESIM"
for d in o1 o2 o3 o4 o5 o6; do [ -e "$d" ] && fail "$d exists after a refused run"; done
[ -z "$(ls -A | grep '^\.')" ] && pass "no staging leftovers" || fail "staging leftovers: $(ls -A)"
expect_exit 0 "--help" -- "$CAVESIM" --help
expect_exit 0 "--version" -- "$CAVESIM" --version
grep -q "cavesim 0" stdout.txt && pass "version printed" || fail "version: $(cat stdout.txt)"
# Not a scenario file at all: a directory, a FIFO (would block), an endless device.
mkdir adir
expect_exit 2 "directory as scenario" -- "$CAVESIM" validate adir
stderr_has "is a directory"
mkfifo afifo
expect_exit 2 "FIFO as scenario" -- timeout 20 "$CAVESIM" validate afifo
stderr_has "not a regular file"
expect_exit 2 "device as scenario" -- timeout 20 "$CAVESIM" run /dev/zero --out o7
stderr_has "not a regular file"

# Numbers that pass a loose range but would break the run: a voxel OpenVDB cannot transform, a
# noise scale whose inverse overflows.
sed 's/^size = \[16, 1, 12\]/size = [16, 1, 12]\nvoxel_size = 1e-5/' good.toml > tinyvoxel.toml
expect_exit 2 "voxel size too small" -- "$CAVESIM" run tinyvoxel.toml --out o8
stderr_has "domain.voxel_size' = 1e-05"
sed 's/^porosity = 0.05/porosity = 0.05\nnoise = { amplitude = 0.02, scale = 5e-324 }/' good.toml > tinynoise.toml
expect_exit 2 "noise scale too small" -- "$CAVESIM" run tinynoise.toml --out o9
stderr_has "rock.noise.scale"

# A --seed the effective scenario.toml could not hold.
expect_exit 2 "--seed beyond 2^63 - 1" -- "$CAVESIM" run good.toml --seed 18446744073709551615 --out o10
stderr_has "--seed"
expect_exit 2 "negative --seed (no wrap-around)" -- "$CAVESIM" run good.toml --seed=-18446744073709551615 --out o10
stderr_has "--seed -18446744073709551615: must be a whole number"

# Output directories that cannot be ours: the current directory, the root, a path under a file.
expect_exit 2 "--out . refused" -- "$CAVESIM" run good.toml --out . --force -q
stderr_has "current directory"
expect_exit 2 "--out / refused" -- "$CAVESIM" run good.toml --out / --force -q
touch afile
expect_exit 2 "--out under a file refused" -- "$CAVESIM" run good.toml --out afile/sub -q
stderr_has "is not a directory"
for o in o7 o8 o9 o10; do [ -e $o ] && fail "$o was created"; done
[ -f good.toml ] && [ -d adir ] && pass "nothing removed by the refused runs" || fail "files went missing"
# A stage 1 whose flow networks would not fit in the memory this process may use is refused before
# they are built (2.1 M voxels in one zone need about 940 MB; the address space is capped at 1 GB).
cat > bigzone.toml <<'TOML'
[domain]
size = [128, 128, 128]
[[source]]
at = [0, 0, 127]
[stage2]
enabled = false
[output]
images = false
mesh = false
TOML
expect_exit 2 "stage 1 larger than the memory limit" -- bash -c "ulimit -v 1000000; exec \"$CAVESIM\" run bigzone.toml --out o11 -q"
stderr_has "this process may use"
[ ! -e o11 ] && pass "no output for the refused stage 1" || fail "o11 was created"
# A block whose whole run would not fit is refused by the pre-flight estimate before any work
# (10^8 voxels need several GB; the address space is capped at 2 GB); validate prints the estimate.
sed -e 's/^size = \[128, 128, 128\]/size = [1000, 1000, 100]/' -e 's/^at = \[0, 0, 127\]/at = [0, 0, 99]/' bigzone.toml > huge.toml
expect_exit 0 "validate prints the estimate" -- "$CAVESIM" validate huge.toml
grep -q "peak memory about" stdout.txt && pass "estimate printed" || fail "no estimate: $(cat stdout.txt)"
expect_exit 2 "run larger than the memory limit" -- bash -c "ulimit -v 2000000; exec \"$CAVESIM\" run huge.toml --out o13 -q"
stderr_has "this process may use"
[ ! -e o13 ] && pass "no output for the refused run" || fail "o13 was created"
# The speleothem stage counts too: the Figure 10 cave decorated at 1 cm voxels (about 100 M
# level-set voxels) is refused before any work, though the undecorated run fits.
sed -e 's/^voxel_size = 0.05$/voxel_size = 0.01/' "$SRC/scenarios/fig10_decorated.toml" > fine_decor.toml
expect_exit 0 "validate estimates the speleothem stage" -- "$CAVESIM" validate fine_decor.toml
grep -q "(speleothems), time roughly .* (speleothems: about 100.8 M level-set voxels" stdout.txt &&
  pass "speleothem estimate printed" || fail "no speleothem estimate: $(cat stdout.txt)"
expect_exit 2 "decorated run larger than the memory limit" -- bash -c "ulimit -v 4000000; exec \"$CAVESIM\" run fine_decor.toml --out o14 -q"
stderr_has "(speleothems,"
[ ! -e o14 ] && pass "no output for the refused decorated run" || fail "o14 was created"
# Geology and recharge that cannot be: a fracture family that cannot fit, recharge outside the land
# surface. Each names file, line, key and value, and writes nothing.
cat good.toml > frac_long.toml
cat >> frac_long.toml <<'TOML'
[[rock.fracture_family]]
dip = 80.0
min_length = 40.0
max_length = 60.0
TOML
expect_exit 2 "fracture longer than the block" -- "$CAVESIM" run frac_long.toml --out o14
# The key's own line (23), not the entry's header (21).
stderr_has "frac_long.toml:23: key 'rock.fracture_family.min_length' = 40: the fracture family cannot fit"
[ ! -e o14 ] && pass "no output for a fracture family that cannot fit" || fail "o14 was created"
sed 's/^min_length = 40.0/min_length = 2.0\nspacing = 30.0/' frac_long.toml > frac_sparse.toml
expect_exit 2 "fracture spacing larger than the block" -- "$CAVESIM" validate frac_sparse.toml
stderr_has "key 'rock.fracture_family.spacing' = 30: the fracture family cannot fit"
sed 's/^min_length = 40.0/kappa = 0.0/' frac_long.toml > frac_kappa.toml
expect_exit 2 "fracture kappa zero" -- "$CAVESIM" validate frac_kappa.toml
stderr_has "key 'rock.fracture_family.kappa' = 0.0: must be a number in (0,"
# A family whose drawn discs all miss the block (seed 1 here) cannot fit either: it once ran with
# no fracture and reported a mean dip of 0.
cat > frac_none.toml <<'TOML'
seed = 1
[domain]
size = [20, 2, 2]
[[rock.fracture_family]]
spacing = 20
min_length = 20
max_length = 20
dip = 0
kappa = 1000
[[source]]
at = [0, 0, 1]
[stage2]
enabled = false
TOML
expect_exit 2 "fracture family with no disc in the block" -- "$CAVESIM" run frac_none.toml --out o18
stderr_has "frac_none.toml:5: key 'rock.fracture_family.spacing' = 20: the fracture family cannot fit: none of its 3 discs drawn with seed 1 reaches the block"
[ ! -e o18 ] && pass "no output for a family with no disc" || fail "o18 was created"
grep -v -e '^\[\[source\]\]' -e '^at = ' good.toml > recharge_out.toml
cat >> recharge_out.toml <<'TOML'
[[recharge]]
kind = "sinkholes"
area = [0, 0, 20, 0]
count = 2
TOML
expect_exit 2 "recharge outside the land surface" -- "$CAVESIM" run recharge_out.toml --out o15
stderr_has "key 'recharge.area' = [0, 0, 20, 0]: recharge outside the land surface"
[ ! -e o15 ] && pass "no output for recharge outside the land surface" || fail "o15 was created"
sed -e 's/^kind = "sinkholes"/kind = "stream"/' -e 's/^area = .*/points = [[1.0, 0.0, 11.0], [18.0, 0.0, 11.0]]/' \
  -e '/^count = /d' recharge_out.toml > stream_out.toml
expect_exit 2 "stream outside the block" -- "$CAVESIM" validate stream_out.toml
stderr_has "key 'recharge.points' = [[1, 0, 11], [18, 0, 11]]: recharge outside the land surface"
# A sinkhole box that does not fit its area or the block's height (it was cut to the block), and
# recharge on a sink (the message names the kind).
sed -e 's/^area = .*/area = [2, 0, 12, 0]/' -e 's/^count = 2/count = 1\nradius = 1/' recharge_out.toml > sinkhole_wide.toml
expect_exit 2 "sinkhole wider than its area" -- "$CAVESIM" validate sinkhole_wide.toml
stderr_has "key 'recharge.radius' = 1: a sinkhole of radius r is a (2r+1) × (2r+1) × (r+1) box, which must fit in its area [2, 0, 12, 0]"
sed -e 's/^kind = "sinkholes"/kind = "stream"/' -e 's/^area = .*/points = [[11.0, 0.0, 11.0], [15.0, 0.0, 11.0]]/' \
  -e '/^count = /d' recharge_out.toml > stream_sink.toml
expect_exit 2 "stream onto a sink" -- "$CAVESIM" validate stream_sink.toml
stderr_has "key 'recharge.kind' = \"stream\" (entry 1): an input at [15, 0, 11] overlaps [[sink]] entry 1"
# A sinkholes-only key on another kind would be ignored: refused with its own line.
sed -e 's/^kind = "sinkholes"/kind = "stream"/' -e 's/^area = .*/points = [[1.0, 0.0, 11.0], [8.0, 0.0, 11.0]]/' \
  recharge_out.toml > stream_count.toml
count_line=$(grep -n '^count = ' stream_count.toml | cut -d: -f1)
expect_exit 2 "count on a stream" -- "$CAVESIM" run stream_count.toml --out o19
stderr_has "stream_count.toml:$count_line: key 'recharge.count' = 2: only sinkholes take a count"
[ ! -e o19 ] && pass "no output for count on a stream" || fail "o19 was created"
sed -e 's/^kind = "sinkholes"/kind = "diffuse"/' -e 's/^count = 2/radius = 0/' recharge_out.toml > diffuse_radius.toml
expect_exit 2 "radius on diffuse recharge" -- "$CAVESIM" validate diffuse_radius.toml
stderr_has "key 'recharge.radius' = 0: only sinkholes take a radius"
# A snapshot the run never reaches would give no picture: refused, with the line.
sed 's/^iterations = 30/iterations = 30\nsnapshots = [10, 31]/' good.toml > snap_late.toml
expect_exit 2 "snapshot after the last iteration" -- "$CAVESIM" run snap_late.toml --out o16
stderr_has "snap_late.toml:17: key 'stage2.snapshots' = 31: a snapshot is taken after one of the run's stage-2 iterations, 1 to 30"
[ ! -e o16 ] && pass "no output for an unreachable snapshot" || fail "o16 was created"
# A snapshot is only a picture: refused without pictures or without stage 2.
sed 's/^iterations = 30/iterations = 30\nsnapshots = [10, 20]/' good.toml > snap_noimg.toml
printf 'images = false\n' >> snap_noimg.toml
expect_exit 2 "snapshots without pictures" -- "$CAVESIM" run snap_noimg.toml --out o16
stderr_has "snap_noimg.toml:17: key 'stage2.snapshots' = [10, 20]: a snapshot is a picture of the state (images/iter_NNNN.png, images/sequence.png) and 'output.images' = false writes no pictures"
sed 's/^iterations = 30/enabled = false\nsnapshots = [10]/' good.toml > snap_off.toml
expect_exit 2 "snapshots with stage 2 off" -- "$CAVESIM" run snap_off.toml --out o16
stderr_has "key 'stage2.snapshots' = [10]: a snapshot is a picture of the state (images/iter_NNNN.png, images/sequence.png) taken in stage 2, and 'stage2.enabled' = false"
[ ! -e o16 ] && pass "no output for snapshots that give no picture" || fail "o16 was created"
{ cat good.toml; printf 'images = false\n[speleothems]\nenabled = true\nframes = 3\n'; } > frames_noimg.toml
expect_exit 2 "speleothem frames without pictures" -- "$CAVESIM" validate frames_noimg.toml
stderr_has "frames_noimg.toml:24: key 'speleothems.frames' = 3: growth frames are pictures, and 'output.images' = false writes none"
{ cat good.toml; printf 'images = false\n[speleothems]\nenabled = true\n'; } > frames_default.toml
expect_exit 0 "speleothems without pictures, frames at the default" -- "$CAVESIM" validate frames_default.toml
# A speleothem step that would need more than a million steps is refused (it ran for days, deaf to SIGTERM).
{ cat good.toml; printf '[speleothems]\nenabled = true\nyears = 5000\ntime_step = 1e-300\n'; } > spstep.toml
expect_exit 2 "a speleothem step far too small" -- "$CAVESIM" run spstep.toml --out o16
stderr_has "spstep.toml:24: key 'speleothems.time_step' = 1e-300: 5000 years in steps of 1e-300 years would take 5e+303 steps, more than 1000000; use a step of at least 0.005 years, or 0 (the stable step)"
[ ! -e o16 ] && pass "no output for a speleothem step far too small" || fail "o16 was created"
{ cat good.toml; printf '[speleothems]\nenabled = true\nyears = 5000\ntime_step = 0.005\n'; } > spstep_edge.toml
expect_exit 0 "a speleothem step of exactly 10^6 steps" -- "$CAVESIM" validate spstep_edge.toml
sed 's/^time_step = 0.005/time_step = 0.00499/' spstep_edge.toml > spstep_past.toml
expect_exit 2 "a speleothem step just past 10^6 steps" -- "$CAVESIM" validate spstep_past.toml
# Leading zeros in --seed are still the same number.
expect_exit 0 "--seed with leading zeros" -- "$CAVESIM" run good.toml --seed 00000000000000000001 --out o12 -q
grep -q "^seed = 1$" o12/scenario.toml && pass "seed 1 recorded" || fail "seed: $(grep seed o12/scenario.toml)"
finish
