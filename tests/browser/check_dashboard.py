#!/usr/bin/env python3
"""The dashboard of `mblab serve --http` in a real browser, against the real server.

Headless chromium (through chromedriver, as check_reports.py drives it) opens the dashboard while
`mblab serve` runs. Checked: the live stream connects; a value written over Modbus by `mblab
write` appears in the page's table; a value edited in the page is what `mblab read` then reads
over Modbus; a fault rule added in the page makes a Modbus read answer exception 04, and its
on/off switch unchecked in the page lets the read through again; the request counters show the
Modbus traffic; the screenshot is the window's size and not one colour; the console has no error.
Then a page from another origin (another local port) tries what a hostile site would: a
text/plain fetch, a form POST and a JSON fetch to the API, and framing the dashboard; none of
them changes the device's fault rules, and the frame stays empty.

Usage: check_dashboard.py MBLAB [SCREENSHOT_DIR]
Exit status 0 passed, 1 failed, 77 skipped (no chromium or chromedriver on this machine).
"""

import http.server
import json
import os
import re
import subprocess
import sys
import threading
import time
import urllib.request

from check_reports import Failure, check, check_screenshot, with_browser


def wait_for(what, condition, seconds=20):
    """Polls `condition` until it returns something true; the value, or a failure naming `what`."""
    deadline = time.monotonic() + seconds
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise Failure(f"the dashboard never showed {what} (waited {seconds} s)")
        time.sleep(0.1)


def mblab_run(mblab, *args):
    done = subprocess.run([mblab, *args], capture_output=True, text=True, timeout=60)
    return done.returncode, done.stdout + done.stderr


