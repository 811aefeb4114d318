# Stage 2 keeps a finite state on every valid scenario.
# 1. Regression: data/nan_fractures.toml (fracture planes every 8 voxels in x and y, a bedding
#    plane, three 21 x 21 box sources) once stopped at iteration 159 with non-finite water: a voxel
#    left an ulp over full by round-off received nothing, and its acceptance fraction was 0 / 0.
# 2. Property: random valid scenarios (fixed seed per case) with many planes, large box sources and
#    extreme-but-allowed parameters all run, and report.json's stage-2 numbers are finite.
. "$(dirname "$0")/lib.sh"

check_report() {  # check_report DIR: stage-2 numbers finite, nulls only where "none yet" is allowed
  python3 - "$1/report.json" <<'PY'
import json, math, sys
s2 = json.load(open(sys.argv[1]))["stage2"]
def walk(x, where):
    if isinstance(x, dict):
        for k, v in x.items(): walk(v, where + "." + k)
    elif isinstance(x, list):
        for i, v in enumerate(x): walk(v, f"{where}[{i}]")
    elif x is None:
        # none yet: no breakthrough, or no centreline to measure against the protochannels
        assert where in ("stage2.breakthrough_iteration", "stage2.near_protochannels.centreline_share") or \
            where.startswith("stage2.source_connected_iteration["), where
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        assert math.isfinite(x), f"{where} = {x}"
walk(s2, "stage2")
assert len(s2["history"]) == s2["iterations"]
assert s2["water_balance_rel_error"] < 1e-6, s2["water_balance_rel_error"]
PY
}

# 1. The regression scenario, stopped a few iterations after the former crash.
sed 's/^iterations = 240$/iterations = 165/' "$SRC/tests/cli/data/nan_fractures.toml" > nan_fractures.toml
printf '\n[output]\nimages = false\nmesh = false\n' >> nan_fractures.toml
grep -q '^iterations = 165$' nan_fractures.toml && pass "regression scenario shortened" || fail "no iterations key to shorten"
expect_exit 0 "fracture scenario runs past iteration 159" -- "$CAVESIM" run nan_fractures.toml --out nan -q --threads 1
check_report nan && pass "fracture scenario: finite stage-2 report" || fail "fracture scenario: stage-2 report"

# 2. Random valid scenarios.
python3 - <<'PY'
import random

def box_on_face(r, n, face, depth):
    """An inclusive box on one face of the grid n = (nx, ny, nz)."""
    lo, hi = [0, 0, 0], [n[0] - 1, n[1] - 1, n[2] - 1]
    axis, side = {"-x": (0, 0), "+x": (0, 1), "-y": (1, 0), "+y": (1, 1), "-z": (2, 0)}[face]
    for a in range(3):
        if a == axis:
            lo[a] = hi[a] = n[a] - 1 if side else 0
            if side: lo[a] = max(0, n[a] - depth)
            else: hi[a] = min(n[a] - 1, depth - 1)
        elif a == 2:  # sinks stay below the source layers
            lo[a] = r.randint(0, max(0, n[2] - 4)); hi[a] = r.randint(lo[a], n[2] - 3)
        else:
            lo[a] = r.randint(0, n[a] - 1); hi[a] = r.randint(lo[a], n[a] - 1)
    return lo, hi

