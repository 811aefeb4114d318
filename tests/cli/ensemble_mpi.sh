# `mpirun -n 2 cavesim ensemble` spreads the members over two ranks and writes, member by member,
# what the local ensemble writes. Skipped (exit 77) without mpirun or in a build without MPI.
. "$(dirname "$0")/lib.sh"
command -v mpirun >/dev/null || { echo "skip: no mpirun"; exit 77; }
MPIRUN=(mpirun -n 2 --oversubscribe)
[ "$(id -u)" -eq 0 ] && MPIRUN+=(--allow-run-as-root)
tiny_ensemble_scenario > t.toml

expect_exit 0 "local ensemble of 4" -- "$CAVESIM" ensemble t.toml --members 4 --out local -j 2
"${MPIRUN[@]}" "$CAVESIM" ensemble t.toml --members 4 --out mpi -j 1 >stdout.txt 2>stderr.txt
rc=$?
if [ $rc -eq 2 ] && grep -q "built without MPI" stderr.txt; then echo "skip: cavesim built without MPI"; exit 77; fi
[ $rc -eq 0 ] && pass "mpirun -n 2 ensemble (exit 0)" || fail "mpirun ensemble: exit $rc: $(cat stderr.txt)"
grep -q "^\[1\] m0001: ok" stderr.txt && grep -q "^\[0\] m0002: ok" stderr.txt \
  && pass "members spread over the ranks (odd on rank 1, even on rank 0)" || fail "members not spread: $(cat stderr.txt)"
[ "$(grep -c '^wrote ' stdout.txt)" -eq 1 ] && pass "one summary" || fail "summary written $(grep -c '^wrote ' stdout.txt) times"
same_members local mpi 4 && pass "2-rank members equal the local ones (checksums and files)" || fail "members differ"
cmp -s local/probability.vti mpi/probability.vti && pass "same probability grid" || fail "probability grids differ"
cmp -s local/ensemble.json mpi/ensemble.json && pass "same ensemble.json" || fail "ensemble.json differs"
# Resume under MPI: nothing left to run.
"${MPIRUN[@]}" "$CAVESIM" ensemble t.toml --members 4 --out mpi -j 1 >stdout.txt 2>stderr.txt
[ "$(grep -c 'already finished, kept' stderr.txt)" -eq 2 ] && pass "both ranks resume" || fail "resume: $(cat stderr.txt)"
finish
