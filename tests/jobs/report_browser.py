#!/usr/bin/env python3
"""Opens canopy's report.html pages in Debian's headless chromium and checks them.

A small Chrome DevTools Protocol client over --remote-debugging-pipe (file descriptors 3 and
4, NUL-separated JSON): no network, no extra Python package. Used by
run_report_browser_test.sh and, with --screenshot, to make the README's picture.

  report_browser.py [--window WxH] [--screenshot OUT.png] [--fruit-views VIEWS.json] KIND REPORT.html [KIND REPORT.html ...]

KIND is run (a complete mission or map), mission (a complete mission: also the robot, the
labels mapped and the table and metrics against summary.json beside the page; a map's page: its
labels mapped), incomplete (an
interrupted one: the page must say so), experiment, or poisoned (a page whose data strings hold
"<!--<script>": it must open and show them as text); the screenshot is of the first run page.
--shots DIR also writes the pictures of docs/report.md into DIR. --fruit-views: the views that saw
each fruit counted apart (fruit_views.py), which a mission page's column "views" must equal.

Exit 0 when every check passes; otherwise one line per failure and exit 1.
"""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


class Browser:
    def __init__(self, width=1280, height=800):
        exe = shutil.which("chromium") or shutil.which("chromium-browser")
        if not exe:
            raise SystemExit("chromium is not installed (tools/deps.sh installs it)")
        self.profile = tempfile.mkdtemp(prefix="canopy-chromium-")
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()

        def fds():  # the child's fd 3 reads commands, fd 4 writes answers
            os.dup2(to_child_r, 3)
            os.dup2(from_child_w, 4)

        args = [exe, "--headless", "--remote-debugging-pipe", "--no-sandbox", "--no-first-run",
                "--no-default-browser-check", "--disable-extensions", "--disable-background-networking",
                "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--mute-audio",
                f"--window-size={width},{height}", f"--user-data-dir={self.profile}", "about:blank"]
        self.proc = subprocess.Popen(args, preexec_fn=fds, pass_fds=(3, 4),
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_child_r)
        os.close(from_child_w)
        self.buf = b""
        self.next_id = 0
        self.events = []
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            self.call(domain + ".enable", session=True)
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False}, session=True)

    def _read(self, timeout_s):
        end = time.monotonic() + timeout_s
        while b"\0" not in self.buf:
            if time.monotonic() > end:
                raise TimeoutError("chromium did not answer")
            chunk = os.read(self.from_child, 1 << 20)
            if not chunk:
                raise RuntimeError("chromium closed the pipe")
            self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def call(self, method, params=None, session=False, timeout_s=60):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = self.session
        os.write(self.to_child, json.dumps(msg).encode() + b"\0")
        while True:
            m = self._read(timeout_s)
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def evaluate(self, expression):
        r = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                      session=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression}: {r['exceptionDetails'].get('text')}")
        return r["result"].get("value")

    def open(self, path, timeout_s=30):
        start = time.monotonic()
        self.call("Page.navigate", {"url": "file://" + os.path.abspath(path)}, session=True)
        while time.monotonic() - start < timeout_s:
            if self.evaluate("!!(window.canopyReport && window.canopyReport.ready)"):
                return time.monotonic() - start
            time.sleep(0.05)
        raise TimeoutError(f"{path}: the page did not become ready in {timeout_s} s")

    def errors(self):
        """Console errors, uncaught exceptions and failed loads seen so far."""
        out = []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                out.append("exception: " + str(d.get("exception", {}).get("description") or d.get("text")))
            elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append("console." + p["type"] + ": " + " ".join(str(a.get("value", a.get("description"))) for a in p.get("args", [])))
            elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                out.append("log: " + p["entry"].get("text", "") + " " + p["entry"].get("url", ""))
        return out

    def screenshot(self, selector=None):
        """The page as PNG bytes, or only the element `selector` (its bounding box)."""
        params = {"format": "png"}
        if selector:
            r = self.evaluate(f"(() => {{ const r = document.querySelector('{selector}').getBoundingClientRect();"
                              " return [r.x, r.y, r.width, r.height]; })()")
            params["clip"] = {"x": r[0], "y": r[1], "width": r[2], "height": r[3], "scale": 1}
        return base64.b64decode(self.call("Page.captureScreenshot", params, session=True)["data"])

    def close(self):
        try:
            self.call("Browser.close", timeout_s=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


def count_colours(b, png, colours, tol=40):
    """Pixels of the screenshot `png` within `tol` (sum of channel differences) of each colour,
    decoded and counted by the browser itself (no image package needed)."""
    js = """(async () => {
      const img = new Image();
      img.src = 'data:image/png;base64,%s';
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width; c.height = img.height;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data, want = %s, n = want.map(() => 0);
      for (let i = 0; i < d.length; i += 4)
        want.forEach((w, k) => { if (Math.abs(d[i] - w[0]) + Math.abs(d[i + 1] - w[1]) + Math.abs(d[i + 2] - w[2]) <= %d) ++n[k]; });
      return n;
    })()""" % (base64.b64encode(png).decode(), json.dumps(colours), tol)
    return b.evaluate(js)


def rects_overlap(a, b):
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]