def start_serve(mblab, *extra):
    serve = subprocess.Popen([mblab, "serve", "--listen", "tcp://127.0.0.1:0",
                              "--http", "127.0.0.1:0", *extra],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    modbus = serve.stdout.readline()
    http = serve.stdout.readline()
    tcp = re.search(r"tcp://127\.0\.0\.1:(\d+)", modbus)
    # The page's address as printed, with the token serve made after '#' (none with
    # --http-no-token).
    web = re.search(r"http://127\.0\.0\.1:\d+/(#token=[0-9a-f]{32})?", http)
    if not tcp or not web:
        serve.kill()
        raise Failure(f"serve did not say where it listens: {modbus!r} {http!r}")
    return serve, f"tcp://127.0.0.1:{tcp.group(1)}", web.group(0)


def shown_value(driver, address):
    """The value in the page's table at `address`, or None while that row is not there."""
    return driver.run(
        "for (const row of document.querySelectorAll('#values tbody tr'))"
        "  if (row.cells[0].textContent === String(arguments[0]))"
        "    return row.cells[1].firstChild.value;"
        "return null;", address)


# A hostile page: every way a site may send a change to a local server without the server's
# consent, and a frame of the dashboard (to overlay it, clickjacking).
ATTACK_PAGE = """<!DOCTYPE html><html><body>
<iframe id="frame" src="{base}"></iframe>
<form id="form" method="POST" action="{base}api/units/1/faults" enctype="text/plain">
<input name='{{"action":"exception","exception":6,"functions":[3],"x":"' value='"}}'></form>
<script>
const rule = JSON.stringify({{action: "exception", exception: 6, functions: [3]}});
const url = "{base}api/units/1/faults";
Promise.allSettled([
  fetch(url, {{method: "POST", mode: "no-cors", headers: {{"Content-Type": "text/plain"}}, body: rule}}),
  fetch(url, {{method: "POST", headers: {{"Content-Type": "application/json"}}, body: rule}}),
]).then(() => {{ document.title = "sent"; document.getElementById("form").submit(); }});
</script></body></html>"""


def serve_attack_page(base):
    """A server on another port (another origin) with the hostile page at /."""
    page = ATTACK_PAGE.format(base=base).encode()

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.end_headers()
            self.wfile.write(page)

        def log_message(self, *args):
            pass

    server = http.server.HTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def fault_rules(base):
    with urllib.request.urlopen(base + "api/units/1/faults", timeout=10) as answer:
        return json.load(answer)


def check_hostile_page(driver, mblab):
    """Against a server without a token, the weakest setting: Origin, Host and JSON still hold."""
    serve, _, base = start_serve(mblab, "--http-no-token")
    attacker = serve_attack_page(base)
    try:
        before = fault_rules(base)
        attack = f"http://127.0.0.1:{attacker.server_address[1]}/"
        driver.open(attack)
        # The form's submission leaves the hostile page once both fetches have settled.
        wait_for("the hostile page's requests sent and its form submitted",
                 lambda: not driver.run("return location.href").startswith(attack))
        time.sleep(1)
        check(fault_rules(base) == before,
              f"a page on another origin changed the fault rules: {fault_rules(base)}")
    finally:
        attacker.shutdown()
        serve.terminate()
        serve.wait(timeout=30)


def check_dashboard(driver, mblab, work, shots):
    serve, target, page = start_serve(mblab)
    try:
        driver.open(page)
        wait_for("the live stream connected",
                 lambda: driver.run("return document.getElementById('status').textContent")
                 == "live")
        check(driver.run("return location.hash") == "",
              "the token is still in the address bar after the page took it")

        # Modbus -> page.
        status, out = mblab_run(mblab, "write", target, "register", "3", "4242")
        check(status == 0, f"mblab write failed: {out}")
        wait_for("register 3 = 4242 after a Modbus write",
                 lambda: shown_value(driver, 3) == "4242")

        # Page -> Modbus: the table's input for register 5 edited and committed.
        driver.run(
            "for (const row of document.querySelectorAll('#values tbody tr'))"
            "  if (row.cells[0].textContent === '5') {"
            "    const input = row.cells[1].firstChild; input.value = '777';"
            "    input.dispatchEvent(new Event('change')); }")

        def read_5():
            status, out = mblab_run(mblab, "read", target, "holding", "5", "1")
            return status == 0 and re.search(r"^5 \(0x0005\)\s+0x0309\s+777$", out, re.M)

        wait_for("register 5 = 777 over Modbus after an edit in the page", read_5)

        # A fault rule from the page, then its switch.
        driver.run("document.getElementById('newrule').value = arguments[0];"
                   "document.getElementById('add').click();",
                   '{"action":"exception","exception":4,"functions":[3]}')
        wait_for("the new fault rule in its table",
                 lambda: driver.run("return document.querySelectorAll('#faults tbody tr')"
                                    ".length") == 1)

        def read_status():
            return mblab_run(mblab, "read", target, "holding", "0", "1")

        wait_for("exception 04 from the rule added in the page",
                 lambda: read_status()[0] != 0 and "04" in read_status()[1])
        driver.run("document.querySelector('#faults tbody input[type=checkbox]').click();")
        wait_for("the rule switched off in the page letting reads through",
                 lambda: read_status()[0] == 0)
        check(driver.run("return document.querySelector('#faults tbody input').checked") is False,
              "the rule's switch is still on after the page switched it off")

        # The counters show the Modbus traffic (FC 03 and FC 06 rows).
        functions = wait_for(
            "FC 03 and FC 06 in the request counters",
            lambda: (lambda f: f if "0x03" in f and "0x06" in f else None)(driver.run(
                "return Array.from(document.querySelectorAll('#requests tbody tr'))"
                ".map(r => r.cells[1].textContent);")))
        shot = check_screenshot(driver, os.path.join(shots, "dashboard.png"))
        errors = driver.console_errors()
        check(not errors, f"the dashboard logged errors: {errors}")
        yield (f"dashboard: Modbus write shown live, page edit read over Modbus, fault rule "
               f"added and switched off from the page, counters for {', '.join(functions)}, "
               f"screenshot {shot[0]}x{shot[1]} with {shot[2]}+ colours")
        check_hostile_page(driver, mblab)
        yield ("a page on another origin: text/plain and JSON fetches and a form POST to the "
               "API changed no fault rule")
    finally:
        serve.terminate()
        serve.wait(timeout=30)


if __name__ == "__main__":
    sys.exit(with_browser(check_dashboard, "mblab-dashboard-"))
