#!/bin/bash
# Robustness tester speed: cases per second of `mblab fuzz` against `mblab serve` on loopback,
# with the liveness check after every case and after every 100, no rate limit. Each figure is
# the median of ROUNDS runs of CASES cases (the same seed, so the same cases).
#
# Usage: bench/run_fuzz_bench.sh [MBLAB] [CASES] [ROUNDS]   (defaults: build/mblab, 1000, 3)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
MBLAB=$(realpath "${1:-$HERE/../build/mblab}")
CASES=${2:-1000}
ROUNDS=${3:-3}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-fuzz-bench.XXXXXX")
SERVER_PID=""
trap '[ -n "$SERVER_PID" ] && kill "$SERVER_PID" 2>/dev/null; wait 2>/dev/null; rm -rf "$WORK"' EXIT

"$MBLAB" serve --listen tcp://127.0.0.1:0 >"$WORK/serve.out" 2>&1 &
SERVER_PID=$!
for _ in $(seq 100); do
    grep -q 'tcp://127.0.0.1:' "$WORK/serve.out" 2>/dev/null && break
    sleep 0.1
done
TARGET=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$WORK/serve.out" | head -1)
[ -n "$TARGET" ] || { echo "mblab serve did not start: $(cat "$WORK/serve.out")" >&2; exit 2; }

echo "mblab fuzz against mblab serve ($TARGET), $CASES cases, median of $ROUNDS runs"
for every in 1 100; do
    rates=()
    for round in $(seq "$ROUNDS"); do
        "$MBLAB" fuzz "$TARGET" --cases "$CASES" --rate 0 --check-every "$every" \
            --json "$WORK/run.json" >"$WORK/run.out" 2>&1 ||
            { echo "mblab fuzz failed:"; cat "$WORK/run.out"; exit 1; }
        rates+=("$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(round(d["cases"] * 1000 / d["elapsed_ms"]))' "$WORK/run.json")")
        : "$round"
    done
    median=$(printf '%s\n' "${rates[@]}" | sort -n | sed -n "$(((ROUNDS + 1) / 2))p")
    printf 'check every %-3s  %6s cases/s   (runs: %s)\n' "$every" "$median" "${rates[*]}"
done
