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
