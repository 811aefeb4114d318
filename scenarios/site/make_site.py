#!/usr/bin/python3
"""Writes the synthetic site of scenarios/site/site.toml: a limestone plateau with three closed
depressions (sinkholes) and a valley cut into its east side (a spring on its floor), in UTM zone 33N
(EPSG:32633, metres).

    /usr/bin/python3 scenarios/site/make_site.py [FOLDER]     # default: this script's folder

Files (all in the same CRS, x east, y north, z elevation in metres):
  terrain.tif            DEM, 5 m pixels, Float32 GeoTIFF
  horizon.tif            an inception horizon dipping gently east, Float32 GeoTIFF
  sinkholes.csv          x,y,name,pressure: the bottoms of the three depressions (on the surface)
  springs.csv            x,y,name: the spring on the valley floor (on the surface)
  base_of_limestone.xyz  x y z points of the base of the limestone (dips east)
  water_table.xyz        x y z points of the water table

Needs GDAL's Python bindings (Debian: python3-gdal). The same files every time.
"""
import math
import os
import struct
import sys

from osgeo import gdal, osr

X0, Y0 = 500000.0, 4100000.0  # the block's low corner (site.toml [site] origin)
PX = 5.0                       # pixel size, m
# The rasters reach 10 m beyond the 300 m x 200 m block on every side.
RX0, RY1, W, H = X0 - 10.0, Y0 + 210.0, 64, 44
DEPRESSIONS = [("D1", 60.0, 50.0, 1.0), ("D2", 110.0, 150.0, 0.8), ("D3", 170.0, 90.0, 0.6)]


def valley_centre(v):
    """x of the valley's thalweg (block metres) at y = v."""
    return 255.0 + 10.0 * math.sin(v / 60.0)


def terrain(u, v):
    """Elevation (m) at block coordinates (u, v): a plateau at 372 m, the valley, the depressions."""
    z = 372.0 - 0.01 * u
    floor = 34.0 + 4.0 * (1.0 - v / 200.0)  # the valley deepens to the south
    z -= floor * math.exp(-(((u - valley_centre(v)) / 28.0) ** 2))
    for _, cu, cv, _ in DEPRESSIONS:
        z -= 7.0 * math.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * 12.0**2))
    return z


def horizon(u, v):
    return 352.0 - 0.04 * u + 1.5 * math.sin(v / 40.0)


def write_tiff(path, f):
    drv = gdal.GetDriverByName("GTiff")
    ds = drv.Create(path, W, H, 1, gdal.GDT_Float32)
    ds.SetGeoTransform((RX0, PX, 0.0, RY1, 0.0, -PX))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(32633)
    ds.SetProjection(srs.ExportToWkt())
    values = []
    for r in range(H):
        for c in range(W):
            x, y = RX0 + (c + 0.5) * PX, RY1 - (r + 0.5) * PX
            values.append(f(x - X0, y - Y0))
    ds.GetRasterBand(1).WriteRaster(0, 0, W, H, struct.pack("<%df" % len(values), *values))
    ds.FlushCache()
    ds = None


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    gdal.UseExceptions()
    write_tiff(os.path.join(out, "terrain.tif"), terrain)
    write_tiff(os.path.join(out, "horizon.tif"), horizon)
    with open(os.path.join(out, "sinkholes.csv"), "w") as f:
        f.write("x,y,name,pressure\n")
        for name, cu, cv, p in DEPRESSIONS:
            f.write("%.1f,%.1f,%s,%.2f\n" % (X0 + cu, Y0 + cv, name, p))
    with open(os.path.join(out, "springs.csv"), "w") as f:
        f.write("x,y,name\n%.1f,%.1f,Spring\n" % (X0 + valley_centre(25.0), Y0 + 25.0))
    with open(os.path.join(out, "base_of_limestone.xyz"), "w") as f:
        f.write("x y z\n")
        for u in range(0, 301, 75):
            for v in range(0, 201, 50):
                f.write("%.1f %.1f %.2f\n" % (X0 + u, Y0 + v, 318.0 - 0.02 * u))
    with open(os.path.join(out, "water_table.xyz"), "w") as f:
        f.write("x y z\n")
        for u in range(0, 301, 100):
            for v in range(0, 201, 100):
                f.write("%.1f %.1f %.2f\n" % (X0 + u, Y0 + v, 346.0 - 0.025 * u))
    print("wrote the site files to " + out)


if __name__ == "__main__":
    main()
