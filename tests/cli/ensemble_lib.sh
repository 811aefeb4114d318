# Helpers of the ensemble tests (sourced after lib.sh).
tiny_ensemble_scenario() {  # 12 × 12 × 6 voxels, both stages, no pictures or meshes: fast members
  cat <<'TOML'
name = "tiny"
seed = 3
[domain]
size = [12, 12, 6]
[rock]
porosity = 0.05
noise = { amplitude = 0.03, scale = 4.0 }
[[source]]
at = [2, 2, 5]
[[sink]]
at = [10, 10, 0]
[stage2]
iterations = 40
[output]
images = false
mesh = false
formats = ["vtk"]
TOML
}
# same_members A B N: the recorded checksums agree and every file but report.json/.md/.html is identical.
same_members() {
  local a=$1 b=$2 n=$3 i m
  for ((i = 0; i < n; i++)); do
    m=$(printf 'm%04d' "$i")
    python3 - "$a/members/$m.json" "$b/members/$m.json" <<'PY' || return 1
import json, sys
x, y = (json.load(open(p)) for p in sys.argv[1:3])
assert x["status"] == y["status"] == "ok" and x["checksum"] == y["checksum"] and x["seed"] == y["seed"], (x, y)
PY
    diff -rq -x report.json -x report.md -x report.html "$a/members/$m" "$b/members/$m" >/dev/null || return 1
  done
}
