"""Loads every export of a run with other programs' readers and checks it against report.json.

Usage: exports_check.py RUN_DIR NORMALS SVX_DUMP TH_DUMP  (run by exports.sh)
NORMALS: inward or outward, the side cave.glb's normals must face.
"""
import csv
import json
import math
import os
import sys

import pyopenvdb
import vtk
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from export_readback import check, finish, glb_blocks, near, stations, vtk_read  # noqa: E402

out, normals, svx_dump, th_dump = sys.argv[1:5]
rep = json.load(open(out + "/report.json"))

h = rep["voxel_size_m"]
nx, ny, nz = rep["grid"]
mesh = rep["mesh"]
skel = rep["skeleton"]
files = rep["exports"]
check(files == ["cave.glb", "state.vti", "skeleton.vtp", "cave.stl", "cave.svx", "cave.th", "cave.ts",
                "skeleton.pl", "history.csv", "branches.csv", "cave.vdb"], "exports listed: %s" % files)
block = (0, nx * h, 0, ny * h, 0, nz * h)


def inside(b, tol):
    return all(b[2 * i] >= block[2 * i] - tol and b[2 * i + 1] <= block[2 * i + 1] + tol for i in range(3))


# --- cave.stl (VTK): the mesh's triangles, inside the block ---
stl = vtk_read(vtk.vtkSTLReader, out + "/cave.stl")
b = stl.GetBounds()
check(stl.GetNumberOfCells() == mesh["faces"], "stl triangles %d vs report %d" % (stl.GetNumberOfCells(), mesh["faces"]))
check(inside(b, h), "stl bounds %s outside the block %s" % (b, block))
mass = vtk.vtkMassProperties()
mass.SetInputData(stl)
mass.Update()
check(abs(mass.GetVolume() - mesh["volume_m3"]) <= 1e-3 * mesh["volume_m3"], "stl volume %g vs %g" % (mass.GetVolume(), mesh["volume_m3"]))
check(abs(mass.GetSurfaceArea() - mesh["area_m2"]) <= 1e-3 * mesh["area_m2"], "stl area")

# --- cave.glb (VTK's glTF reader): same triangles, y up, normals on the asked side ---
blocks = glb_blocks(out + "/cave.glb")
check(len(blocks) == 1, "glb blocks %d" % len(blocks))
g = blocks[0]
check(g.GetNumberOfCells() == mesh["faces"], "glb triangles %d" % g.GetNumberOfCells())
check(g.GetNumberOfPoints() == mesh["vertices"], "glb vertices %d vs %d" % (g.GetNumberOfPoints(), mesh["vertices"]))
gb = g.GetBounds()  # glTF y up: (x, z, -y)
check(near(gb, (b[0], b[1], b[4], b[5], -b[3], -b[2]), 1e-4), "glb bounds %s vs stl %s" % (gb, b))
# The side of the normals: the signed volume of the triangles (winding) and the vertex normals
# against the face normals. Outward: positive volume; inward: negative, normals re-wound too.
pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
tri = vtk_to_numpy(g.GetPolys().GetConnectivityArray()).reshape(-1, 3)
a, b_, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
cross = ((b_ - a)[:, [1, 2, 0]] * (c - a)[:, [2, 0, 1]] - (b_ - a)[:, [2, 0, 1]] * (c - a)[:, [1, 2, 0]])
signed = float((a * cross).sum()) / 6.0
want = 1 if normals == "outward" else -1
check(signed * want > 0 and abs(abs(signed) - mesh["volume_m3"]) <= 1e-3 * mesh["volume_m3"],
      "glb signed volume %g for %s normals (report %g)" % (signed, normals, mesh["volume_m3"]))
vn = vtk_to_numpy(g.GetPointData().GetNormals()).astype(float)
agree = float((vn[tri[:, 0]] * cross).sum(axis=1).__gt__(0).mean())
check(agree > 0.95, "glb vertex normals agree with the winding for %.3f of triangles" % agree)

# --- state.vti: every grid, x fastest, metres ---
img = vtk_read(vtk.vtkXMLImageDataReader, out + "/state.vti")
check(img.GetDimensions() == (nx + 1, ny + 1, nz + 1), "vti dims %s" % (img.GetDimensions(),))
check(near(img.GetSpacing(), (h, h, h), 1e-12), "vti spacing %s" % (img.GetSpacing(),))
cd = img.GetCellData()
arrays = sorted(cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays()))
check(arrays == sorted(["porosity", "porosity0", "flags", "zone", "pressure", "flow", "water", "cave"]), "vti arrays %s" % arrays)
cave = vtk_to_numpy(cd.GetArray("cave"))
check(int(cave.sum()) == rep["morphometry"]["cave_voxels"], "vti cave voxels %d vs report %d" % (cave.sum(), rep["morphometry"]["cave_voxels"]))
fd = img.GetFieldData()
check(fd.GetAbstractArray("length_unit").GetValue(0) == "m", "vti length unit")

