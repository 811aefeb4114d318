# Stage-2 rules of docs/model.md that the figures do not pin down:
#   pressure drives discharge: two mirror-placed sources of pressure 1 and 2 — the stronger one
#   takes in twice the water and grows about twice the cave on its side; with inflow = "head" the
#   inflow rises once the channel joins the sink, and a lower head (pressure_scale) takes in less;
#   with inflow = "level" the head scale does not matter.
. "$(dirname "$0")/lib.sh"
cat > two.toml <<'TOML'
name = "two_sources"
seed = 3
[domain]
size = [40, 21, 10]
[rock]
porosity = 0.05
[[source]]
at = [3, 4, 5]
pressure = 1.0
[[source]]
at = [3, 16, 5]
pressure = 2.0
[[sink]]
box = [[39, 0, 0], [39, 20, 9]]
[stage2]
iterations = 400
[output]
images = false
mesh = false
formats = ["vtk"]
TOML
sed 's/^iterations = 400/iterations = 400\npressure_scale = 12/' two.toml > low.toml
sed 's/^iterations = 400/iterations = 400\ninflow = "level"/' two.toml > level.toml
sed 's/^iterations = 400/iterations = 400\ninflow = "level"\npressure_scale = 12/' two.toml > level_low.toml
for s in two low level level_low; do expect_exit 0 "$s runs" -- "$CAVESIM" run $s.toml --out $s -q; done
/usr/bin/python3 - <<'PY' && pass "the stronger source takes in more water and grows a larger cave; the head sets the inflow" || fail "pressure-driven discharge"
import json
import vtk
from vtk.util.numpy_support import vtk_to_numpy

def load(d):
    r = json.load(open(d + "/report.json"))
    rd = vtk.vtkXMLImageDataReader()
    rd.SetFileName(d + "/state.vti")
    rd.Update()
    cave = vtk_to_numpy(rd.GetOutput().GetCellData().GetArray("cave")).reshape(10, 21, 40)
    return r["stage2"], cave

s, cave = load("two")
weak, strong = s["source_water_injected"]
cw, cs = int(cave[:, :10, :].sum()), int(cave[:, 11:, :].sum())
print("head: injected", weak, strong, "cave voxels", cw, cs, "breakthrough", s["breakthrough_iteration"])
assert s["breakthrough_iteration"] is not None
assert 1.8 < strong / weak < 2.2, (weak, strong)
assert cs > 1.5 * cw, (cw, cs)
inflow = [h["injected"] for h in s["history"]]
b = s["breakthrough_iteration"]
before, after = sum(inflow[b - 21:b - 1]) / 20, sum(inflow[-20:]) / 20
print("inflow before breakthrough", before, "at the end", after)
assert after > before
low, _ = load("low")
print("head, pressure_scale 12: injected", low["source_water_injected"])
assert sum(low["source_water_injected"]) < 0.9 * (weak + strong)
lv, lvc = load("level")
lvl, lvlc = load("level_low")
print("level: injected", lv["source_water_injected"], "with pressure_scale 12", lvl["source_water_injected"])
assert lv["source_water_injected"] == lvl["source_water_injected"] and (lvc == lvlc).all()
PY
finish
