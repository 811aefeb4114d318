# report.html: written beside report.md with the 3D viewer copied next to it; opened in headless
# Chromium (tests/cli/report_html_check.py): no console errors, the cave drawn in the 3D view.
# Without the viewer script the page still works and says why. $4: the build's viewer directory.
. "$(dirname "$0")/lib.sh"
VIEWER_DIR=$4
if [ ! -f "$VIEWER_DIR/model-viewer-umd.min.js" ]; then
  echo "skip: no viewer in $VIEWER_DIR (scripts/setup.sh fetches it)"
  exit 77
fi
shared_run fig10
for f in report.html report_files/model-viewer-umd.min.js report_files/model-viewer-LICENSE; do
  [ -s "fig10/$f" ] && pass "$f written" || fail "$f missing"
done
grep -q 'src="data:model/gltf-binary;base64,' fig10/report.html && pass "cave.glb embedded" || fail "cave.glb not embedded"
grep -q '<script src="report_files/model-viewer-umd.min.js">' fig10/report.html && pass "viewer linked" \
  || fail "viewer not linked"
for f in map_plan.png map_extended_elevation.png perspective.png sections.png; do
  grep -q "images/$f" fig10/report.html && pass "$f in the page" || fail "$f not in the page"
done
# Without the viewer (setup not run): no script, a note saying why.
small_scenario > s.toml
export CAVESIM_MODEL_VIEWER_DIR=/nonexistent
expect_exit 0 "run without the viewer" -- "$CAVESIM" run s.toml --out small -q
unset CAVESIM_MODEL_VIEWER_DIR
[ ! -e small/report_files ] && pass "no report_files without a viewer" || fail "report_files without a viewer"
grep -q "No interactive 3D view" small/report.html && pass "page says why" || fail "page does not say why"
grep -q "<script" small/report.html && fail "a script without a viewer" || pass "no script"
# The browser checks.
check() {
  /usr/bin/python3 "$SRC/tests/cli/report_html_check.py" "$@" > check.txt 2>&1
  local rc=$?
  cat check.txt
  if [ "$rc" -eq 77 ]; then echo "skip: $(head -1 check.txt)"; exit 77; fi
  return $rc
}
check fig10/report.html fig10_view.png && pass "fig10 report.html in Chromium" || fail "fig10 report.html in Chromium"
check small/report.html small_view.png --no-viewer && pass "report.html without the viewer in Chromium" \
  || fail "report.html without the viewer in Chromium"
finish
