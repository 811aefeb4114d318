# The paper's 2D behaviours emerge from the rules (Figures 8 and 9), and do not depend on the
# orientation of the section or on a few voxels of padding:
#   fig08: every source connected, at least one phreatic loop and one tributary capture;
#   fig09: no phreatic loops.
. "$(dirname "$0")/lib.sh"
TRANSFORM="$(dirname "$0")/toml_transform.py"
check() {  # report.json, python condition on network n
  python3 - "$1" "$2" <<'PY'
import json, sys
n = json.load(open(sys.argv[1]))["network"]
ok = eval(sys.argv[2], {}, {"n": n})
print(sys.argv[1], n, "->", "ok" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY
}
for variant in plain mirror pad; do
  for fig in fig08 fig09; do
    case $variant in
      plain) cp "$SRC/scenarios/$fig.toml" "$fig-$variant.toml" ;;
      mirror) python3 "$TRANSFORM" mirror 0 "$SRC/scenarios/$fig.toml" "$fig-$variant.toml" ;;
      pad) python3 "$TRANSFORM" pad 3 "$SRC/scenarios/$fig.toml" "$fig-$variant.toml" ;;
    esac
    expect_exit 0 "$fig $variant runs" -- "$CAVESIM" run "$fig-$variant.toml" --out "$fig-$variant" -q
  done
  check "fig08-$variant/report.json" \
    'n["sources_connected"] == n["sources_total"] == 3 and n["phreatic_loops"] >= 1 and n["tributary_captures"] >= 1' \
    && pass "fig08 $variant: sequential linkage with loops and captures" || fail "fig08 $variant"
  check "fig09-$variant/report.json" 'n["phreatic_loops"] == 0' \
    && pass "fig09 $variant: no phreatic loops" || fail "fig09 $variant"
done
# Paper §3.2: the result stays the same while the ratio of the rates is unchanged. Rates and source
# pressures × 4 (exact in floating point) must give the same cave bit for bit.
python3 - "$SRC/scenarios/fig09.toml" fig09-x4.toml <<'PY'
import re, sys
s = open(sys.argv[1]).read()
s = re.sub(r"^p_rate = ([0-9.]+)", lambda m: f"p_rate = {float(m.group(1)) * 4!r}", s, flags=re.M)
s = re.sub(r"^p_rate_channel = ([0-9.]+)", lambda m: f"p_rate_channel = {float(m.group(1)) * 4!r}", s, flags=re.M)
s = s.replace("[[source]]\n", "[[source]]\npressure = 4.0\n")
open(sys.argv[2], "w").write(s)
PY
grep -q "pressure = 4.0" fig09-x4.toml && grep -q "^p_rate = 0.01$" fig09-x4.toml && pass "fig09 x4 scenario" || fail "fig09 x4 scenario: $(cat fig09-x4.toml)"
expect_exit 0 "fig09 x4 runs" -- "$CAVESIM" run fig09-x4.toml --out fig09-x4 -q
python3 - fig09-plain/report.json fig09-x4/report.json <<'PY' && pass "fig09: rates x4 give the same channels" || fail "fig09: rates x4 changed the channels"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ("porosity", "flags", "flow"):
    assert a["checksums"][k] == b["checksums"][k], k
assert a["network"]["phreatic_loops"] == b["network"]["phreatic_loops"]
PY
finish
