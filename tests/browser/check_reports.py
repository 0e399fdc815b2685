#!/usr/bin/env python3
"""The HTML reports of `mblab conform --html` and `mblab load --html` in a real browser.

Debian's headless chromium opens each report from file:// through chromedriver, spoken to as
the W3C WebDriver JSON protocol over loopback with nothing but the standard library. Checked:
every case of the JSON report is on the page, the verdict filters and the case id search show
exactly the cases they should, the differing bytes of a failure are marked, a 250-byte frame's
evidence wraps so the source column stays on a 1280-pixel screen (the load report's latency
columns too), the load report has its node table and a latency chart per node with named axes,
the screenshots are the window's size and not one
colour, and the browser's console has no error.

Usage: check_reports.py MBLAB [SCREENSHOT_DIR]
Exit status 0 passed, 1 failed, 77 skipped (no chromium or chromedriver on this machine).
"""

import base64
import contextlib
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
import zlib

SKIP = 77
WIDTH, HEIGHT = 1200, 900


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class WebDriver:
    """A session of chromedriver's W3C WebDriver protocol."""

    def __init__(self, port, profile_dir):
        self.base = f"http://127.0.0.1:{port}"
        capabilities = {
            "browserName": "chrome",
            "goog:loggingPrefs": {"browser": "ALL"},
            "goog:chromeOptions": {
                "binary": shutil.which("chromium"),
                # Root in a container has no sandbox to drop into.
                "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                         "--disable-dev-shm-usage", f"--user-data-dir={profile_dir}",
                         f"--window-size={WIDTH},{HEIGHT}", "--hide-scrollbars"],
            },
        }
        answer = self.call("POST", "/session",
                           {"capabilities": {"alwaysMatch": capabilities}})
        self.session = f"/session/{answer['sessionId']}"

    def call(self, method, path, body=None):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(self.base + path, data=data, method=method,
                                         headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request, timeout=60) as response:
                return json.load(response)["value"]
        except urllib.error.HTTPError as error:
            raise Failure(f"webdriver {method} {path}: {error.read().decode()[:500]}")

    def do(self, method, path, body=None):
        return self.call(method, self.session + path, body)

    def open(self, url):
        self.do("POST", "/url", {"url": url})

    def run(self, script, *args):
        return self.do("POST", "/execute/sync", {"script": script, "args": list(args)})

    def element(self, css):
        found = self.do("POST", "/element", {"using": "css selector", "value": css})
        return next(iter(found.values()))  # the reference, under W3C's fixed element key

    def click(self, css):
        self.do("POST", f"/element/{self.element(css)}/click", {})

    def type(self, css, text):
        self.do("POST", f"/element/{self.element(css)}/value", {"text": text})

    def screenshot(self):
        return base64.b64decode(self.do("GET", "/screenshot"))

    def console_errors(self):
        entries = self.do("POST", "/se/log", {"type": "browser"})
        return [e["message"] for e in entries if e.get("level") == "SEVERE"]

    def quit(self):
        try:
            self.do("DELETE", "")
        except Exception:  # the browser may be gone already; the driver is killed next
            pass


def png_size_and_colours(png):
    """(width, height, distinct colours) of an 8-bit RGB or RGBA PNG, decoded here."""
    check(png[:8] == b"\x89PNG\r\n\x1a\n", "the screenshot is not a PNG")
    at, idat = 8, b""
    while at < len(png):
        length = int.from_bytes(png[at:at + 4], "big")
        kind, data = png[at + 4:at + 8], png[at + 8:at + 8 + length]
        if kind == b"IHDR":
            width, height = int.from_bytes(data[:4], "big"), int.from_bytes(data[4:8], "big")
            depth, colour_type = data[8], data[9]
        elif kind == b"IDAT":
            idat += data
        at += 12 + length
    check(depth == 8 and colour_type in (2, 6), f"unexpected PNG format {depth}/{colour_type}")
    bpp = 3 if colour_type == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    previous = bytearray(stride)
    colours = set()
    for row in range(height):
        start = row * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):  # the five filters of the PNG specification
            left = line[i - bpp] if i >= bpp else 0
            up = previous[i]
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                corner = previous[i - bpp] if i >= bpp else 0
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                nearest = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[i] = (line[i] + nearest) & 0xFF
        if row % 8 == 0:
            colours.update(bytes(line[i:i + 3]) for i in range(0, stride, bpp * 4))
        previous = line
    return width, height, len(colours)


