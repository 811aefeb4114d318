#!/usr/bin/env python3
"""Writes the Figure 10 scenario scaled by k (bench/README.md, issue 13): every position, radius,
sink box, noise scale and the iteration count times k. With --pad-to NX NY NZ the scaled features
sit in the corner of a block of that size (the padding test).

usage: fig10_scaled.py K [--pad-to NX NY NZ] > scenario.toml
"""
import re
import sys

SRC = """name = "fig10_k{k}"
seed = 7
[domain]
size = [{nx}, {ny}, {nz}]
voxel_size = 1.0
[rock]
porosity = 0.05
noise = {{ amplitude = 0.02, scale = {noise} }}
[[rock.sphere]]
center = [{s1}]
radius = {r1}
core_porosity = 0.005
[[rock.sphere]]
center = [{s2}]
radius = {r2}
core_porosity = 0.005
[[rock.sphere]]
center = [{s3}]
radius = {r2}
core_porosity = 0.005
[[source]]
at = [{a1}]
pressure = 1.0
[[source]]
at = [{a2}]
pressure = 1.0
[[source]]
at = [{a3}]
pressure = 1.0
[[sink]]
box = [[{b0}], [{b1}]]
[stage1]
protosinks = "boundary"
[stage2]
iterations = {it}
p_rate = 0.50
p_rate_channel = 0.001
w0 = 0.15
wa = 0.25
m = 1.0
"""


def main():
    k = int(sys.argv[1])
    size = [60 * k, 60 * k, 20 * k]
    if "--pad-to" in sys.argv:
        i = sys.argv.index("--pad-to")
        size = [int(x) for x in sys.argv[i + 1:i + 4]]
    p = lambda *xs: ", ".join(str(x * k) for x in xs)
    print(SRC.format(k=k, nx=size[0], ny=size[1], nz=size[2], noise=8.0 * k,
                     s1=p(24, 30, 9), r1=7 * k, s2=p(40, 18, 12), r2=6 * k, s3=p(38, 44, 7),
                     a1=p(6, 10, 16), a2=p(8, 48, 14), a3=p(26, 52, 17),
                     b0=p(54, 26, 1), b1=", ".join(str(x) for x in (54 * k + 4 * k, 26 * k + 8 * k, 1 * k + 3 * k)),
                     it=240 * k))


main()
