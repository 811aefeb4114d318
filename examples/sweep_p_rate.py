#!/usr/bin/env python3
"""Sweep stage 2's pressure rate `p_rate` over a few values on a small scenario and plot how the
cave responds: the breakthrough iteration and the cave's volume against p_rate (a PNG).

With the automatic source pressure (`stage2.pressure_scale = 0`, which scales with p_rate) what
shapes the cave is the ratio of p_rate to the channel rate `p_rate_channel` (0.001 here), so the
sweep spans that ratio from 1.5 to 500 on a logarithmic axis: near 1 channels lose their advantage
over rock and the sources no longer reach the sink in time.

Notebook style: plain cells you can paste into Jupyter. Run from the repository root with the
module importable from the build tree:

    PYTHONPATH=build/python python3 examples/sweep_p_rate.py --out sweep_p_rate.png
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cavesim  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--scenario", default=os.path.join(here, "small.toml"), help="scenario file (default: small.toml)")
parser.add_argument("--values", default="0.0015,0.0025,0.005,0.01,0.05,0.5", help="p_rate values, comma-separated")
parser.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
parser.add_argument("--out", default="sweep_p_rate.png", help="PNG to write")
args = parser.parse_args()

# %% The scenario, and one run per value of p_rate (every other key as in the file).
base = cavesim.Scenario.from_toml(args.scenario)
values = [float(v) for v in args.values.split(",")]
rows = []
for p in values:
    s = base.copy()
    s["stage2.p_rate"] = p
    r = cavesim.run(s, threads=args.threads, mesh=False)
    rep = r.report
    breakthrough = rep["stage2"]["breakthrough_iteration"]
    cave_m3 = float(r.cave_mask.sum()) * r.voxel_size ** 3
    rows.append((p, breakthrough, cave_m3, rep["network"]["sources_connected"]))
    print(f"p_rate {p:<5g}  breakthrough {breakthrough if breakthrough is not None else 'none':>4}  "
          f"cave {cave_m3:7.1f} m³  sources connected {rows[-1][3]}")

# %% Plot: breakthrough iteration (left axis) and cave volume (right axis) against p_rate.
p = np.array([row[0] for row in rows])
bt = np.array([np.nan if row[1] is None else row[1] for row in rows], dtype=float)
vol = np.array([row[2] for row in rows])
fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
ax.semilogx(p, bt, "o-", color="tab:blue", label="breakthrough iteration")
ax.set_xlabel("stage 2 p_rate (pressure per voxel of rock)")
ax.set_ylabel("breakthrough iteration", color="tab:blue")
ax2 = ax.twinx()
ax2.semilogx(p, vol, "s--", color="tab:red", label="cave volume")
ax2.set_ylabel("cave volume (m³)", color="tab:red")
ax.set_title(f"{base.name}: {base.size[0]}×{base.size[1]}×{base.size[2]} voxels, seed {base.seed}")
fig.tight_layout()
fig.savefig(args.out)
print(f"wrote {args.out}")
sys.exit(0 if np.isfinite(bt).any() else 1)  # a sweep where nothing broke through is suspicious
