#!/usr/bin/env python3
"""The dashboard of `mblab serve --http` in a real browser, against the real server.

Headless chromium (through chromedriver, as check_reports.py drives it) opens the dashboard while
`mblab serve` runs. Checked: the live stream connects; a value written over Modbus by `mblab
write` appears in the page's table; a value edited in the page is what `mblab read` then reads
over Modbus; the fault rule form names a mistake beside it and sends nothing, shows only the
fields of the fault chosen, and a rule added with it (exception 04 on FC 03 at addresses 0 to 4)
makes a Modbus read there answer exception 04 while one at address 10 goes through, and its
on/off switch unchecked in the page lets the read through again; the request counters show the
Modbus traffic; answers/s shows within two seconds of the first request, near the rate sent,
and falls to 0 within three seconds of the last; the screenshot is the window's size and not one
colour; the console has no error. With the moving profile the page opens on the input registers,
where the behaviours move values, and draws a trend for the moving points that rises and falls.
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
import socket
import struct
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


def fill_rule(driver, **fields):
    """Sets the rule form's fields (by id without "rule-") and submits it."""
    driver.run("for (const [id, value] of Object.entries(arguments[0])) {"
               "  const e = document.getElementById('rule-' + id); e.value = value;"
               "  e.dispatchEvent(new Event('change')); }"
               "document.getElementById('add').click();", fields)


def rule_rows(driver):
    return driver.run("return Array.from(document.querySelectorAll('#faults tbody tr'))"
                      ".map(r => r.cells[1].textContent);")


def check_rule_form(driver):
    """Mistakes named beside the form and nothing sent; only the chosen fault's fields shown;
    then exception 04 on FC 03 at addresses 0 to 4, added."""
    error = "return document.getElementById('rule-error').textContent"
    for fields, named in [({"functions": "3, 200"}, "function codes: 200 is not"),
                          ({"functions": "3", "first": "10", "last": "5"}, "addresses: the first"),
                          ({"first": "", "last": "", "when": "probability", "when-value": "1.5"},
                           "probability: give a number from 0 to 1")]:
        fill_rule(driver, **fields)
        wait_for(f"the form naming '{named}'", lambda: named in driver.run(error))
        check(rule_rows(driver) == [], f"a refused form still added a rule: {rule_rows(driver)}")
    shown = ("return Array.from(document.querySelectorAll('#ruleform label'))"
             ".filter(l => l.offsetParent !== null && l.className).map(l => l.className)")
    driver.run("const a = document.getElementById('rule-action'); a.value = 'delay';"
               "a.dispatchEvent(new Event('change'));")
    check(driver.run(shown) == ["for-delay"], f"a delay rule's form shows {driver.run(shown)}")
    fill_rule(driver, action="exception", exception="4", functions="3", first="0", last="4",
              when="always")
    rows = wait_for("the form's rule in its table", lambda: rule_rows(driver))
    check(rows == ["exception 0x04 on FC 0x03, addresses 0 to 4"],
          f"the rule added from the form shows as {rows}")
    check(driver.run(error) == "", f"the form still shows an error: {driver.run(error)!r}")


def send_reads(target, per_second, seconds):
    """FC 03 requests on one connection at about `per_second`; how many were answered."""
    host, port = target[len("tcp://"):].rsplit(":", 1)
    answered = 0
    with socket.create_connection((host, int(port)), timeout=5) as s:
        start = time.monotonic()
        while time.monotonic() - start < seconds:
            s.sendall(struct.pack(">HHHBBHH", answered & 0xFFFF, 0, 6, 1, 3, 0, 1))
            s.recv(256)
            answered += 1
            time.sleep(max(0.0, start + answered / per_second - time.monotonic()))
    return answered


def shown_rate(driver):
    text = driver.run("return document.getElementById('rate').textContent")
    return int(text) if text.lstrip("-").isdigit() else None


