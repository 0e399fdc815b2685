#!/usr/bin/env python3
"""The HTML report of `mblab conform-client --html` in a real browser, at 1280 pixels.

A client built wrong on purpose (tests/clients/modbus_client.py --defect wrong-unit) is examined,
so the page has a failure. Checked: the page speaks of the client under test (its command and
declarations), not of a device; every scenario of the JSON report is on it with its verdict and
a linked citation; the failure's wire transcript is open and marks the decoy the client took,
the passes' transcripts are folded; at 1280 px the page does not scroll sideways and the source
column is on screen; the verdict filter works; the screenshot is not one colour; the console has
no error.

Usage: check_client_report.py MBLAB [SCREENSHOT_DIR]
Exit status 0 passed, 1 failed, 77 skipped (no chromium or chromedriver on this machine).
"""

import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_reports import (check, laptop_window, png_size_and_colours,  # noqa: E402
                           visible_cases, with_browser)

CLIENT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "clients",
                      "modbus_client.py")


def check_client_report(driver, mblab, work, shots):
    html, report = os.path.join(work, "client.html"), os.path.join(work, "client.json")
    run = subprocess.run(
        [mblab, "conform-client", "--client-timeout", "300ms", "--client-retries", "1",
         "--html", html, "--json", report, "--", "python3", CLIENT, "{host}", "{port}", "{unit}",
         "{address}", "{count}", "--timeout", "0.3", "--retries", "1", "--defect", "wrong-unit"],
        capture_output=True, text=True, timeout=300)
    check(run.returncode == 1, f"conform-client exited {run.returncode}: {run.stderr}")
    with open(report) as f:
        suites = json.load(f)["suites"]
    cases = [(c["id"], c["verdict"]) for s in suites for c in s["cases"]]
    check([i for i, v in cases if v == "FAIL"] == ["tcp.4"], f"tcp.4 alone should fail: {cases}")

    with laptop_window(driver, html) as inner:
        title = driver.run("return document.querySelector('h1').textContent;")
        check(title.startswith("mblab conform-client tcp://127.0.0.1:"), f"the title is {title}")
        text = driver.run("return document.body.textContent;")
        check("Client under test" in text and "Device under test" not in text,
              "the page does not speak of the client under test")
        command = driver.run("return document.getElementById('client').textContent;")
        check("modbus_client.py '{host}' '{port}'" in command and "300 ms" in command,
              f"the client's command and timeout are not in its table: {command}")
        on_page = driver.run("return Array.from(document.querySelectorAll('.case'))"
                             ".map(c => [c.dataset.id, c.dataset.verdict]);")
        check([tuple(c) for c in on_page] == cases,
              f"the page's scenarios differ from the JSON report's ({len(on_page)} vs {len(cases)})")
        cited = driver.run("return Array.from(document.querySelectorAll('tbody.case'))"
                           ".filter(c => c.querySelector('tr').cells[4].querySelector('a'))"
                           ".length;")
        check(cited == len(cases), f"{cited} of {len(cases)} scenarios link their citation")
        failure = "tbody.case[data-verdict=\"FAIL\"]"
        wire = driver.run(f"var d = document.querySelector('{failure} details.wire');"
                          "return d ? [d.open, d.textContent] : null;")
        check(wire and wire[0], "the failure's wire transcript is not open")
        check("00 01 00 00 00 07 02 03 04 9C A4 9C A5  (decoy)" in wire[1],
              f"the decoy from unit 2 is not in the failure's transcript: {wire}")
        marked = driver.run(f"return document.querySelectorAll('{failure} mark.diff').length;")
        check(marked >= 1, "the decoy is not marked")
        folded = driver.run("return Array.from(document.querySelectorAll("
                            "'tbody.case[data-verdict=\"PASS\"] details.wire'))"
                            ".filter(d => d.open).length;")
        check(folded == 0, f"{folded} passes show their transcripts unfolded")
        right = driver.run("var row = document.querySelector('tbody.case tr');"
                           "return row.cells[4].getBoundingClientRect().right;")
        check(0 < right <= inner, f"the source column ends at {right} px, off a {inner} px window")
        driver.run(f"document.querySelector('{failure}').scrollIntoView({{block: 'center'}});")
        png = driver.screenshot()
        with open(os.path.join(shots, "conform-client.png"), "wb") as f:
            f.write(png)
        width, _, colours = png_size_and_colours(png)
        check(width == inner and colours >= 8,
              f"the screenshot is {width} px wide with {colours} colours")
        driver.click("input.verdict-filter[value='PASS']")
        check(visible_cases(driver) == [i for i, v in cases if v != "PASS"],
              "unticking PASS does not leave exactly the other scenarios")
        errors = driver.console_errors()
        check(not errors, f"console errors on the conform-client report: {errors}")
    yield (f"conform-client report at {inner} px: {len(cases)} scenarios with their citations, "
           f"the failure's transcript open with its decoy marked, source column ends at "
           f"{right:.0f} px")


if __name__ == "__main__":
    sys.exit(with_browser(check_client_report, "mblab-browser-client-"))