# --- skeleton.vtp: the skeleton's nodes and edges ---
p = vtk_read(vtk.vtkXMLPolyDataReader, out + "/skeleton.vtp")
check(p.GetNumberOfPoints() == skel["nodes"], "vtp points %d vs %d" % (p.GetNumberOfPoints(), skel["nodes"]))
segs = sum(p.GetCell(i).GetNumberOfPoints() - 1 for i in range(p.GetNumberOfCells()))
check(segs == skel["edges"], "vtp segments %d vs edges %d" % (segs, skel["edges"]))
check(inside(p.GetBounds(), 0), "vtp bounds %s" % (p.GetBounds(),))
length = float(vtk_to_numpy(p.GetCellData().GetArray("length_m")).sum())
check(abs(length - rep["morphometry"]["length_m"]) <= 1e-6 * length, "vtp length %g vs %g" % (length, rep["morphometry"]["length_m"]))


# --- cave.svx through cavern, cave.th through therion: one station per skeleton node ---
for dump in (svx_dump, th_dump):
    pos = stations(dump)
    check(len(pos) == skel["nodes"], "%s stations %d vs nodes %d" % (dump, len(pos), skel["nodes"]))
    legs, sl, at = 0, 0.0, None  # dump3d: MOVE x y z starts a line, LINE x y z [survey] is one leg
    for line in open(dump):
        if line.startswith(("MOVE ", "LINE ")):
            xyz = [float(v) for v in line.split()[1:4]]
            if line.startswith("LINE "):
                legs += 1
                sl += math.dist(at, xyz)
            at = xyz
    check(legs == skel["edges"], "%s legs %d vs edges %d" % (dump, legs, skel["edges"]))
    check(all(inside((x, x, y, y, z, z), 0.01) for x, y, z in pos.values()), "%s stations outside the block" % dump)
    check(abs(sl - rep["morphometry"]["length_m"]) <= 0.01 * sl, "%s surveyed length %g vs %g" % (dump, sl, rep["morphometry"]["length_m"]))

# --- GOCAD (no Debian reader; a plain parse) ---
ts = open(out + "/cave.ts").read().split("\n")
check(ts[0] == "GOCAD TSurf 1", "ts header")
check(len([l for l in ts if l.startswith("TRGL ")]) == mesh["faces"], "ts triangles")
check(len([l for l in ts if l.startswith("VRTX ")]) == mesh["vertices"], "ts vertices")
check('AXIS_UNIT "m" "m" "m"' in ts, "ts units")
pl = open(out + "/skeleton.pl").read().split("\n")
check(len([l for l in pl if l.startswith("PVRTX ")]) >= skel["nodes"], "pl vertices")
check(len([l for l in pl if l.startswith("SEG ")]) == skel["edges"], "pl segments")

# --- CSV ---
rows = list(csv.DictReader(open(out + "/history.csv")))
check(len(rows) == rep["stage2"]["iterations"], "history.csv rows %d" % len(rows))
check(abs(sum(float(r["injected"]) for r in rows) - rep["stage2"]["water_injected"]) <= 1e-9 * max(1, rep["stage2"]["water_injected"]), "history.csv injected")
rows = list(csv.DictReader(open(out + "/branches.csv")))
check(len(rows) >= 1, "branches.csv rows")
check(abs(sum(float(r["length_m"]) for r in rows) - rep["morphometry"]["length_m"]) <= 1e-6 * rep["morphometry"]["length_m"], "branches.csv length")

# --- cave.vdb: pyopenvdb reads every grid; `cave` is a level set in metres ---
grids, meta = pyopenvdb.readAll(out + "/cave.vdb")
by = {gr.name: gr for gr in grids}
check(sorted(by) == ["cave", "flags", "flow", "porosity", "porosity0", "pressure", "water", "zone"], "vdb grids %s" % sorted(by))
check(by["cave"].gridClass == "level set" and by["cave"].metadata["unit"] == "m", "vdb cave level set")
check(abs(by["porosity"].transform.voxelSize()[0] - h) < 1e-12, "vdb voxel size")

finish("FAILED (%s):" % out, "%s: %d export files read back" % (out, len(files)))