def check_rates(driver, target):
    """answers/s from the first two seconds of traffic, near the rate sent, and 0 soon after."""
    wait_for("answers/s at 0 before the traffic", lambda: shown_rate(driver) == 0)
    sent = 40
    thread = threading.Thread(target=send_reads, args=(target, sent, 6))
    start = time.monotonic()
    thread.start()
    wait_for("answers/s above 0 after the first requests", lambda: (shown_rate(driver) or 0) > 0,
             seconds=10)
    first = time.monotonic() - start
    check(first < 2.5, f"answers/s showed the traffic only after {first:.1f} s")
    time.sleep(2.5)
    rate = shown_rate(driver)
    check(sent / 2 <= rate <= sent * 1.5, f"answers/s shows {rate} while {sent}/s are sent")
    fc3 = driver.run("for (const r of document.querySelectorAll('#requests tbody tr'))"
                     "  if (r.cells[1].textContent === '0x03') return Number(r.cells[4].textContent);")
    check(sent / 2 <= fc3 <= sent * 1.5, f"FC 03 requests/s shows {fc3} while {sent}/s are sent")
    thread.join()
    stop = time.monotonic()
    wait_for("answers/s back at 0 after the traffic", lambda: shown_rate(driver) == 0)
    return first, rate, sent, time.monotonic() - stop


def check_trends(driver, mblab, shots):
    """The moving profile: the page opens where values move and draws their trends."""
    serve, _, page = start_serve(mblab, "moving")
    try:
        driver.open(page)
        wait_for("the live stream connected",
                 lambda: driver.run("return document.getElementById('status').textContent")
                 == "live")
        bank = driver.run("return document.getElementById('bank').value")
        check(bank == "input_registers", f"the moving profile's page opened on {bank}")
        line = ("for (const r of document.querySelectorAll('#points tbody tr'))"
                "  if (r.cells[0].textContent === '0') {"
                "    const l = r.querySelector('svg.trend polyline');"
                "    return l ? l.getAttribute('points') : null; }"
                "return null;")
        # Input 0 is a sine with a 10 s period: in 4 s its trend both rises and falls or moves
        # a good part of its height.
        def moving_line():
            points = driver.run(line)
            heights = {p.split(",")[1] for p in points.split()} if points else set()
            return points if points and len(points.split()) >= 8 and len(heights) >= 4 else None

        points = wait_for("a trend for input 0, the moving sine", moving_line)
        still = driver.run("return Array.from(document.querySelectorAll('#points tbody tr'))"
                           ".filter(r => r.cells[4].querySelector('svg')).length")
        check(still >= 2, f"only {still} of the moving profile's points draw a trend")
        # The trends in the screenshot, for the person who looks at it.
        driver.run("document.getElementById('points').scrollIntoView();")
        shot = check_screenshot(driver, os.path.join(shots, "dashboard-moving.png"))
        return (f"moving profile: opens on input registers, trends for {still} points "
                f"(input 0 with {len(points.split())} values so far), screenshot "
                f"{shot[0]}x{shot[1]}")
    finally:
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

        check_rule_form(driver)

        def read_status(address="0"):
            return mblab_run(mblab, "read", target, "holding", address, "1")

        wait_for("exception 04 from the rule added in the page",
                 lambda: read_status()[0] != 0 and "04" in read_status()[1])
        status, out = read_status("10")
        check(status == 0, f"a read at 10, outside the rule's addresses 0 to 4, failed: {out}")
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
        rate = check_rates(driver, target)
        driver.run("document.getElementById('faults').scrollIntoView();")
        shot = check_screenshot(driver, os.path.join(shots, "dashboard.png"))
        errors = driver.console_errors()
        check(not errors, f"the dashboard logged errors: {errors}")
        yield (f"dashboard: Modbus write shown live, page edit read over Modbus, fault rule "
               f"added from the form (mistakes named, not sent) and switched off, counters for {', '.join(functions)}, "
               f"screenshot {shot[0]}x{shot[1]} with {shot[2]}+ colours")
        check_hostile_page(driver, mblab)
        yield (f"dashboard rates: answers/s shown {rate[0]:.1f} s after the first request, "
               f"{rate[1]}/s for {rate[2]} sent/s, 0 again {rate[3]:.1f} s after the last")
        yield check_trends(driver, mblab, shots)
        yield ("a page on another origin: text/plain and JSON fetches and a form POST to the "
               "API changed no fault rule")
    finally:
        serve.terminate()
        serve.wait(timeout=30)


if __name__ == "__main__":
    sys.exit(with_browser(check_dashboard, "mblab-dashboard-"))
