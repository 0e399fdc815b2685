#!/bin/sh
# docs/robustness.md's "Learning from a capture" example, run exactly as printed from the
# repository root (it serves, captures mbpoll's reads with dumpcap, then fuzzes with --learn); the
# reconnaissance lines it prints must be the ones the document shows.
# Usage: test_robustness_learn_doc.sh MBLAB BUILD_DIR
set -u
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root" || exit 1
[ -x build/mblab ] || { echo "SKIP: build/mblab is not built here"; exit 0; }
for tool in dumpcap mbpoll; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool is not installed"; exit 0; }
done
[ "$(id -u)" = 0 ] || { echo "SKIP: capturing on lo needs root"; exit 0; }
section='## Learning from a capture'
block=$(awk -v h="$section" 'index($0, h) == 1 {on=1} on&&/^```sh/{grab=1;next} grab&&/^```/{exit} grab{print}' docs/robustness.md)
want=$(awk -v h="$section" 'index($0, h) == 1 {on=1} on&&/^prints/{p=1;next} p&&/^```$/{if(g)exit; g=1;next} g{print}' docs/robustness.md)
[ -n "$block" ] && [ -n "$want" ] || { echo "FAIL: the example is not found"; exit 1; }
out=$(mktemp)
# Its own process group, so that the device it serves in the background is stopped by that id.
setsid sh -c "$block" >"$out" 2>&1 &
group=$!
for _ in $(seq 600); do
    grep -q '^no finding\|^FINDING' "$out" && break
    kill -0 "$group" 2>/dev/null || break
    sleep 0.1
done
sleep 0.2
kill -TERM "-$group" 2>/dev/null
wait 2>/dev/null
cat "$out"
got=$(grep -E '^(mblab fuzz|reconnaissance|  liveness check|  answered at|no finding)' "$out")
rm -f "$out" /tmp/normal.pcapng
[ "$got" = "$want" ] || { printf 'FAIL: expected\n%s\n' "$want"; exit 1; }
echo "docs/robustness.md --learn example: as printed"
