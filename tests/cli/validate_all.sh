# Every shipped scenario validates.
. "$(dirname "$0")/lib.sh"
for f in "$SRC"/scenarios/*.toml; do
  expect_exit 0 "validate $(basename "$f")" -- "$CAVESIM" validate "$f"
done
finish
