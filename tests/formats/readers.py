"""Loads every export of the hand-made cave (tests/formats/sample.h) with other programs'
readers and checks counts, bounds and units against the known answers.

Usage: readers.py OUT_DIR WRITTEN_LIST SVX_DUMP TH_DUMP  (run by readers.sh)
"""
import csv
import os
import sys

import pyopenvdb
import vtk
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from export_readback import check, finish, glb_blocks, near, stations, vtk_read  # noqa: E402

out, written, svx_dump, th_dump = sys.argv[1:5]

# Known answers (sample.h): 0.5 m voxels, 12 x 8 x 6; 52 cave voxels; passage box x 0.5-5.5,
# y 1.5-2.5 (side passage to 4.0), z 1-2; skeleton nodes below.
H = 0.5
NODES = [(1, 2, 1.5), (2, 2, 1.5), (3, 2, 1.5), (4, 2, 1.5), (5, 2, 1.5), (3, 3, 1.5), (3, 3.8, 1.5)]
CAVE_BOX = (0.5, 5.5, 1.5, 4.0, 1.0, 2.0)  # xmin xmax ymin ymax zmin zmax, metres

files = open(written).read().split()
check(files == ["cave.glb", "state.vti", "skeleton.vtp", "cave.stl", "cave.svx", "cave.th", "cave.ts",
                "skeleton.pl", "history.csv", "branches.csv", "cave.vdb"], "files written: %s" % files)

# --- cave.vdb: pyopenvdb reads every grid; `cave` is a level set ---
grids, meta = pyopenvdb.readAll(out + "/cave.vdb")
names = sorted(g.name for g in grids)
check(names == ["cave", "flags", "flow", "porosity", "porosity0", "pressure", "water", "zone"], "vdb grids %s" % names)
by = {g.name: g for g in grids}
for g in grids:
    check(g.valueTypeName == "float", "vdb %s type %s" % (g.name, g.valueTypeName))
    check("unit" in g.metadata and "description" in g.metadata, "vdb %s lacks unit/description" % g.name)
check(by["cave"].gridClass == "level set", "cave class %s" % by["cave"].gridClass)
check(by["cave"].metadata["unit"] == "m", "cave unit")
check(abs(by["flags"].transform.voxelSize()[0] - H) < 1e-12, "flags voxel size")
acc = by["flags"].getConstAccessor()
check(acc.getValue((3, 3, 2)) == 8.0 and acc.getValue((0, 0, 0)) == 0.0, "flags values")
check(by["zone"].getConstAccessor().getValue((3, 3, 2)) == 1.0, "zone value")
check(by["zone"].getConstAccessor().getValue((0, 0, 0)) == -1.0, "zone -1")
ls = by["cave"]
lacc = ls.getConstAccessor()
h = ls.transform.voxelSize()[0]


def sdf(x, y, z):  # level-set index m is centred at (m + 0.5) h
    return lacc.getValue((round(x / h - 0.5), round(y / h - 0.5), round(z / h - 0.5)))


check(sdf(3.0, 2.0, 1.5) < -0.3, "cave sdf at the passage centre %g" % sdf(3.0, 2.0, 1.5))
check(sdf(3.0, 0.25, 1.5) > 0, "cave sdf in the rock %g" % sdf(3.0, 0.25, 1.5))
check(abs(sdf(3.0, 1.5, 1.5)) < 0.2, "cave sdf at the wall %g" % sdf(3.0, 1.5, 1.5))

# --- state.vti ---
img = vtk_read(vtk.vtkXMLImageDataReader, out + "/state.vti")
check(img.GetDimensions() == (13, 9, 7), "vti dims %s" % (img.GetDimensions(),))
check(img.GetSpacing() == (H, H, H) and img.GetOrigin() == (0, 0, 0), "vti spacing/origin")
check(img.GetNumberOfCells() == 576, "vti cells")
cd = img.GetCellData()
arrays = [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())]
check(arrays == ["porosity", "porosity0", "flags", "zone", "pressure", "flow", "water", "cave"], "vti arrays %s" % arrays)
cave = vtk_to_numpy(cd.GetArray("cave"))
check(int(cave.sum()) == 52, "vti cave voxels %d" % cave.sum())
flow = vtk_to_numpy(cd.GetArray("flow"))
check(flow[3 + 12 * (3 + 8 * 2)] == 3.0, "vti flow at (3,3,2) (x-fastest order)")
fd = img.GetFieldData()
check(fd.GetAbstractArray("length_unit").GetValue(0) == "m", "vti length unit")
units = fd.GetAbstractArray("units")
check(units.GetNumberOfValues() == 8 and units.GetValue(0).startswith("porosity:"), "vti units")
check(abs(fd.GetArray("voxel_size_m").GetValue(0) - H) < 1e-15, "vti voxel size")

