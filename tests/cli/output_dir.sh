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
# A staging directory left by a killed run (its PID no longer exists, untouched for ten minutes) is
# removed by the next run into the same place; one of a live process, a fresh one, a file and a
# symlink of the same name pattern are left alone.
mkdir -p .again.partial-999999999 .again.partial-1 .again.partial-999999998 keepme
echo half > .again.partial-999999999/report.json
touch -d '1 hour ago' .again.partial-999999999 .again.partial-1
echo mine > keepme/file && ln -s keepme .again.partial-999999997 && echo x > .again.old-999999996
expect_exit 0 "run next to stale staging dirs" -- "$CAVESIM" run s.toml --out again -q
[ ! -e .again.partial-999999999 ] && pass "stale staging dir removed" || fail "stale staging dir kept"
[ -d .again.partial-1 ] && pass "live process's staging dir kept" || fail "removed a live staging dir"
[ -d .again.partial-999999998 ] && pass "fresh staging dir kept" || fail "removed a fresh staging dir"
[ -L .again.partial-999999997 ] && [ "$(cat keepme/file)" = mine ] && [ -f .again.old-999999996 ] \
  && pass "symlink, its target and a file left alone" || fail "touched a symlink or file"
rm -rf .again.partial-1 .again.partial-999999998 .again.partial-999999997 .again.old-999999996 keepme
# --out that no directory can replace: a dangling symlink, a symlink loop, a mount point.
ln -s nowhere dangling && ln -s loop2 loop1 && ln -s loop1 loop2
expect_exit 2 "--out a dangling symlink" -- "$CAVESIM" run s.toml --out dangling -q --force
stderr_has "leads nowhere"
expect_exit 2 "--out a symlink loop" -- "$CAVESIM" run s.toml --out loop1 -q --force
mkdir -p msrc mnt
if mount --bind msrc mnt 2>/dev/null; then
  expect_exit 2 "--out a mount point" -- "$CAVESIM" run s.toml --out mnt -q
  stderr_has "mount point"
  expect_exit 0 "--out inside a mount point" -- "$CAVESIM" run s.toml --out mnt/inner -q
  umount mnt
else
  pass "mount point case skipped (no permission to mount here)"
fi
# A symlink inside the --out path that leads back up would make --force replace the folder that
# holds it; names this program never writes (leading zeros) are left alone; parents created for a
# run that then fails are removed again; a 250-byte target name works.
mkdir -p project/sub && echo keep > project/important.txt && ln -s .. project/sub/results
expect_exit 2 "--out through a symlink to a parent" -- "$CAVESIM" run s.toml --out project/sub/results --force -q
stderr_has "itself"
[ "$(cat project/important.txt)" = keep ] && pass "the parent folder survived" || fail "project/ was replaced"
mkdir -p .zero.partial-0999999 && touch -d '1 hour ago' .zero.partial-0999999
expect_exit 0 "run next to a leading-zero name" -- "$CAVESIM" run s.toml --out zero -q
[ -d .zero.partial-0999999 ] && pass "leading-zero name left alone" || fail "removed .zero.partial-0999999"
sed 's/^enabled = false/enabled = true\nmax_graph_voxels = 1/' s.toml > bad.toml
expect_exit 2 "a run that fails after creating parents for --out" -- "$CAVESIM" run bad.toml --out newp/q/x -q
graph_line=$(grep -n '^max_graph_voxels = ' bad.toml | cut -d: -f1)
stderr_has "bad.toml:$graph_line: key 'stage1.max_graph_voxels' = 1: "
[ ! -e newp ] && pass "no parents left behind" || fail "newp/ left behind"
long=$(printf 'a%.0s' $(seq 250))
expect_exit 0 "a 250-byte --out name" -- "$CAVESIM" run s.toml --out "$long" -q
[ -f "$long/report.json" ] && pass "written under the long name" || fail "long name: $(ls)"
# A trailing slash or "/." names the same folder.
expect_exit 0 "--out with a trailing slash" -- "$CAVESIM" run s.toml --out slash/ -q
expect_exit 0 "--out with a trailing /." -- "$CAVESIM" run s.toml --out slash2/. -q
expect_exit 0 "--out with a trailing slash and --force over a run" -- "$CAVESIM" run s.toml --out slash/ --force -q
[ -f slash/report.json ] && [ -f slash2/report.json ] && pass "written into slash/ and slash2/" || fail "trailing slash: $(ls)"
# An empty --out (an unset variable) is refused; it once wrote to out/<name> instead.
expect_exit 2 "an empty --out" -- "$CAVESIM" run s.toml --out "" -q
stderr_has "--out: an empty path"
[ ! -e out ] && pass "nothing written for an empty --out" || fail "out/ was created"
expect_exit 2 "an empty ensemble --out" -- "$CAVESIM" ensemble s.toml --members 1 --out ""
# So is an empty folder to resume (it failed with a raw library message, exit 1).
expect_exit 2 "resume with an empty folder" -- "$CAVESIM" resume ""
stderr_has "dir: an empty path"
# A name longer than the file system allows is refused before the run (it failed when the results
# were moved into place, exit 1, after all the work).
toolong=$(printf 'n%.0s' $(seq 256))
expect_exit 2 "a 256-byte --out name" -- "$CAVESIM" run s.toml --out "sub/$toolong" -q
stderr_has "has 256 bytes; the file system allows at most 255"
[ ! -e sub ] && pass "nothing created for a name too long" || fail "sub/ was created"
finish
