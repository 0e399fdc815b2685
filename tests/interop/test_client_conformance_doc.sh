#!/bin/sh
# docs/client-conformance.md's example, run exactly as printed from the repository root: what
# conform-client prints must be what the document shows, but for the run's duration.
# Usage: test_client_conformance_doc.sh MBLAB BUILD_DIR
set -u
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root" || exit 1
[ -x build/mblab ] || { echo "SKIP: build/mblab is not built here"; exit 0; }
doc=docs/client-conformance.md
heading='## An example'
example=$(awk -v h="$heading" 'index($0, h) == 1 {on=1} on&&/^```sh/{g=1;next} g&&/^```/{exit} g{print}' "$doc")
want=$(awk -v h="$heading" 'index($0, h) == 1 {on=1} on&&/^prints/{p=1;next} p&&/^```$/{if(g)exit; g=1;next} g{print}' "$doc")
[ -n "$example" ] && [ -n "$want" ] || { echo "FAIL: the example is not found in $doc"; exit 1; }
got=$(sh -c "$example" 2>&1)
status=$?
[ "$status" = 0 ] || { printf 'FAIL: exit status %s\n%s\n' "$status" "$got"; exit 1; }
duration='s/ in [0-9.]+ m?s, / in D, /'
[ "$(printf '%s\n' "$got" | sed -E "$duration")" = "$(printf '%s\n' "$want" | sed -E "$duration")" ] ||
    { printf 'FAIL: printed\n%s\nexpected\n%s\n' "$got" "$want"; exit 1; }
echo "$doc example: as printed"
