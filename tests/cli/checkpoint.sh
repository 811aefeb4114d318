# Checkpoint and resume: a small 3D run (a shrunk Figure 10, both stages, snapshots, --formats
# all) killed with SIGKILL in stage 2, resumed, killed again, resumed again, gives every file of an
# uninterrupted run byte for byte (report.json, .md, .html: but for the timings); so does a
# run with checkpoints that is never stopped; so does a run with base-level phases and a water
# table killed at and between phase boundaries. A damaged, cut or missing checkpoint: exit 2 and
# nothing written.
. "$(dirname "$0")/lib.sh"
cat > s.toml <<'TOML'
name = "small3d"
seed = 7
[domain]
size = [30, 30, 10]
[rock]
porosity = 0.05
noise = { amplitude = 0.02, scale = 4.0 }
[[rock.sphere]]
center = [12, 15, 4]
radius = 3
core_porosity = 0.005
[[source]]
at = [3, 5, 8]
[[source]]
at = [4, 24, 7]
[[source]]
at = [13, 26, 8]
[[sink]]
box = [[27, 13, 0], [29, 17, 2]]
[stage2]
iterations = 120
snapshots = [20, 45, 90, 110]
[output]
image_width = 256
TOML
# Every file of $1 and $2 the same; report files compared without their timings.
same_outputs() {
  local a=$1 b=$2 what=$3
  if diff -rq -x report.json -x report.md -x report.html "$a" "$b" >diff.txt; then
    pass "$what: every file but the reports identical"
  else
    fail "$what: files differ: $(cat diff.txt)"
  fi
  same_report_figures "$a/report.json" "$b/report.json" && pass "$what: report.json identical but for timings" || fail "$what: report.json differs"
  local f timing='(stage 1|stage 2|mesh and pictures|skeleton and report|files for other tools|total)'
  for f in report.md report.html; do
    if [ -f "$a/$f" ] && [ -f "$b/$f" ] && diff <(grep -vE "^\| $timing \||<tr><td>$timing</td>" "$a/$f") <(grep -vE "^\| $timing \||<tr><td>$timing</td>" "$b/$f") >/dev/null; then
      pass "$what: $f identical but for timings"
    else
      fail "$what: $f differs"
    fi
  done
}

expect_exit 0 "uninterrupted run" -- "$CAVESIM" run s.toml --formats all --out whole -q
[ -e whole/images/iter_0045.png ] && [ -e whole/images/sequence.png ] && pass "snapshots taken" || fail "no snapshots"

expect_exit 0 "run with checkpoints every 10" -- "$CAVESIM" run s.toml --formats all --out ck --checkpoint-every 10 -q
same_outputs whole ck "checkpointed run"
[ ! -e .ck.checkpoint ] && pass "checkpoint folder removed after success" || fail ".ck.checkpoint left behind"

# Killed (SIGKILL, no clean-up) after iteration 57: the newest checkpoint is after 50.
expect_exit 137 "killed after iteration 57" -- env CAVESIM_TEST_KILL_AT_ITERATION=57 \
  "$CAVESIM" run s.toml --formats all --out r --checkpoint-every 10 -j 1 -q
[ ! -e r ] && [ -f .r.checkpoint/checkpoint.cavesim ] && pass "no output folder, a checkpoint" ||
  fail "after the kill: $(ls -A)"
# Resumed with another thread count, killed again after iteration 100 (checkpoint after 100).
expect_exit 137 "resume killed after iteration 100" -- env CAVESIM_TEST_KILL_AT_ITERATION=100 \
  "$CAVESIM" resume r -j 2
stderr_has "after stage-2 iteration 50"
expect_exit 0 "resume to the end" -- "$CAVESIM" resume r
stderr_has "after stage-2 iteration 100"
same_outputs whole r "killed twice and resumed"
[ ! -e .r.checkpoint ] && pass "checkpoint folder removed after the resumed run" || fail ".r.checkpoint left behind"
[ -z "$(ls -A | grep partial)" ] && pass "no staging folders left" || fail "left: $(ls -A)"

# A resumed run refuses a folder that appeared meanwhile, as run does.
expect_exit 137 "killed after iteration 30" -- env CAVESIM_TEST_KILL_AT_ITERATION=30 \
  "$CAVESIM" run s.toml --formats all --out q --checkpoint-every 30 -q
mkdir q && touch q/x
expect_exit 2 "resume into a non-empty folder" -- "$CAVESIM" resume q -q
stderr_has "not empty"
expect_exit 0 "resume with --force" -- "$CAVESIM" resume q --force -q
same_outputs whole q "resumed with --force"

# SIGTERM: the staging folder goes, the checkpoint stays and the message says how to go on.
sed -e 's/^iterations = 120/iterations = 100000/' s.toml > long.toml
"$CAVESIM" run long.toml --out t --checkpoint-every 5 -j1 >stdout.txt 2>stderr.txt &
pid=$!
for _ in $(seq 1 300); do [ -f .t.checkpoint/checkpoint.cavesim ] && break; sleep 0.1; done
kill -s TERM "$pid"
wait "$pid"
got=$?
[ "$got" -eq 143 ] && pass "SIGTERM with checkpoints (exit 143)" || fail "SIGTERM with checkpoints: exit $got"
stderr_has "cavesim resume t"
[ -f .t.checkpoint/checkpoint.cavesim ] && [ -z "$(ls -A | grep '^\.t\.partial')" ] && pass "SIGTERM: checkpoint kept, staging removed" ||
  fail "SIGTERM: left $(ls -A)"
