# The runs that several end-to-end tests read, made once before them (the CTest fixture
# cli_shared_runs; each reader copies what it needs with shared_run, tests/cli/lib.sh): Figure 10 as
# shipped (caves_3d, report_html) and Figure 8, a 2D section, with every export format (exports,
# behaviour_2d).
. "$(dirname "$0")/lib.sh"
expect_exit 0 "fig10 runs" -- "$CAVESIM" run "$SRC/scenarios/fig10.toml" --out fig10 -q
expect_exit 0 "fig08 (2D section) with every format" -- \
  "$CAVESIM" run "$SRC/scenarios/fig08.toml" --out fig08 --formats all -q
finish
