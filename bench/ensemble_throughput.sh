#!/usr/bin/env bash
# Members per hour of `cavesim ensemble` on this machine: the fig10 scenario (full outputs: mesh,
# pictures, default formats), N members, run locally (all cores, members in parallel) and under
# `mpirun -n 2` (one thread and one member at a time per rank). Prints one line per repetition;
# quote the medians (bench/README.md).
#   bash bench/ensemble_throughput.sh [MEMBERS=8] [REPS=3] [CAVESIM=build/cavesim]
set -euo pipefail
MEMBERS=${1:-8} REPS=${2:-3} CAVESIM=$(realpath "${3:-build/cavesim}")
SCEN=$(realpath scenarios/fig10.toml)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
MPIRUN=(mpirun -n 2 --oversubscribe)
[ "$(id -u)" -eq 0 ] && MPIRUN+=(--allow-run-as-root)
rate() { python3 -c "import sys; print('%.0f' % ($MEMBERS * 3600.0 / float(sys.argv[1])))" "$1"; }
for ((r = 1; r <= REPS; r++)); do
  t0=$(date +%s.%N)
  "$CAVESIM" ensemble "$SCEN" --members "$MEMBERS" --out "$WORK/local$r" 2>/dev/null >/dev/null
  t1=$(date +%s.%N)
  "${MPIRUN[@]}" "$CAVESIM" ensemble "$SCEN" --members "$MEMBERS" --out "$WORK/mpi$r" -j 1 2>/dev/null >/dev/null
  t2=$(date +%s.%N)
  l=$(python3 -c "print($t1 - $t0)") m=$(python3 -c "print($t2 - $t1)")
  same=yes
  for ((i = 0; i < MEMBERS; i++)); do
    f=$(printf 'members/m%04d.json' "$i")
    python3 -c "import json,sys; a,b=(json.load(open(p))['checksum'] for p in sys.argv[1:]); sys.exit(a!=b)" \
      "$WORK/local$r/$f" "$WORK/mpi$r/$f" || same=no
  done
  echo "rep $r: local $(printf '%.1f' "$l") s = $(rate "$l") members/h; mpirun -n 2: $(printf '%.1f' "$m") s = $(rate "$m") members/h; identical members: $same"
done