# --- skeleton.vtp ---
p = vtk_read(vtk.vtkXMLPolyDataReader, out + "/skeleton.vtp")
check(p.GetNumberOfPoints() == 7 and p.GetNumberOfLines() == 3, "vtp counts")
check(near(p.GetBounds(), (1, 5, 2, 3.8, 1.5, 1.5), 1e-12), "vtp bounds %s" % (p.GetBounds(),))
pd = p.GetPointData()
for a in ("radius", "passage_id", "degree", "flow", "pressure"):
    check(pd.GetArray(a) is not None, "vtp point array %s" % a)
check(list(vtk_to_numpy(pd.GetArray("flow"))) == [2, 4, 6, 8, 10, 6, 6], "vtp flow")
check(list(vtk_to_numpy(pd.GetArray("degree"))) == [1, 2, 3, 2, 1, 2, 1], "vtp degree")
length = vtk_to_numpy(p.GetCellData().GetArray("length_m"))
check(abs(length.sum() - 5.8) < 1e-12, "vtp total length %g" % length.sum())

# --- cave.stl and cave.glb: VTK's readers ---
stl = vtk_read(vtk.vtkSTLReader, out + "/cave.stl")
b = stl.GetBounds()
check(stl.GetNumberOfCells() > 100, "stl triangles")
check(near(b, CAVE_BOX, 0.1), "stl bounds %s" % (b,))

blocks = glb_blocks(out + "/cave.glb")
check(len(blocks) == 1, "glb blocks %d" % len(blocks))
g = blocks[0]
check(g.GetNumberOfCells() == stl.GetNumberOfCells(), "glb triangles %d vs stl %d" % (g.GetNumberOfCells(), stl.GetNumberOfCells()))
check(g.GetPointData().GetNormals() is not None, "glb normals")
gb = g.GetBounds()  # glTF y up: (x, z, -y)
check(near(gb, (b[0], b[1], b[4], b[5], -b[3], -b[2]), 1e-5), "glb bounds %s vs stl %s" % (gb, b))

# --- cave.svx through cavern, cave.th through therion: station positions ---
def xsects(dump):
    return [tuple(float(v) for v in line.split()[1:5]) for line in open(dump) if line.startswith("XSECT ")]


for dump, sep in ((svx_dump, "."), (th_dump, "_")):
    pos = stations(dump)
    check(len(pos) == 7, "%s stations %d" % (dump, len(pos)))
    got = sorted(pos.values())
    check(all(near(a, b_, 0.006) for a, b_ in zip(got, sorted(NODES))), "%s positions %s" % (dump, got))
    check(("cave.p2%s2" % sep) in pos and near(pos["cave.p2%s2" % sep], (3, 3.8, 1.5), 0.006), "%s p2.2" % dump)
x = xsects(svx_dump)
check(len(x) == 9 and (2.5, 2.5, 0.5, 0.5) in x and (0.5, 0.5, 0.5, 0.5) in x, "svx LRUD %s" % x)

# --- GOCAD: counts and bounds (no Debian reader; a plain parse) ---
ts = open(out + "/cave.ts").read().split("\n")
check(ts[0] == "GOCAD TSurf 1" and ts[-2] == "END", "ts header/end")
vrtx = [tuple(float(v) for v in l.split()[2:5]) for l in ts if l.startswith("VRTX ")]
trgl = [l for l in ts if l.startswith("TRGL ")]
check(len(trgl) == stl.GetNumberOfCells(), "ts triangles")
check(near([min(v[0] for v in vrtx), max(v[0] for v in vrtx)], [b[0], b[1]], 1e-5), "ts x bounds")
check('AXIS_UNIT "m" "m" "m"' in ts and "ZPOSITIVE Elevation" in ts, "ts units")
pl = open(out + "/skeleton.pl").read().split("\n")
check(len([l for l in pl if l.startswith("PVRTX ")]) == 7 and len([l for l in pl if l.startswith("SEG ")]) == 6, "pl counts")

# --- CSV ---
rows = list(csv.DictReader(open(out + "/history.csv")))
check(len(rows) == 3 and rows[2]["injected"] == "4.5" and rows[1]["sources_connected"] == "1", "history.csv")
rows = list(csv.DictReader(open(out + "/branches.csv")))
check(len(rows) == 3, "branches.csv rows")
check(abs(sum(float(r["length_m"]) for r in rows) - 5.8) < 1e-12, "branches.csv length")
check(sorted(float(r["azimuth_deg"]) for r in rows) == [0, 90, 90], "branches.csv azimuths")

finish("FAILED:", "readers: every export loaded back (%d files)" % len(files))
