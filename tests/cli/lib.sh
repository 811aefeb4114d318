# Shared helpers for the end-to-end scripts: $1 binary, $2 source dir, $3 scratch dir.
set -u
CAVESIM=$1
SRC=$2
WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
failures=0
pass() { echo "ok: $*"; }
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# expect_exit CODE DESCRIPTION -- command...
expect_exit() {
  local want=$1 what=$2; shift 3
  "$@" >stdout.txt 2>stderr.txt
  local got=$?
  if [ "$got" -eq "$want" ]; then pass "$what (exit $got)"; else fail "$what: exit $got, wanted $want; stderr: $(cat stderr.txt)"; fi
}
stderr_has() { if grep -qF -- "$1" stderr.txt; then pass "stderr mentions '$1'"; else fail "stderr lacks '$1': $(cat stderr.txt)"; fi; }
# shared_run NAME [AS]: copies the run NAME of tests/cli/shared_runs.sh (the CTest fixture
# cli_shared_runs, whose folder CTest passes in CAVESIM_SHARED_RUNS) here, as AS (default NAME).
shared_run() {
  local from=${CAVESIM_SHARED_RUNS:?the shared runs come from tests/cli/shared_runs.sh (CTest: cli.shared_runs)}/$1
  if [ -f "$from/report.json" ] && cp -r "$from" "${2:-$1}"; then pass "shared run $1"; else fail "no shared run $from"; fi
}
finish() { if [ "$failures" -eq 0 ]; then echo "all passed"; exit 0; else echo "$failures failure(s)"; exit 1; fi; }
small_scenario() {  # a tiny, fast scenario
  cat <<'TOML'
name = "small"
seed = 5
[domain]
size = [16, 1, 12]
[rock]
porosity = 0.05
[[rock.channel]]
points = [[4, 0, 11], [4, 0, 6]]
[[source]]
at = [4, 0, 11]
[[sink]]
box = [[15, 0, 0], [15, 0, 11]]
[stage1]
enabled = false
[stage2]
iterations = 30
p_rate = 0.05
p_rate_channel = 0.001
[output]
image_width = 256
TOML
}
tiny_ensemble_scenario() {  # 12 × 12 × 6 voxels, both stages, no pictures or meshes: fast members
  cat <<'TOML'
name = "tiny"
seed = 3
[domain]
size = [12, 12, 6]
[rock]
porosity = 0.05
noise = { amplitude = 0.03, scale = 4.0 }
[[source]]
at = [2, 2, 5]
[[sink]]
at = [10, 10, 0]
[stage2]
iterations = 40
[output]
images = false
mesh = false
formats = ["vtk"]
TOML
}
# same_members A B N: the recorded checksums agree and every file but report.json/.md/.html is identical.
same_members() {
  local a=$1 b=$2 n=$3 i m
  for ((i = 0; i < n; i++)); do
    m=$(printf 'm%04d' "$i")
    python3 - "$a/members/$m.json" "$b/members/$m.json" <<'PY' || return 1
import json, sys
x, y = (json.load(open(p)) for p in sys.argv[1:3])
assert x["status"] == y["status"] == "ok" and x["checksum"] == y["checksum"] and x["seed"] == y["seed"], (x, y)
PY
    diff -rq -x report.json -x report.md -x report.html "$a/members/$m" "$b/members/$m" >/dev/null || return 1
  done
}
# same_report_figures A B: the two report.json files agree but for the timings and thread count.
same_report_figures() {
  python3 - "$1" "$2" <<'PY'
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
}
