"""Shared by the export read-back checks (tests/formats/readers.py on the hand-made cave,
tests/cli/exports_check.py on real runs): the failure list, and the files opened with other
programs' readers (VTK's Python module, Survex's dump3d listing)."""
import sys

import vtk

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def near(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def vtk_read(reader_class, path):
    """The output of a VTK file reader (vtk.vtkSTLReader, vtk.vtkXMLImageDataReader, ...) on path."""
    r = reader_class()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def glb_blocks(path):
    """The data sets of a glTF file, through VTK's glTF reader."""
    it = vtk_read(vtk.vtkGLTFReader, path).NewIterator()
    it.InitTraversal()
    blocks = []
    while not it.IsDoneWithTraversal():
        blocks.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return blocks


def stations(dump):
    """Station name -> (x, y, z) of a dump3d listing (NODE x y z [name] ...)."""
    pos = {}
    for line in open(dump):
        if line.startswith("NODE"):
            parts = line.split()
            pos[parts[4].strip("[]")] = tuple(float(v) for v in parts[1:4])
    return pos


def finish(failed_title, passed_line):
    """Prints the failures under failed_title and exits 1, or prints passed_line and exits 0."""
    if failures:
        print(failed_title + "\n  " + "\n  ".join(failures))
        sys.exit(1)
    print(passed_line)
