#!/usr/bin/env python3
"""The dashboard of `mblab serve --http` in a real browser, against the real server.

Headless chromium (through chromedriver, as check_reports.py drives it) opens the dashboard while
`mblab serve` runs. Checked: the live stream connects; a value written over Modbus by `mblab
write` appears in the page's table; a value edited in the page is what `mblab read` then reads
over Modbus; a fault rule added in the page makes a Modbus read answer exception 04, and its
on/off switch unchecked in the page lets the read through again; the request counters show the
Modbus traffic; the screenshot is the window's size and not one colour; the console has no error.

Usage: check_dashboard.py MBLAB [SCREENSHOT_DIR]
Exit status 0 passed, 1 failed, 77 skipped (no chromium or chromedriver on this machine).
"""

import os
import re
import subprocess
import sys
import time

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


def start_serve(mblab):
    serve = subprocess.Popen([mblab, "serve", "--listen", "tcp://127.0.0.1:0",
                              "--http", "127.0.0.1:0"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    modbus = serve.stdout.readline()
    http = serve.stdout.readline()
    tcp = re.search(r"tcp://127\.0\.0\.1:(\d+)", modbus)
    web = re.search(r"http://127\.0\.0\.1:(\d+)/", http)
    if not tcp or not web:
        serve.kill()
        raise Failure(f"serve did not say where it listens: {modbus!r} {http!r}")
    return serve, f"tcp://127.0.0.1:{tcp.group(1)}", f"http://127.0.0.1:{web.group(1)}/"


def shown_value(driver, address):
    """The value in the page's table at `address`, or None while that row is not there."""
    return driver.run(
        "for (const row of document.querySelectorAll('#values tbody tr'))"
        "  if (row.cells[0].textContent === String(arguments[0]))"
        "    return row.cells[1].firstChild.value;"
        "return null;", address)


def check_dashboard(driver, mblab, work, shots):
    serve, target, page = start_serve(mblab)
    try:
        driver.open(page)
        wait_for("the live stream connected",
                 lambda: driver.run("return document.getElementById('status').textContent")
                 == "live")

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
    finally:
        serve.terminate()
        serve.wait(timeout=30)


if __name__ == "__main__":
    sys.exit(with_browser(check_dashboard, "mblab-dashboard-"))
