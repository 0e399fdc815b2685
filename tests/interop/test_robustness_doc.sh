#!/bin/sh
# docs/robustness.md's example, run exactly as printed from the repository root: the reference
# device served, then fuzzed with a short budget; no finding (exit 0) and a JUnit report.
# Usage: test_robustness_doc.sh MBLAB BUILD_DIR
set -u
. "$(dirname "$0")/doc_example_lib.sh"
out=$(mktemp)
run_doc_example docs/robustness.md '# The robustness tester' fuzz "$out" ||
    { echo "FAIL: the example exited $?"; exit 1; }
grep -q '^no finding' "$out" || { echo "FAIL: no 'no finding' line"; exit 1; }
grep -q '<testcase classname="robustness" name="protocol-id"' /tmp/fuzz.xml ||
    { echo "FAIL: no JUnit report"; exit 1; }
rm -f "$out"
echo "docs/robustness.md example: no finding"