# A run into the folder that succeeds makes an older checkpoint of it spent.
expect_exit 0 "a run without checkpoints into t" -- "$CAVESIM" run s.toml --out t -q
[ ! -e .t.checkpoint ] && pass "the older checkpoint removed" || fail ".t.checkpoint left behind"

# Damaged checkpoints: exit 2, a message naming the file, nothing written.
expect_exit 137 "killed after iteration 40" -- env CAVESIM_TEST_KILL_AT_ITERATION=40 \
  "$CAVESIM" run s.toml --formats all --out d --checkpoint-every 20 -q
ck=.d.checkpoint/checkpoint.cavesim
cp "$ck" good.bin
head -c $(($(stat -c %s good.bin) / 2)) good.bin > "$ck"
expect_exit 2 "cut checkpoint" -- "$CAVESIM" resume d -q
stderr_has "checkpoint.cavesim: damaged or not a file this program wrote"
python3 -c "
import sys; b = bytearray(open('good.bin', 'rb').read()); b[len(b) // 3] ^= 0x10; open(sys.argv[1], 'wb').write(b)" "$ck"
expect_exit 2 "changed checkpoint" -- "$CAVESIM" resume d -q
stderr_has "checksum"
: > "$ck"
expect_exit 2 "empty checkpoint" -- "$CAVESIM" resume d -q
[ ! -e d ] && [ -e "$ck" ] && pass "damaged checkpoints: no output folder, the checkpoint kept" || fail "left: $(ls -A)"
cp good.bin "$ck"
expect_exit 0 "the intact checkpoint resumes" -- "$CAVESIM" resume d -q
same_outputs whole d "resumed from iteration 40"
expect_exit 2 "no checkpoint" -- "$CAVESIM" resume nowhere -q
stderr_has "no checkpoint to resume from"
expect_exit 2 "negative interval" -- "$CAVESIM" run s.toml --out n --checkpoint-every -1 -q
# Base-level phases under a dipping water table (sinks and sources change with the phase, the
# sources refill by head): killed at a phase boundary (the newest checkpoint after iteration 90,
# the last of phase 1), mid-phase and at the next boundary, resumed each time, gives every file of
# an uninterrupted run.
cat > ph.toml <<'TOML'
name = "phased"
seed = 5
[domain]
size = [28, 14, 20]
[rock]
porosity = 0.05
noise = { amplitude = 0.01, scale = 4.0 }
[[source]]
at = [5, 4, 19]
[[source]]
at = [12, 10, 19]
[[sink]]
box = [[27, 5, 12], [27, 8, 14]]
[[sink]]
box = [[27, 5, 3], [27, 8, 5]]
[stage1]
enabled = false
[stage2]
p_rate = 0.05
p_rate_channel = 0.001
source_porosity = 0.5
iterations = 150              # replaced by the phases' 200: resume checks against those
snapshots = [30, 60, 90, 130]
[hydrology]
water_table = 13
dip = 5
dip_direction = 90
vadose_lateral = 0.1
[[phase]]
iterations = 90
sinks = [1]
[[phase]]
iterations = 90
water_table = 4
sinks = [2]
sources = [1]
[[phase]]
iterations = 20
water_table = 4
[output]
image_width = 256
TOML
expect_exit 0 "phased run" -- "$CAVESIM" run ph.toml --formats all --out phwhole -q
python3 - <<'PY' && pass "phased run: three phases, each grows cave" || fail "phased run: phases"
import json
p = json.load(open("phwhole/report.json"))["stage2"]["phases"]
assert [x["first_iteration"] for x in p] == [1, 91, 181] and all(x["cave_voxels_added"] > 0 for x in p[1:])
PY
expect_exit 0 "phased run with checkpoints every 30" -- "$CAVESIM" run ph.toml --formats all --out phck --checkpoint-every 30 -q
same_outputs phwhole phck "phased checkpointed run"
expect_exit 137 "phased run killed after iteration 95" -- env CAVESIM_TEST_KILL_AT_ITERATION=95 \
  "$CAVESIM" run ph.toml --formats all --out ph --checkpoint-every 30 -j 1 -q
expect_exit 137 "phased resume killed after iteration 130" -- env CAVESIM_TEST_KILL_AT_ITERATION=130 \
  "$CAVESIM" resume ph -j 2
stderr_has "after stage-2 iteration 90"
expect_exit 137 "phased resume killed after iteration 180" -- env CAVESIM_TEST_KILL_AT_ITERATION=180 \
  "$CAVESIM" resume ph -j 1
stderr_has "after stage-2 iteration 120"
expect_exit 0 "phased resume to the end" -- "$CAVESIM" resume ph
stderr_has "after stage-2 iteration 180"
same_outputs phwhole ph "phased run killed three times and resumed"
[ ! -e .ph.checkpoint ] && pass "phased: checkpoint folder removed" || fail ".ph.checkpoint left behind"
finish
