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
finish
