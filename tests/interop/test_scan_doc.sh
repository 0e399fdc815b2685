#!/bin/sh
# docs/scan.md's example, run exactly as printed from the repository root: the instrument served,
# then scanned; what the scan prints must be what the document shows, and the file it writes must
# hold the keys the document shows.
# Usage: test_scan_doc.sh MBLAB BUILD_DIR
set -u
. "$(dirname "$0")/doc_example_lib.sh"
heading='# Learning a device'
out=$(mktemp)
run_doc_example docs/scan.md "$heading" scan "$out" ||
    { echo "FAIL: the example exited $?"; exit 1; }
want=$(awk -v h="$heading" 'index($0, h) == 1 {on=1} on&&/^prints/{p=1;next} p&&/^```$/{if(g)exit; g=1;next} g{print}' docs/scan.md)
keys=$(awk -v h="$heading" 'index($0, h) == 1 {on=1} on&&/^```toml/{g=1;next} g&&/^$/{exit} g{print}' docs/scan.md)
[ -n "$want" ] && [ -n "$keys" ] || { echo "FAIL: the example's output is not found"; exit 1; }
[ "$(cat "$out")" = "$want" ] || { printf 'FAIL: expected\n%s\n' "$want"; exit 1; }
got=$(grep -v '^#' /tmp/instrument.toml | grep -v '^$')
[ "$got" = "$keys" ] || { printf 'FAIL: the file holds\n%s\nexpected\n%s\n' "$got" "$keys"; exit 1; }
rm -f "$out" /tmp/instrument.toml
echo "docs/scan.md example: as printed"