def scenario(case):
    r = random.Random(1000 + case)
    def pick(typical, extreme):  # an extreme value in about a third of the draws
        return r.choice(extreme) if r.random() < 0.3 else r.choice(typical)
    n = [r.randint(16, 26), 1 if case % 7 == 3 else r.randint(16, 26), r.randint(8, 13)]
    L = [f'name = "prop{case:02d}"', f"seed = {r.randint(0, 2**40)}", "[domain]", f"size = {n}",
         "[rock]", f"porosity = {pick([0.02, 0.05, 0.1], [0.0, 0.001, 0.5, 1.0])}",
         f"noise = {{ amplitude = {r.choice([0.0, 0.01, 0.05, 0.3])}, scale = {r.uniform(1, 10):.3f} }}"]
    for _ in range(r.randint(4, 14)):  # fractures and bedding, axis-aligned or oblique
        axis = r.randrange(3)
        normal = [0, 0, 0]; normal[axis] = 1
        if r.random() < 0.3: normal = [round(r.uniform(-1, 1), 3) for _ in range(3)]; normal[axis] = 1
        point = [r.uniform(0, n[0]), r.uniform(0, n[1]), r.uniform(0, n[2])]
        L += ["[[rock.plane]]", f"point = [{point[0]:.2f}, {point[1]:.2f}, {point[2]:.2f}]", f"normal = {normal}",
              f"thickness = {r.choice([0.5, 1.0, 2.0, 3.0])}", f"porosity = {r.choice([0.1, 0.3, 0.6, 1.0])}",
              f"extent = {r.choice([0, 0, 6])}", f'kind = "{r.choice(["bedding", "fracture"])}"']
    for _ in range(r.randint(0, 2)):
        L += ["[[rock.sphere]]", f"center = [{r.uniform(0, n[0]):.1f}, {r.uniform(0, n[1]):.1f}, {r.uniform(0, n[2]):.1f}]",
              f"radius = {r.uniform(1, 6):.1f}", f"core_porosity = {r.choice([0.0, 0.005])}"]
    # Large box sources in the top two layers, side by side along x.
    ns = r.randint(1, 3)
    for s in range(ns):
        x0 = s * n[0] // ns; x1 = max(x0, (s + 1) * n[0] // ns - 1 - r.randint(0, 2))
        y0 = r.randint(0, n[1] // 3); y1 = r.randint(max(y0, 2 * n[1] // 3 - 1), n[1] - 1)
        k0 = n[2] - r.randint(1, 2)
        L += ["[[source]]", f"box = [[{x0}, {y0}, {k0}], [{x1}, {y1}, {n[2] - 1}]]",
              f"pressure = {r.choice([1.0, 1.0, 0.5, 100.0, 1e-3])}"]
    faces = ["-x", "+x", "-z"] + (["-y", "+y"] if n[1] > 1 else [])
    for face in r.sample(faces, r.randint(1, 2)):
        lo, hi = box_on_face(r, n, face, r.randint(1, 3))
        L += ["[[sink]]", f"box = [{lo}, {hi}]"]
    L += ["[stage1]", f"enabled = {r.choice(['true', 'true', 'false'])}",
          f'protosinks = "{r.choice(["boundary", "clustered"])}"', f"clusters = {r.randint(1, 6)}",
          f'permeability = "{r.choice(["uniform", "porosity"])}"', f"capacity_exponent = {r.choice([0.1, 1.0, 8.0])}",
          f"protosink_share = {r.choice([0.01, 0.5, 1.0])}", f"branch_flow = {r.choice([0.0, 0.02, 0.5, 1.0])}",
          f"resistance_noise = {r.choice([0.0, 0.5, 1.0])}",
          f"protochannel_porosity = {r.choice([0.0, 0.35, 1.0])}"]
    p_rate = 10 ** r.uniform(-3, 3)
    p_ch = pick([p_rate * 0.002, p_rate * 0.02], [p_rate, p_rate * (1 - 1e-9), p_rate * 0.999, p_rate * 1e-12, 1e-30])
    L += ["[stage2]", "iterations = 60", f"p_rate = {p_rate!r}", f"p_rate_channel = {min(p_ch, p_rate)!r}",
          f"w0 = {pick([0.15, 0.5], [0.0, 1.0, 5.0, 10.0])}", f"wa = {pick([0.25, 1.0], [0.0, 10.0, 100.0])}",
          f"m = {pick([0.5, 1.0, 2.0], [0.1, 4.0])}",
          f"pressure_scale = {pick([0], [p_rate * 1e-3, p_rate * 3.0, 1e9])!r}",
          f"channel_threshold = {pick([0.3, 0.5], [1e-6, 0.01, 0.06, 1.0])}",
          f"protochannel_porosity = {pick([0.25], [0.0, 1.0])}",
          f"source_porosity = {pick([0.1, 0.3], [1e-6, 1.0, 1.0])}",
          f'weight = "{r.choice(["proportional", "uniform"])}"', f'blending = "{r.choice(["max", "split"])}"',
          "[output]", "images = false", "mesh = false"]
    return "\n".join(L) + "\n"

import os
for case in range(int(os.environ.get("STAGE2_FINITE_CASES", "24"))):
    open(f"prop{case:02d}.toml", "w").write(scenario(case))
PY
for f in prop*.toml; do
  c=${f%.toml}
  if "$CAVESIM" run "$f" --out "$c" -q --threads 1 >"$c.out" 2>"$c.err"; then
    check_report "$c" >"$c.check" 2>&1 && pass "$c: finite" || fail "$c: report: $(tail -1 "$c.check")"
  else
    fail "$c: exit $?: $(cat "$c.err")"
  fi
done
finish
