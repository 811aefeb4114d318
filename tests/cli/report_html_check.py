#!/usr/bin/python3
"""Opens a run's report.html in headless Chromium through the DevTools protocol and checks it:
no console errors, warnings of level error or uncaught exceptions, the <model-viewer> has loaded
cave.glb, and the screenshot of its canvas is not blank (pixel variance). Usage:
report_html_check.py REPORT.html SCREENSHOT.png [--no-viewer]
With --no-viewer the page must have no 3D view and say why (no viewer script). Exit 0 when every
check passes, 1 otherwise (each failure printed), 77 when Chromium or a Python module is missing."""
import base64
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

try:
    import numpy as np
    import websocket
    from PIL import Image
except ImportError as e:  # test-only packages: scripts/test.sh installs them
    print(f"skip: {e}")
    sys.exit(77)

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
if not CHROMIUM:
    print("skip: no chromium")
    sys.exit(77)

page_path, shot_path = os.path.abspath(sys.argv[1]), sys.argv[2]
expect_viewer = "--no-viewer" not in sys.argv[3:]
failures = []

profile = tempfile.mkdtemp(prefix="cavesim-chromium-")
# Software WebGL (SwiftShader) so the check runs on machines without a GPU.
proc = subprocess.Popen(
    [CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
     "--enable-unsafe-swiftshader", "--no-first-run", "--no-default-browser-check", "--remote-debugging-port=0",
     f"--user-data-dir={profile}", "--window-size=1200,1000", "about:blank"],
    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
try:
    port = None
    deadline = time.time() + 60
    while time.time() < deadline and port is None:
        line = proc.stderr.readline()
        m = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
        if m:
            port = int(m.group(1))
    if port is None:
        print("FAIL: chromium did not start its DevTools endpoint")
        sys.exit(1)
    targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list"))
    page = next(t for t in targets if t.get("type") == "page")
    ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=120, suppress_origin=True)
    next_id = [0]
    events = []

    def call(method, **params):
        next_id[0] += 1
        ws.send(json.dumps({"id": next_id[0], "method": method, "params": params}))
        while True:
            msg = json.loads(ws.recv())
            if msg.get("id") == next_id[0]:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            events.append(msg)

    def evaluate(expr):
        r = call("Runtime.evaluate", expression=expr, awaitPromise=True, returnByValue=True)
        return r.get("result", {}).get("value")

    call("Runtime.enable")
    call("Log.enable")
    call("Page.enable")
    call("Page.navigate", url="file://" + page_path)
    # Wait for the document, then for the viewer's model.
    deadline = time.time() + 90
    while time.time() < deadline and evaluate("document.readyState") != "complete":
        time.sleep(0.2)
    has_viewer = evaluate("!!document.querySelector('model-viewer')")
    text = evaluate("document.body.innerText") or ""
    if expect_viewer:
        if not has_viewer:
            failures.append("no <model-viewer> in the page")
        else:
            while time.time() < deadline and not evaluate("document.querySelector('model-viewer').loaded === true"):
                time.sleep(0.25)
            if not evaluate("document.querySelector('model-viewer').loaded === true"):
                failures.append("model-viewer did not load cave.glb within 90 s")
            # A few frames after the load, so that the model is drawn.
            evaluate("new Promise(r => { let n = 0; const f = () => (++n < 30 ? requestAnimationFrame(f) : r(1));"
                     " requestAnimationFrame(f); })")
            time.sleep(1.0)
            rect = evaluate("(() => { const e = document.querySelector('model-viewer'); e.scrollIntoView();"
                            " const r = e.getBoundingClientRect();"
                            " return [r.x + scrollX, r.y + scrollY, r.width, r.height]; })()")
            shot = call("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                        clip={"x": rect[0], "y": rect[1], "width": rect[2], "height": rect[3], "scale": 1})
            png = base64.b64decode(shot["data"])
            with open(shot_path, "wb") as f:
                f.write(png)
            pixels = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.float64)
            variance = float(pixels.var())
            # The fraction of pixels far from the background colour (the most common one).
            flat = pixels.reshape(-1, 3)
            values, counts = np.unique(flat, axis=0, return_counts=True)
            background = values[counts.argmax()]
            drawn = float((np.abs(flat - background).sum(axis=1) > 60).mean())
            print(f"canvas {pixels.shape[1]}x{pixels.shape[0]} px: variance {variance:.1f}, "
                  f"{100 * drawn:.1f} % of pixels away from the background")
            if variance < 100 or drawn < 0.01:
                failures.append(f"the 3D view looks blank (variance {variance:.1f}, drawn {100 * drawn:.2f} %)")
    else:
        if has_viewer:
            failures.append("a <model-viewer> without a viewer script")
        if "No interactive 3D view" not in text:
            failures.append("the page does not say why there is no 3D view")
    for name in ("Parameters", "Timings", "Events", "Pictures"):
        if name not in text:
            failures.append(f"no '{name}' section in the page")
    broken = evaluate("[...document.images].filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src)")
    if broken:
        failures.append(f"pictures that did not load: {broken}")
    # Console errors, errors logged by the browser, uncaught exceptions.
    try:
        while True:
            ws.settimeout(0.5)
            events.append(json.loads(ws.recv()))
    except Exception:
        pass
    for e in events:
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            failures.append("console error: " + " ".join(str(a.get("value", a.get("description", "")))
                                                          for a in p.get("args", [])))
        elif m == "Runtime.exceptionThrown":
            failures.append("uncaught exception: " + json.dumps(p.get("exceptionDetails", {}))[:300])
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            failures.append("browser error: " + p["entry"].get("text", "") + " " + p["entry"].get("url", ""))
    ws.close()
finally:
    proc.terminate()
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
    shutil.rmtree(profile, ignore_errors=True)

for f in failures:
    print("FAIL: " + f)
print("all passed" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
