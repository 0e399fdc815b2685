#!/bin/bash
# Whether the HTTP side slows the Modbus side: FC 03 of 125 registers at 16 closed-loop
# connections (bench/server_load.c) against `mblab serve` without --http, and with --http while
# the dashboard's event stream is open and /metrics is scraped every second. Alternating rounds,
# so a noisy moment on a shared machine hits one run of each.
#
# Usage: bench/run_http_bench.sh [MBLAB] [SECONDS_PER_RUN] [ROUNDS]   (defaults: build/mblab, 10, 3)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
MBLAB=$(realpath "${1:-$HERE/../build/mblab}")
RUN_SECONDS=${2:-10}
ROUNDS=${3:-3}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-http-bench.XXXXXX")
PIDS=()
trap 'for p in "${PIDS[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null; rm -rf "$WORK"' EXIT
cc -std=c11 -O2 -Wall -Wextra -o "$WORK/server_load" "$HERE/server_load.c"

free_port() {
    /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
wait_listening() {
    for _ in $(seq 100); do
        (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null && return 0
        sleep 0.1
    done
    echo "nothing listens on $1" >&2
    exit 1
}

for round in $(seq "$ROUNDS"); do
    for mode in without-http with-http; do
        port=$(free_port)
        http=$(free_port)
        args=(serve --listen "tcp://127.0.0.1:$port")
        [ $mode = with-http ] && args+=(--http "127.0.0.1:$http")
        "$MBLAB" "${args[@]}" >"$WORK/serve.out" 2>&1 &
        server=$!
        PIDS=("$server")
        wait_listening "$port"
        if [ $mode = with-http ]; then
            wait_listening "$http"
            curl -s -N "http://127.0.0.1:$http/api/events?unit=1&bank=holding_registers&start=0&count=20" \
                >"$WORK/events" &
            PIDS+=($!)
            (while true; do curl -s "http://127.0.0.1:$http/metrics" >/dev/null; sleep 1; done) &
            PIDS+=($!)
        fi
        result=$("$WORK/server_load" 127.0.0.1 "$port" 16 "$RUN_SECONDS")
        extra=""
        [ $mode = with-http ] && extra=" events=$(grep -c '^data:' "$WORK/events")"
        echo "round $round $mode: $result$extra"
        for p in "${PIDS[@]}"; do kill "$p" 2>/dev/null || true; done
        wait 2>/dev/null || true
        PIDS=()
    done
done