def check_readable(b, views):
    """What a user of RViz looks for (issue 48 point 5), on any run page: axes and a scale in
    the 3D view, the orbit hint and a reset that works, labelled ticks on both axes of the
    curves with the cursor's label clear of them, stops and attempts from 1, every metric a
    labelled number, entropy colours apart from the fruits', the note on the phases' times."""
    fails = []
    st = json.loads(b.evaluate("JSON.stringify(canopyReport.state())"))
    names = {l["name"]: l for l in st["labels3d"]}
    if not st["axes"] or not all(f"axis-{a}" in names for a in "xyz"):
        fails.append(f"no axes triad with x, y, z labels in the 3D view: {sorted(names)}")
    scale = [l for n, l in names.items() if n.startswith("scale-")]
    if len(scale) < 2 or not all(l["text"] == "0" or l["text"].endswith(" m") for l in scale):
        fails.append(f"the grid has no labelled scale in metres: {[l['text'] for l in scale]}")
    legend = b.evaluate("document.getElementById('legend').textContent")
    if "grid: 0.5 m" not in legend:
        fails.append(f"the legend does not give the grid's size: '{legend}'")
    hint = b.evaluate("(document.getElementById('orbit-hint') || {}).textContent || ''")
    if not all(w in hint for w in ("orbit", "pan", "zoom")):
        fails.append(f"no orbit hint: '{hint}'")
    home = st["camera"]
    b.evaluate("""(() => { const c = document.querySelector('#view3d canvas');
      for (let i = 0; i < 5; ++i) c.dispatchEvent(new WheelEvent('wheel', { deltaY: -120, clientX: 300, clientY: 300, bubbles: true })); })()""")
    zoomed = json.loads(b.evaluate("JSON.stringify(canopyReport.state())"))["camera"]
    b.evaluate("document.getElementById('reset-view').click()")
    back = json.loads(b.evaluate("JSON.stringify(canopyReport.state())"))["camera"]
    if max(abs(p - q) for p, q in zip(zoomed, home)) < 1e-3:
        fails.append("the wheel did not move the camera (the reset test needs it moved)")
    if max(abs(p - q) for p, q in zip(back, home)) > 1e-6:
        fails.append(f"reset view did not bring the camera back: {back} vs {home}")
    # Curves: ticks with numbers on both axes, increasing; the cursor's label clear of them.
    for svg in ("curve-sc", "curve-h"):
        for axis in ("x", "y"):
            t = b.evaluate(f"[...document.querySelectorAll('#{svg} text.tick-{axis}')].map(e => e.textContent)")
            vals = [float(v) for v in t]
            want = 2 if axis == "x" and views < 5 else 3
            if views > 1 and (len(vals) < want or vals != sorted(vals)):
                fails.append(f"#{svg}: {axis} ticks {t}")
        for k in sorted({0, views // 2, max(0, views - 1)}):
            b.evaluate(f"canopyReport.setView({k})")
            hit = b.evaluate(f"""(() => {{ const box = (e) => {{ const r = e.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; }};
              const c = box(document.querySelector('#{svg} .cursor-label'));
              return [...document.querySelectorAll('#{svg} text.tick-x, #{svg} text.tick-y')].filter(e => {{ const t = box(e);
                return c[0] < t[0] + t[2] && t[0] < c[0] + c[2] && c[1] < t[1] + t[3] && t[1] < c[1] + c[3]; }}).map(e => e.textContent); }})()""")
            if hit:
                fails.append(f"#{svg} at view {k + 1}: the cursor's label overlaps the ticks {hit}")
    # Stops and attempts from 1, as the log counts them.
    b.evaluate("canopyReport.setView(0)")
    info = b.evaluate("document.getElementById('view-info').textContent")
    stops = b.evaluate("(JSON.parse(document.getElementById('canopy-data').textContent).stops || []).length")
    if views and stops:
        m = re.match(r"stop (\d+) of (\d+), .*attempt (\d+);", info)
        if not m or m.group(1) != "1" or int(m.group(2)) != stops or int(m.group(3)) < 1:
            fails.append(f"the first view's stop and attempt are not counted from 1: '{info}'")
    # Every metric a labelled number.
    rows = b.evaluate("[...document.querySelectorAll('#metrics tr')].map(r => [r.dataset.metric, r.cells[0].textContent, r.cells[1].textContent])")
    bad = [r for r in rows if not r[1] or not re.fullmatch(r"-?\d+(\.\d+)?", r[2])]
    if not rows or bad:
        fails.append(f"metrics not each a labelled number: {bad or 'none shown'}")
    # Occupancy and entropy colours apart from the true fruits' colours.
    col = b.evaluate("canopyReport.colours()")
    for level in col["entropy"] + col["occupancy"]:
        for name, f in col["fruits"].items():
            if sum(abs(a - c) for a, c in zip(level, f)) < 150:
                fails.append(f"entropy/occupancy colour {level} is close to the {name} fruits' {f}")
    if len({tuple(c) for c in col["entropy"]}) != 8:
        fails.append(f"the 8 entropy levels do not have 8 colours: {col['entropy']}")
    wall = json.loads(b.evaluate("document.getElementById('canopy-wall').textContent"))
    if "phases_s" in wall and sum(wall["phases_s"].values()) > 1.01 * wall.get("wall_time_s", 1e9):
        note = b.evaluate("(document.getElementById('phase-note') || {}).textContent || ''")
        if "two threads" not in note:
            fails.append("the phases add up to more than the wall time and nothing says why")
    b.evaluate(f"canopyReport.setView({max(0, views - 1)})")
    return fails


def count_changed(b, png_a, png_b, tol=30):
    """Pixels that differ by more than `tol` (sum over RGB) between two screenshots of one size."""
    js = """(async () => {
      const load = async (b64) => { const i = new Image(); i.src = 'data:image/png;base64,' + b64; await i.decode();
        const c = document.createElement('canvas'); c.width = i.width; c.height = i.height;
        const g = c.getContext('2d'); g.drawImage(i, 0, 0); return g.getImageData(0, 0, c.width, c.height).data; };
      const a = await load('%s'), b = await load('%s');
      let n = 0;
      for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > %d) ++n;
      return n;
    })()""" % (base64.b64encode(png_a).decode(), base64.b64encode(png_b).decode(), tol)
    return b.evaluate(js)


def check_robot_shapes(b, robot, views, ok):
    """The robot drawn as its URDF's shapes (issue 48): every shape of data.robot.shapes drawn at
    the first, middle and last view, the camera's box within 2 cm of the view's camera, the
    shapes moving between the views, and the robot covering pixels of the 3D view (shown against
    hidden)."""
    fails = []
    want = sum(len(l) for l in robot.get("shapes", []))
    if not want:
        return ["the page's robot has no shapes (the URDF's geometry)"]
    at = []
    for k in sorted({0, len(ok) // 2, len(ok) - 1}):
        b.evaluate(f"canopyReport.setView({k})")
        shapes = json.loads(b.evaluate("JSON.stringify(canopyReport.state().robotShapes)")) or []
        cam = [views[c][ok[k]] for c in ("reached_x", "reached_y", "reached_z")]
        boxes = [s["at"] for s in shapes if s["type"] == "box"]
        d = min((sum((a - c) ** 2 for a, c in zip(p, cam)) ** 0.5 for p in boxes), default=float("inf"))
        if len(shapes) != want or d > 0.02:
            fails.append(f"view {k + 1}: {len(shapes)} robot shapes drawn of {want}, the nearest box {d:.3f} m from the camera")
        at.append(shapes)
    if len(at) > 1 and at[0] == at[-1]:
        fails.append("the robot's shapes do not move between the first and the last view")
    shown = b.screenshot("#view3d canvas")
    b.evaluate("(() => { const c = document.getElementById('show-robot'); c.checked = false; c.dispatchEvent(new Event('change')); })()")
    time.sleep(0.3)  # the draw waits for the next animation frame
    hidden = b.screenshot("#view3d canvas")
    b.evaluate("(() => { const c = document.getElementById('show-robot'); c.checked = true; c.dispatchEvent(new Event('change')); })()")
    n = count_changed(b, shown, hidden)
    if n < 200:
        fails.append(f"the robot's shapes cover {n} pixels of the 3D view at the last view")
    else:
        print(f"robot: {want} shapes, {n} pixels of the 3D view at the last view")
    return fails


def check_mapped(b):
    """The thumbnail of the labels mapped (after segmentation and noise) is shown beside the truth."""
    mapped = b.evaluate("getComputedStyle(document.getElementById('thumb-mapped')).backgroundImage")
    if "report_mapped_" not in mapped or b.evaluate("document.getElementById('fig-mapped').style.display") == "none":
        return [f"no thumbnail of the labels mapped: '{mapped}'"]
    return []


def check_mission(b, path, fruit_views=None):
    """A complete mission's page against its summary.json: one fruit row per true fruit,
    sortable; detection F1, precision and recall as in the summary; the robot drawn at each view
    with a link at the camera; the labels mapped beside the true labels."""
    fails = []
    summary = json.load(open(os.path.join(os.path.dirname(path), "summary.json")))
    fin = summary["final"]
    data = json.loads(b.evaluate("document.getElementById('canopy-data').textContent"))
    rows = b.evaluate("[...document.querySelectorAll('#fruit-table tr[data-fruit]')].map(r => r.dataset.fruit)")
    if len(rows) != fin["target_fruits"] or len(set(rows)) != len(rows):
        fails.append(f"{len(rows)} fruit rows ({len(set(rows))} distinct) for {fin['target_fruits']} true fruits")
    matched = sum(1 for f in data["fruits"] if "centre_error_m" in f)
    if matched != fin["detection"]["matched"]:
        fails.append(f"{matched} fruits with errors in the table, the summary matched {fin['detection']['matched']}")
    cov = {str(f["id"]): f["cov"] for f in data["fruits"]}
    for order, name in ((lambda v: v == sorted(v, reverse=True), "descending"), (lambda v: v == sorted(v), "ascending")):
        b.evaluate("document.querySelector('#fruit-table th[data-sort=cov]').click()")
        got = [cov[i] for i in b.evaluate("canopyReport.fruitTable.order()")]
        if not order(got):
            fails.append(f"a click on SC did not sort the fruits {name}: {got[:8]}...")
    head = b.evaluate("[...document.querySelectorAll('#fruit-table th')].map(h => h.dataset.sort)")
    cells = {key: dict(b.evaluate(f"[...document.querySelectorAll('#fruit-table tr[data-fruit]')].map(r => [r.dataset.fruit, r.cells[{head.index(key)}].textContent])"))
             for key in ("views", "raised") if key in head}
    if "views" not in cells or "raised" not in cells:
        fails.append(f"the fruit table has no 'views' or 'raised' column: {head}")
    else:
        if not any(v not in ("0", "–") for v in cells["raised"].values()):
            fails.append(f"no fruit has views that raised its SC: {list(cells['raised'].values())[:8]}")
        if fruit_views is not None:  # the views that saw each fruit, counted apart (fruit_views.py)
            want = {i: str(fruit_views["views"].get(i, 0)) for i in cells["views"]}
            if cells["views"] != want:
                fails.append(f"the views that saw each fruit differ from the count of the exported frames: page "
                             f"{cells['views']}, frames {want}")
            elif fruit_views["frames"] != b.evaluate("canopyReport.views"):
                fails.append(f"{fruit_views['frames']} exported frames for {b.evaluate('canopyReport.views')} views")
            else:
                print(f"{path}: views that saw each fruit as counted from the exported frames: {cells['views']}")
    for key in ("precision", "recall", "f1"):
        shown = b.evaluate(f"(document.querySelector('#metrics tr[data-metric=detection_{key}] td') || {{}}).textContent")
        if shown != f"{fin['detection'][key]:.3f}":
            fails.append(f"detection {key}: the page shows {shown}, summary.json {fin['detection'][key]}")
    # The robot: a link within 2 cm of the camera pose of each view it is shown at, and moving.
    robot = data.get("robot")
    if not robot:
        fails.append("the page has no robot")
    else:
        views = data["views"]
        ok = [i for i, s in enumerate(views["success"]) if s]
        at = []
        for k in sorted({0, len(ok) // 2, len(ok) - 1}):
            b.evaluate(f"canopyReport.setView({k})")
            joints = json.loads(b.evaluate("JSON.stringify(canopyReport.state().robot)"))
            cam = [views[c][ok[k]] for c in ("reached_x", "reached_y", "reached_z")]
            d = min(sum((a - c) ** 2 for a, c in zip(j, cam)) ** 0.5 for j in joints)
            if len(joints) != len(robot["links"]) or d > 0.02:
                fails.append(f"view {k + 1}: the robot's nearest link is {d:.3f} m from the camera ({len(joints)} links drawn)")
            at.append(joints)
        if len(at) > 1 and at[0] == at[-1]:
            fails.append("the robot does not move between the first and the last view")
        fails += check_robot_shapes(b, robot, views, ok)
    fails += check_mapped(b)
    return fails


def check_run(b, path, incomplete, shot, mission=False, shots=None, fruit_views=None):
    fails = []
    load_s = b.open(path)
    last = b.evaluate("JSON.stringify(canopyReport.state())")
    last = json.loads(last)
    if not last["webgl"]:
        fails.append("no WebGL context: the 3D view is off")
    if shot:
        with open(shot, "wb") as f:
            f.write(b.screenshot())
    png = b.screenshot("#view3d canvas")  # the 3D view alone: the thumbnails have these colours too
    colours = json.loads(b.evaluate("document.getElementById('canopy-data').textContent"))["classes"]
    by_name = {c["name"]: c["color"] for c in colours}
    leaf, fruit = count_colours(b, png, [by_name["leaf"], by_name["fruit"]])
    if leaf < 50 or fruit < 5:
        fails.append(f"the 3D view looks blank: {leaf} leaf-coloured and {fruit} fruit-coloured pixels")
    views = b.evaluate("canopyReport.views")
    b.evaluate("(() => { const s = document.getElementById('slider'); s.value = 0; s.dispatchEvent(new Event('input')); })()")
    first = json.loads(b.evaluate("JSON.stringify(canopyReport.state())"))
    count_text = b.evaluate("document.getElementById('view-count').textContent")
    if views > 1:
        if first["view"] != 0 or count_text != f"view 1 / {views}":
            fails.append(f"the slider did not move to view 1: {first}, '{count_text}'")
        if not first["shownAttempts"] < last["shownAttempts"]:
            fails.append(f"moving the slider did not change the cameras drawn: {first['shownAttempts']} vs {last['shownAttempts']}")
        if not first["cursor"] < last["cursor"]:
            fails.append(f"moving the slider did not move the curve cursor: {first['cursor']} vs {last['cursor']}")
        if not first["drawnVoxels"] < last["drawnVoxels"]:
            fails.append(f"the map at view 1 is not smaller than at the end: {first['drawnVoxels']} vs {last['drawnVoxels']}")
    banner = b.evaluate("document.getElementById('incomplete') ? document.getElementById('incomplete').textContent : ''")
    if incomplete and "Incomplete" not in banner:
        fails.append("the report of an interrupted run does not say it is incomplete")
    if not incomplete and banner:
        fails.append("a complete run's report says: " + banner)
    fails += check_readable(b, views)
    if mission:
        fails += check_mission(b, path, fruit_views)
    elif b.evaluate("JSON.parse(document.getElementById('canopy-data').textContent).kind") == "map" and not incomplete:
        fails += check_mapped(b)  # canopy map's page too
    if shots:
        b.evaluate(f"canopyReport.setView({max(0, views // 4)})")
        with open(os.path.join(shots, "report_readable.png"), "wb") as f:
            f.write(b.screenshot())
        for name, selector in (("report_metrics.png", "#metrics"), ("report_fruits.png", "#fruits")):
            b.evaluate(f"document.querySelector('{selector}').scrollIntoView()")
            with open(os.path.join(shots, name), "wb") as f:
                f.write(b.screenshot(selector))
    fails += b.errors()
    ready_ms = b.evaluate("canopyReport.readyMs")
    marks = b.evaluate("canopyReport.marks")
    print(f"{path}: ready in {load_s:.2f} s ({ready_ms / 1000:.2f} s after navigation started, page's own clock), {views} views, {last['drawnVoxels']} voxels at the end, "
          f"{first['drawnVoxels']} at view 1, {leaf} leaf and {fruit} fruit pixels; page marks (ms) "
          + ", ".join(f"{k} {v:.0f}" for k, v in marks.items()))
    return fails


def check_experiment(b, path, shots=None):
    fails = []
    load_s = b.open(path)
    links = b.evaluate("canopyReport.links")
    trials = b.evaluate("canopyReport.trials")
    if not links or len(links) != trials:
        fails.append(f"{len(links or [])} trial links for {trials} trials")
    for link in links or []:
        target = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), link))
        if not os.path.isfile(target):
            fails.append(f"link {link} does not resolve")
    # Hovering a trial's curve names its method, P_gt, world and value.
    tip = b.evaluate("""(() => {
      const svg = document.getElementById('exp-sc'), line = svg.querySelector('path.trial-line');
      if (!line) return '';
      const p = line.getPointAtLength(line.getTotalLength()), r = svg.getBoundingClientRect();
      svg.dispatchEvent(new MouseEvent('mousemove', { clientX: r.left + p.x, clientY: r.top + p.y }));
      return document.getElementById('exp-tip').textContent;
    })()""")
    if trials and not all(w in tip for w in ("P_gt", "world", "SC ")):
        fails.append(f"hovering a curve did not name its method, P_gt, world and value: '{tip}'")
    if b.evaluate("typeof THREE") != "undefined":
        fails.append("the experiment page carries three.js but draws SVG only")
    size = os.path.getsize(path)
    if size > 400_000:
        fails.append(f"the experiment page is {size} bytes")
    for svg in ("exp-sc", "exp-h"):
        order = b.evaluate(f"[...document.querySelectorAll('#{svg} path')].map(p => p.classList.contains('trial-line') ? 't' : p.classList.contains('mean-line') ? 'm' : '')")
        seq = "".join(order)
        if "m" not in seq or "t" in seq[seq.index("m"):]:
            fails.append(f"#{svg}: a mean line is drawn under a trial's line ({seq})")
        for axis in ("x", "y"):
            t = b.evaluate(f"[...document.querySelectorAll('#{svg} text.tick-{axis}')].map(e => e.textContent)")
            if len(t) < 2 or [float(v) for v in t] != sorted(float(v) for v in t):
                fails.append(f"#{svg}: {axis} ticks {t}")
    if shots:
        with open(os.path.join(shots, "report_experiment.png"), "wb") as f:
            f.write(b.screenshot("#exp-sc"))
    hrefs = b.evaluate("[...document.querySelectorAll('a.trial-link')].map(a => a.href)")
    if links and hrefs:
        b.open(hrefs[0][len("file://"):])  # the first trial's own report opens
    fails += b.errors()
    print(f"{path}: ready in {load_s:.2f} s, {trials} trials, {len(links or [])} links; hover: {tip}")
    return fails


def check_poisoned(b, path):
    """A page whose data strings hold "<!--<script>" (which once blanked it): it becomes ready,
    throws nothing, and shows the string as text. Links and images built from poisoned names
    may not resolve; that is not checked here."""
    fails = []
    load_s = b.open(path)
    shown = b.evaluate("""(() => {  // text nodes of the page (hidden and SVG ones too), not its scripts
      const w = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
      let n = 0;
      while (w.nextNode())
        if (!['SCRIPT', 'STYLE'].includes(w.currentNode.parentNode.nodeName))
          n += w.currentNode.nodeValue.split('<!--<script>').length - 1;
      return n;
    })()""")
    if not shown:
        fails.append("the page shows no '<!--<script>' as text")
    fails += [e for e in b.errors() if not e.startswith("log: Failed to load resource")]
    print(f"{path}: ready in {load_s:.2f} s, '<!--<script>' shown {shown} times as text")
    return fails


def main(argv):
    args = argv[1:]
    shot, size, shots = None, (1280, 800), None
    if "--window" in args:  # WxH of the browser window
        i = args.index("--window")
        size = tuple(int(x) for x in args[i + 1].split("x"))
        del args[i:i + 2]
    if "--shots" in args:  # the pictures of docs/report.md
        i = args.index("--shots")
        shots = args[i + 1]
        del args[i:i + 2]
    fruit_views = None
    if "--fruit-views" in args:  # the views that saw each fruit, counted apart (fruit_views.py's JSON)
        i = args.index("--fruit-views")
        fruit_views = json.load(open(args[i + 1]))
        del args[i:i + 2]
    if "--screenshot" in args:
        i = args.index("--screenshot")
        shot = args[i + 1]
        del args[i:i + 2]
    if not args or len(args) % 2 or any(k not in ("run", "mission", "incomplete", "experiment", "poisoned") for k in args[::2]):
        print(__doc__)
        return 2
    b = Browser(*size)  # one browser for every page
    fails = []
    try:
        for kind, path in zip(args[::2], args[1::2]):
            if kind == "experiment":
                got = check_experiment(b, path, shots)
            elif kind == "poisoned":
                got = check_poisoned(b, path)
            else:
                got = check_run(b, path, kind == "incomplete", shot, kind == "mission", shots if kind == "mission" else None,
                                fruit_views if kind == "mission" else None)
                shot = None
            fails += [f"{path}: {f}" for f in got]
            b.events.clear()
    finally:
        b.close()
    for f in fails:
        print("FAIL:", f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