def check_screenshot(driver, path):
    png = driver.screenshot()
    with open(path, "wb") as f:
        f.write(png)
    width, height, colours = png_size_and_colours(png)
    check(width == WIDTH and height >= HEIGHT * 0.6,
          f"{path}: screenshot is {width}x{height}, not the {WIDTH}x{HEIGHT} window")
    # A blank or one-colour page has one or two; text, tables and marks have many.
    check(colours >= 8, f"{path}: the screenshot has only {colours} colours")
    return width, height, colours


def visible_cases(driver):
    return driver.run("return Array.from(document.querySelectorAll('.case'))"
                      ".filter(c => !c.hidden).map(c => c.dataset.id);")


def check_conform(driver, mblab, work, shots):
    html, report = os.path.join(work, "conform.html"), os.path.join(work, "conform.json")
    # Declaring fewer registers than the built-in device has makes the register cases fail, so
    # the page has failures with marked bytes as well as passes and N/A.
    run = subprocess.run([mblab, "conform", "--registers", "50", "--html", html, "--json", report],
                         capture_output=True, text=True, timeout=300)
    check(run.returncode == 1, f"conform exited {run.returncode}: {run.stderr}")
    with open(report) as f:
        suites = json.load(f)["suites"]
    cases = [(c["id"], c["verdict"]) for s in suites for c in s["cases"]]
    suite_of = [s["name"] for s in suites for _ in s["cases"]]
    check(any(v == "FAIL" for _, v in cases), "the run has no failure to show")

    driver.open("file://" + html)
    on_page = driver.run("return Array.from(document.querySelectorAll('.case'))"
                         ".map(c => [c.dataset.id, c.dataset.verdict]);")
    check([tuple(c) for c in on_page] == cases,
          f"the page's cases differ from the JSON report's ({len(on_page)} vs {len(cases)})")
    check(driver.run("return document.getElementById('shown').textContent;") ==
          f"{len(cases)} of {len(cases)} cases shown", "the case count is not shown")
    marks = driver.run("return document.querySelectorAll('tbody.case[data-verdict=\"FAIL\"] "
                       "mark.diff').length;")
    check(marks > 0, "no differing byte is marked in the failures")
    shot = check_screenshot(driver, os.path.join(shots, "conform.png"))

    # Untick PASS: every other case stays, no PASS is left.
    driver.click("input.verdict-filter[value='PASS']")
    check(visible_cases(driver) == [i for i, v in cases if v != "PASS"],
          "unticking PASS does not leave exactly the other cases")
    # Only FAIL ticked.
    for verdict in ("N/A", "NOT RUN"):
        driver.click(f"input.verdict-filter[value='{verdict}']")
    failed = [i for i, v in cases if v == "FAIL"]
    check(visible_cases(driver) == failed, "FAIL alone does not show exactly the failures")
    suites = driver.run("return Array.from(document.querySelectorAll('section.suite'))"
                        ".filter(s => !s.hidden).length;")
    check(suites == len({s for s, (_, v) in zip(suite_of, cases) if v == "FAIL"}),
          "suites without a failure are still shown under FAIL alone")
    driver.run("document.querySelector('tbody.case[data-verdict=\"FAIL\"]').scrollIntoView({block: 'center'});")
    check_screenshot(driver, os.path.join(shots, "conform-failures.png"))
    # Everything ticked again, then a search by id.
    for verdict in ("PASS", "N/A", "NOT RUN"):
        driver.click(f"input.verdict-filter[value='{verdict}']")
    driver.type("#search", "7.5")
    wanted = [i for i, _ in cases if "7.5" in i]
    check(wanted and visible_cases(driver) == wanted,
          "searching 7.5 does not show exactly the cases whose id holds it")
    check(driver.run("return document.getElementById('shown').textContent;") ==
          f"{len(wanted)} of {len(cases)} cases shown", "the count does not follow the search")
    errors = driver.console_errors()
    check(not errors, f"console errors on the conform report: {errors}")
    return len(cases), len(failed), shot


