# A [site] run from the shipped example's files (scenarios/site/make_site.py): the block placed in
# UTM 33N, the transform in report.json, state.vti and state.vdb; a small site ensemble; bad site
# input exits 2 with nothing written. Skipped (exit 77) without GDAL's Python bindings.
. "$(dirname "$0")/lib.sh"
PY=/usr/bin/python3
$PY -c "from osgeo import gdal" 2>/dev/null || { echo "skip: no python3-gdal"; exit 77; }
mkdir site && $PY "$SRC/scenarios/site/make_site.py" site >/dev/null && pass "example files written"
sed -e 's/^iterations = .*/iterations = 60/' "$SRC/scenarios/site/site.toml" > site/s.toml
expect_exit 0 "validate" -- "$CAVESIM" validate site/s.toml
expect_exit 0 "site run" -- "$CAVESIM" run site/s.toml --out r -q
python3 - r <<'PY' && pass "world transform in report.json, state.vti and the effective scenario" || fail "world transform"
import json, re, sys
d = sys.argv[1]
r = json.load(open(d + "/report.json"))
w = r["world_from_index"]
assert w["origin_m"] == [500000.0, 4100000.0, 300.0] and w["scale_m"] == 5.0, w
assert w["crs"] == "WGS 84 / UTM zone 33N", w
head = open(d + "/state.vti", "rb").read(4000).decode("latin-1")
assert re.search(r'Origin="5e\+05 4100000 300"', head), head[:400]
assert r["stage2"]["source_connected_iteration"] is not None and len(r["stage2"]["source_connected_iteration"]) == 3
PY
if $PY -c "import pyopenvdb" 2>/dev/null; then
  $PY - r/state.vdb <<'PY' && pass "state.vdb transform puts voxel (0,0,0) at the origin" || fail "state.vdb transform"
import sys, pyopenvdb as vdb
g = vdb.read(sys.argv[1], "porosity")
x = g.transform.indexToWorld((0, 0, 0))
assert abs(x[0] - 500002.5) < 1e-6 and abs(x[1] - 4100002.5) < 1e-6 and abs(x[2] - 302.5) < 1e-6, x
PY
fi
# [[recharge]] under the DEM: diffuse inputs on the land surface of their columns, beside the
# site's sinkholes (3) and spring (1), counted by validate.
{ cat site/s.toml; printf '\n[[recharge]]\nkind = "diffuse"\nspacing = 15.0\n'; } > site/recharge.toml
expect_exit 0 "validate a site with diffuse recharge" -- "$CAVESIM" validate site/recharge.toml
grep -qF "15 source(s), 1 sink(s)" stdout.txt stderr.txt && pass "validate counts recharge, sinkholes and springs" ||
  fail "validate's counts: $(cat stdout.txt stderr.txt)"
expect_exit 0 "site run with diffuse recharge" -- "$CAVESIM" run site/recharge.toml --out rr -q --formats none
python3 - rr/report.json <<'PY' && pass "recharge sources on the land surface" || fail "recharge sources"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["recharge"]["sources"] == 12 and r["recharge"]["first_source"] == 1, r["recharge"]
PY
expect_exit 0 "report rebuilds a site run" -- "$CAVESIM" report r
expect_exit 0 "site ensemble of 2" -- "$CAVESIM" ensemble site/s.toml --members 2 --out e -j 2
python3 - e/ensemble.json <<'PY' && pass "site ensemble summary" || fail "site ensemble summary"
import json, sys
e = json.load(open(sys.argv[1]))
assert e["ok"] == 2 and e["probability"]["world_origin_m"] == [500000.0, 4100000.0, 300.0], e["probability"]
PY
[ -s e/images/probability_plan.png ] && pass "probability map" || fail "no probability map"

# Bad site input: exit 2, the file and the value named, no output folder.
$PY - site <<'PY'
import sys
from osgeo import gdal, osr
d = sys.argv[1]
def tif(name, epsg, x0, y1, px):
    ds = gdal.GetDriverByName("GTiff").Create(d + "/" + name, 64, 44, 1, gdal.GDT_Float32)
    ds.SetGeoTransform((x0, px, 0, y1, 0, -px))
    s = osr.SpatialReference(); s.ImportFromEPSG(epsg); ds.SetProjection(s.ExportToWkt())
    ds.GetRasterBand(1).Fill(360.0); ds = None
tif("degrees.tif", 4326, 15.0, 37.0, 0.0001)
tif("zone34.tif", 32634, 499990, 4100210, 5)
open(d + "/notatiff.tif", "w").write("hello\n")
open(d + "/far.csv", "w").write("x,y,name\n500100,4100100,Near\n510000,4100100,Far\n")
PY
bad() {  # bad DESCRIPTION KEY VALUE EXPECTED
  sed -e "s|^$2 = .*|$2 = \"$3\"|" site/s.toml > site/bad.toml
  expect_exit 2 "$1" -- "$CAVESIM" run site/bad.toml --out badrun -q
  stderr_has "$4"
  [ ! -e badrun ] && pass "nothing written ($1)" || fail "badrun written ($1)"
}
bad "not a GeoTIFF" dem notatiff.tif "notatiff.tif: not a GeoTIFF"
bad "geographic CRS" dem degrees.tif "geographic CRS 'WGS 84' (degrees)"
bad "CRSs that disagree" base_of_limestone zone34.tif "differs from the CRS 'WGS 84 / UTM zone 33N'"
bad "a point outside the block" sinkholes far.csv "far.csv:3: sinkhole 'Far' at x = 510000, y = 4100100 m lies outside the block"
sed -e 's|^origin = .*|origin = [500000.0, 4100000.0, 200.0]|' site/s.toml > site/bad.toml
expect_exit 2 "a surface that leaves the block" -- "$CAVESIM" run site/bad.toml --out badrun -q
stderr_has "terrain.tif: the surface leaves the block"
expect_exit 2 "validate names the bad file too" -- "$CAVESIM" validate site/bad.toml
finish
