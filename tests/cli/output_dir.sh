# A non-empty output directory is refused without --force and left untouched; --force replaces it.
. "$(dirname "$0")/lib.sh"
small_scenario > s.toml
mkdir -p taken && echo keep > taken/mine.txt
expect_exit 2 "non-empty --out refused" -- "$CAVESIM" run s.toml --out taken
stderr_has "--force"
[ "$(cat taken/mine.txt)" = keep ] && [ "$(ls taken)" = mine.txt ] && pass "refused dir untouched" || fail "taken/ changed"
expect_exit 0 "--force replaces" -- "$CAVESIM" run s.toml --out taken --force -q
[ ! -e taken/mine.txt ] && [ -f taken/report.json ] && pass "replaced" || fail "not replaced: $(ls taken)"
mkdir empty
expect_exit 0 "empty --out accepted" -- "$CAVESIM" run s.toml --out empty -q
[ -f empty/report.json ] && pass "written into empty dir" || fail "empty/ lacks report.json"
[ -z "$(ls -A | grep '^\.')" ] && pass "no staging leftovers" || fail "staging leftovers: $(ls -A)"
# A staging directory left by a killed run (its PID no longer exists) is removed by the next run
# into the same place; one of a live process is left alone.
mkdir -p .again.partial-999999999 .again.partial-1 && echo half > .again.partial-999999999/report.json
expect_exit 0 "run next to stale staging dirs" -- "$CAVESIM" run s.toml --out again -q
[ ! -e .again.partial-999999999 ] && pass "stale staging dir removed" || fail "stale staging dir kept"
[ -d .again.partial-1 ] && pass "live process's staging dir kept" || fail "removed a live staging dir"
rm -rf .again.partial-1
finish