@contextlib.contextmanager
def laptop_window(driver, html):
    """`html` opened in a 1280-pixel window: yields the window's inner width after checking
    that the page does not scroll sideways; the usual size is back afterwards."""
    driver.do("POST", "/window/rect", {"width": 1280, "height": HEIGHT})
    try:
        driver.open("file://" + html)
        inner = driver.run("return window.innerWidth;")
        wide = driver.run("return document.documentElement.scrollWidth;")
        check(wide <= inner, f"{html} is {wide} px wide in a {inner} px window")
        yield inner
    finally:
        driver.do("POST", "/window/rect", {"width": WIDTH, "height": HEIGHT})


def check_long_frame(driver, mblab, work, shots):
    """A 250-byte answer in a failure's evidence: at 1280 px the page does not scroll sideways
    and the source column is on screen."""
    # 125 holding registers whose bytes never repeat 8 times, so no run is compacted.
    values = ", ".join(str((i << 8) | (i ^ 0x5A)) for i in range(125))
    profile = os.path.join(work, "long.toml")
    with open(profile, "w") as f:
        f.write(f'name = "long frames"\n[[unit]]\nid = 1\n'
                f'holding_registers = [{{start = 0, values = [{values}]}}]\n')
    suite = os.path.join(work, "long-suite.toml")
    with open(suite, "w") as f:
        f.write('[suite]\nname = "long"\n[[case]]\nsource = "APP 6.3"\nid = "long.1"\n'
                'title = "125 registers where 1 was expected"\n'
                'request = "00 01 00 00 00 06 01 03 00 00 00 7D"\n'
                'expect = "00 01 00 00 00 05 01 03 02 XX XX"\n')
    html = os.path.join(work, "long.html")
    run = subprocess.run([mblab, "conform", "--profile", profile, "--suite", suite,
                          "--html", html], capture_output=True, text=True, timeout=120)
    check(run.returncode == 1, f"conform exited {run.returncode}: {run.stdout}{run.stderr}")
    with laptop_window(driver, html) as inner:
        received = driver.run("return document.querySelector('pre.evidence').textContent"
                              ".split('\\n')[1].length;")
        check(received > 700, f"the evidence holds no 250-byte frame ({received} characters)")
        right = driver.run("var row = document.querySelector('tbody.case tr');"
                           "return row.cells[4].getBoundingClientRect().right;")
        check(0 < right <= inner, f"the source column ends at {right} px, off a {inner} px window")
        driver.run("document.querySelector('pre.evidence').scrollIntoView({block: 'center'});")
        shot = driver.screenshot()
        with open(os.path.join(shots, "conform-long-frame.png"), "wb") as f:
            f.write(shot)
    return inner, right


