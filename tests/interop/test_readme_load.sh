#!/bin/sh
# The README's `mblab load` example, run exactly as printed from the repository root: two served
# reference devices, no declarations, and the verdict must be PASS (exit 0).
# Usage: test_readme_load.sh MBLAB BUILD_DIR
set -u
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root" || exit 1
[ -x build/mblab ] || { echo "SKIP: build/mblab is not built here"; exit 0; }
block=$(awk '/^## The interoperability test: `mblab load`/{on=1} on&&/^```sh/{grab=1;next} grab&&/^```/{exit} grab{print}' README.md)
serve=$(printf '%s\n' "$block" | grep '^build/mblab serve ')
load=$(printf '%s\n' "$block" | grep '^build/mblab load ')
[ -n "$serve" ] && [ -n "$load" ] || { echo "FAIL: the README's load example is not found"; exit 1; }
serve=${serve% &}
out=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$out"' EXIT
sh -c "exec $serve" >"$out/serve.out" 2>"$out/serve.err" &
pid=$!
for _ in $(seq 100); do
    grep -q 1503 "$out/serve.out" 2>/dev/null && break
    sleep 0.1
done
sh -c "$load" >"$out/load.out" 2>&1
status=$?
cat "$out/load.out"
[ "$status" = 0 ] || { echo "FAIL: the README's load example exited $status"; cat "$out/serve.err"; exit 1; }
grep -q '^PASS' "$out/load.out" || { echo "FAIL: no PASS line"; exit 1; }
echo "README load example: PASS"
