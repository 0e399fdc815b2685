#!/bin/sh
# The README's `mblab load` example, run exactly as printed from the repository root: two served
# reference devices (ready once the second, port 1503, is), no declarations, and the verdict must
# be PASS (exit 0).
# Usage: test_readme_load.sh MBLAB BUILD_DIR
set -u
. "$(dirname "$0")/doc_example_lib.sh"
out=$(mktemp)
run_doc_example README.md '## The interoperability test: `mblab load`' load "$out" 1503 ||
    { echo "FAIL: the README's load example exited $?"; exit 1; }
grep -q '^PASS' "$out" || { echo "FAIL: no PASS line"; exit 1; }
rm -f "$out"
echo "README load example: PASS"
