# Every kind of bad input: exit code 2, one clear message, no output directory created.
. "$(dirname "$0")/lib.sh"
small_scenario > good.toml

sed 's/^porosity = 0.05/porosty = 0.05/' good.toml > misspelt.toml
expect_exit 2 "misspelt key" -- "$CAVESIM" run misspelt.toml --out o1
stderr_has "misspelt.toml:6: unknown key 'rock.porosty'"
[ ! -e o1 ] && pass "no output dir for a bad scenario" || fail "o1 was created"

sed 's/^iterations = 30/iterations = "many"/' good.toml > wrongtype.toml
expect_exit 2 "wrong type" -- "$CAVESIM" run wrongtype.toml --out o2
stderr_has "stage2.iterations"
stderr_has "whole number"

sed 's/^p_rate = 0.05/p_rate = -3/' good.toml > range.toml
expect_exit 2 "out of range" -- "$CAVESIM" validate range.toml
stderr_has "stage2.p_rate' = -3"

sed 's/^at = \[4, 0, 11\]/at = [4, 0, 12]/' good.toml > outside.toml
expect_exit 2 "source outside" -- "$CAVESIM" run outside.toml --out o3
stderr_has "inside the domain"

sed 's/^at = \[4, 0, 11\]/at = [15, 0, 3]/' good.toml > overlap.toml
expect_exit 2 "source overlaps sink" -- "$CAVESIM" validate overlap.toml
stderr_has "overlaps"

grep -v -e '^\[\[sink\]\]' -e '^box' good.toml > nosink.toml
expect_exit 2 "stage 2 without sinks" -- "$CAVESIM" run nosink.toml --out o4
stderr_has "stage 2 needs at least one [[sink]]"

printf 'name = "x"\n[domain\n' > malformed.toml
expect_exit 2 "malformed TOML" -- "$CAVESIM" validate malformed.toml
stderr_has "malformed.toml:2"

expect_exit 2 "missing file" -- "$CAVESIM" run does-not-exist.toml --out o5
stderr_has "does-not-exist.toml"

expect_exit 2 "bad option value" -- "$CAVESIM" run good.toml --threads 0 --out o6
expect_exit 2 "unknown option" -- "$CAVESIM" run good.toml --frobnicate
expect_exit 2 "no subcommand" -- "$CAVESIM"
for d in o1 o2 o3 o4 o5 o6; do [ -e "$d" ] && fail "$d exists after a refused run"; done
[ -z "$(ls -A | grep '^\.')" ] && pass "no staging leftovers" || fail "staging leftovers: $(ls -A)"
expect_exit 0 "--help" -- "$CAVESIM" --help
expect_exit 0 "--version" -- "$CAVESIM" --version
grep -q "cavesim 0" stdout.txt && pass "version printed" || fail "version: $(cat stdout.txt)"
finish
