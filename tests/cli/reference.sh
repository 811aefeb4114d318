# `cavesim reference` is docs/scenario-format.md exactly; `cavesim reference --example` is a complete
# scenario that validates and names every key of the reference, and the scenario fuzzer's seed.
. "$(dirname "$0")/lib.sh"
expect_exit 0 "reference" -- "$CAVESIM" reference
if cmp -s stdout.txt "$SRC/docs/scenario-format.md"; then pass "docs/scenario-format.md is the output of cavesim reference"
else fail "docs/scenario-format.md differs from 'cavesim reference' (regenerate: cavesim reference > docs/scenario-format.md): $(diff stdout.txt "$SRC/docs/scenario-format.md" | head -5)"; fi
cp stdout.txt reference.md
expect_exit 0 "reference --example" -- "$CAVESIM" reference --example
cp stdout.txt example.toml
expect_exit 0 "the example validates" -- "$CAVESIM" validate example.toml
# The scenario fuzzer starts from the example: its seed is the current one.
if cmp -s example.toml "$SRC/fuzz/corpus/scenario/example.toml"; then pass "fuzz/corpus/scenario/example.toml is the example"
else fail "fuzz/corpus/scenario/example.toml differs from 'cavesim reference --example' (regenerate it)"; fi
# Every key of the reference's tables is set in the example (commented out only for `box`).
missing=0
for key in $(grep -o '^| `[a-z_0-9]*`' reference.md | tr -d '|` ' | sort -u); do
  grep -qE "^#? ?$key = " example.toml || { fail "key '$key' missing in the example"; missing=1; }
done
[ "$missing" -eq 0 ] && pass "the example sets every key"
finish
