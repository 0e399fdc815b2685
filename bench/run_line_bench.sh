#!/bin/bash
# A serial line's use under `mblab load` against what its baud rate carries, with the reference
# device (`mblab serve`) at the other end of a socat pty pair and pace=1 on both ends (each side
# sends one character per character time, as a UART does). Prints, per baud rate, the
# characters per second that crossed the line, the limit (characters at the baud rate with t3.5
# between RTU frames) and their ratio, for the paced line and, beside it, for the same pty
# unpaced (memory speed, so over 100%).
#
# The paced figures are only as good as the machine's scheduling: a thread woken late leaves a
# silence that cuts a frame (the answer never comes) or a burst. As root the three processes
# run SCHED_FIFO (chrt) so that a busy machine disturbs them less; run it on an idle machine.
#
# Usage: bench/run_line_bench.sh [MBLAB] [SECONDS_PER_RUN]   (defaults: build/mblab, 10)
# BAUDS="9600 19200" narrows the run.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
MBLAB=$(realpath "${1:-$HERE/../build/mblab}")
RUN_SECONDS=${2:-10}
BAUDS=${BAUDS:-"9600 19200 38400 115200"}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-line-bench.XXXXXX")
PIDS=""
trap 'for p in $PIDS; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null; rm -rf "$WORK"' EXIT

RT=""
if [ "$(id -u)" = 0 ] && chrt -f 50 true 2>/dev/null; then RT="chrt -f 50"; fi

# run BAUD PACE: one load run; prints "chars/s limit/s share failures".
run() {
    local baud=$1 pace=$2 settings="baud=$1"
    [ "$pace" = 1 ] && settings="$settings&pace=1"
    rm -f "$WORK/a" "$WORK/b"
    $RT socat "pty,raw,echo=0,link=$WORK/a" "pty,raw,echo=0,link=$WORK/b" 2>/dev/null &
    local socat=$!
    for _ in $(seq 50); do [ -e "$WORK/b" ] && break; sleep 0.1; done
    $RT "$MBLAB" serve reference --listen "rtu://$WORK/a?$settings" >"$WORK/serve.out" 2>&1 &
    local serve=$!
    PIDS="$socat $serve"
    for _ in $(seq 50); do grep -q "^mblab serve: " "$WORK/serve.out" && break; sleep 0.1; done
    $RT "$MBLAB" load "rtu://$WORK/b?$settings" --duration "${RUN_SECONDS}s" --connections 1 \
        --timeout 3000 --json "$WORK/load.json" >/dev/null 2>&1 || true
    kill "$serve" "$socat" 2>/dev/null || true
    wait "$serve" "$socat" 2>/dev/null || true
    python3 - "$WORK/load.json" <<'PY'
import json, sys
node = json.load(open(sys.argv[1]))["nodes"][0]
line = node["line"]
print(f'{line["characters_per_s"]:.0f} {line["limit_per_s"]:.0f} {100 * line["share"]:.1f}% '
      f'{node["failures"]["total"]}')
PY
}

echo "mblab $("$MBLAB" --version | head -n 1); ${RUN_SECONDS} s per run; ${RT:-no real-time priority}"
printf '%-8s  %-34s  %-34s\n' "baud" "paced: chars/s limit/s use fails" "unpaced pty: chars/s limit/s use"
for baud in $BAUDS; do
    paced=$(run "$baud" 1)
    unpaced=$(run "$baud" 0 | cut -d' ' -f1-3)
    printf '%-8s  %-34s  %-34s\n' "$baud" "$paced" "$unpaced"
done