def check_load(driver, mblab, work, shots):
    serve = subprocess.Popen([mblab, "serve", "--listen", "tcp://127.0.0.1:0"],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        port = None
        for line in serve.stdout:
            found = re.search(r"on tcp://127\.0\.0\.1:(\d+)", line)
            if found:
                port = found.group(1)
                break
        check(port, "mblab serve did not say its port")
        html = os.path.join(work, "load.html")
        run = subprocess.run([mblab, "load", f"tcp://127.0.0.1:{port}", "--duration", "2s",
                              "--connections", "2", "--html", html],
                             capture_output=True, text=True, timeout=120)
        check(run.returncode == 0, f"load exited {run.returncode}: {run.stdout}{run.stderr}")
    finally:
        serve.terminate()
        serve.wait(timeout=30)

    driver.open("file://" + html)
    rows = driver.run("return Array.from(document.querySelectorAll('#nodes tr.node'))"
                      ".map(r => r.cells[0].textContent);")
    check(rows == [f"tcp://127.0.0.1:{port}"], f"the node table has {rows}")
    bars = driver.run("return Array.from(document.querySelectorAll('svg.histogram'))"
                      ".map(s => s.querySelectorAll('rect.bar').length);")
    check(len(bars) == 1 and bars[0] > 0, f"no latency chart with bars: {bars}")
    height = driver.run("return document.querySelector('svg.histogram').getBoundingClientRect()"
                        ".height;")
    check(height > 100, f"the latency chart is not drawn ({height} px high)")
    check(driver.run("return document.getElementById('outcome').textContent;") == "PASS",
          "the load report does not say PASS")
    titles = driver.run("return Array.from(document.querySelectorAll('svg.histogram "
                        ".axis-title')).map(t => t.textContent);")
    check(titles == ["answers", "latency (ms)"], f"the latency chart's axes are named {titles}")
    # At 1280 px the page does not scroll sideways and every latency column is on screen.
    with laptop_window(driver, html) as inner:
        right = driver.run("var head = document.querySelector('#nodes tr').cells;"
                           "return head[head.length - 2].getBoundingClientRect().right;")
        check(0 < right <= inner, f"the max ms column ends at {right} px, off a {inner} px window")
    driver.open("file://" + html)
    driver.run("document.querySelector('svg.histogram').scrollIntoView({block: 'center'});")
    shot = check_screenshot(driver, os.path.join(shots, "load.png"))
    errors = driver.console_errors()
    check(not errors, f"console errors on the load report: {errors}")
    return bars[0], shot


def with_browser(body, prefix):
    """Runs body(driver, mblab, work, shots) in headless chromium: the process's exit status.

    body returns lines to print when every check passed, or raises Failure. argv is
    MBLAB [SCREENSHOT_DIR]; without chromium or chromedriver the status is SKIP."""
    mblab = os.path.abspath(sys.argv[1])
    chromium, chromedriver = shutil.which("chromium"), shutil.which("chromedriver")
    if not chromium or not chromedriver:
        print("SKIP: chromium and chromium-driver are not installed "
              "(scripts/install-deps.sh installs them)")
        return SKIP
    work = tempfile.mkdtemp(prefix=prefix)
    shots = sys.argv[2] if len(sys.argv) > 2 else work
    os.makedirs(shots, exist_ok=True)
    port = free_port()
    driver_process = subprocess.Popen([chromedriver, f"--port={port}"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    driver = None
    try:
        for _ in range(100):
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=1):
                    break
            except OSError:
                time.sleep(0.1)
        driver = WebDriver(port, os.path.join(work, "profile"))
        for line in body(driver, mblab, work, shots):
            print(line)
        print(f"screenshots in {shots}")
        return 0
    except Failure as failure:
        print(f"FAIL: {failure}")
        return 1
    finally:
        if driver:
            driver.quit()
        driver_process.terminate()
        driver_process.wait(timeout=30)
        if shots != work:
            shutil.rmtree(work, ignore_errors=True)


def check_both(driver, mblab, work, shots):
    cases, failed, shot = check_conform(driver, mblab, work, shots)
    yield (f"conform report: {cases} cases, {failed} failures, filters and search work, "
           f"screenshot {shot[0]}x{shot[1]} with {shot[2]}+ colours")
    inner, right = check_long_frame(driver, mblab, work, shots)
    yield (f"a 250-byte frame at {inner} px: no sideways scroll, the source column ends at "
           f"{right:.0f} px")
    bars, shot = check_load(driver, mblab, work, shots)
    yield (f"load report: node table, latency chart of {bars} bars, "
           f"screenshot {shot[0]}x{shot[1]} with {shot[2]}+ colours")


if __name__ == "__main__":
    sys.exit(with_browser(check_both, "mblab-browser-"))
