#!/bin/bash
# Server throughput: mblab serve against libmodbus's server, pymodbus's asyncio server and a
# canned-answer epoll server (the ceiling), with 1, 16 and 1000 closed-loop connections each
# reading 125 holding registers (FC 03). Then mblab's resident memory with 10,000 idle
# connections. Prints a table; run it on an otherwise idle machine.
#
# Each figure is the median of ROUNDS runs; a round runs every server once at each connection
# count, so a noisy moment on a shared machine hits one run of each, not all runs of one server.
#
# Usage: bench/run_server_bench.sh [MBLAB] [SECONDS_PER_RUN] [ROUNDS]   (defaults: build/mblab, 5, 3)
# SERVERS="mblab libmodbus" CONNECTIONS=1 narrow the run (mblab must stay in SERVERS); SKIP_RSS=1
# leaves out the memory measurement. BASE=OTHER_MBLAB adds a server "base" run from another build
# in the same rounds: before and after a change, side by side, each time beside the same ceiling.
# Server "bare" is bench/bare_mbap_server from MBLAB's build (ninja bare_mbap_server): mblab's own
# session core and reference device in canned_server.c's loop, to split mblab's distance to the
# ceiling into the Modbus work (bare / canned) and the run loop (mblab / bare).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
MBLAB=$(realpath "${1:-$HERE/../build/mblab}")
RUN_SECONDS=${2:-5}
ROUNDS=${3:-3}
TOOLS=$(dirname "$MBLAB")/bench-tools
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-bench.XXXXXX")
SERVER_PID=""
trap '[ -n "$SERVER_PID" ] && kill "$SERVER_PID" 2>/dev/null; wait 2>/dev/null; rm -rf "$WORK"' EXIT

# 10,000 idle connections need 10,000 descriptors in the server and in the client.
ulimit -n "$(ulimit -Hn)" 2>/dev/null || true
[ "$(ulimit -n)" -ge 10100 ] || { echo "need ulimit -n >= 10100 (have $(ulimit -n))" >&2; exit 2; }

mkdir -p "$TOOLS"
cc -std=c11 -O2 -Wall -Wextra -o "$TOOLS/server_load" "$HERE/server_load.c"
cc -std=c11 -O2 -Wall -Wextra -o "$TOOLS/canned_server" "$HERE/canned_server.c"
# shellcheck disable=SC2046 # pkg-config prints several words on purpose
cc -std=c11 -O2 -Wall -Wextra -o "$TOOLS/libmodbus_server" "$HERE/libmodbus_server.c" \
    $(pkg-config --cflags --libs libmodbus)

free_port() {
    /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
wait_listening() {
    for _ in $(seq 100); do
        (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null && return 0
        sleep 0.1
    done
    echo "server on port $1 did not start" >&2
    return 1
}
# wait_line FILE SED_EXPR: the first match of SED_EXPR in FILE once the server printed it.
wait_line() {
    for _ in $(seq 100); do
        value=$(sed -n "$2" "$1" | head -1)
        [ -n "$value" ] && { echo "$value"; return 0; }
        sleep 0.1
    done
    return 1
}

# start_server NAME: sets SERVER_PID and PORT. $PIN, when set, prefixes the server's command.
start_server() {
    case $1 in
        mblab | base)
            binary=$MBLAB
            [ "$1" = base ] && binary=$BASE
            $PIN "$binary" serve --listen tcp://127.0.0.1:0 --max-connections 20000 --idle-timeout 0 \
                >"$WORK/server.out" 2>&1 &
            SERVER_PID=$!
            PORT=$(wait_line "$WORK/server.out" 's/.* on tcp:\/\/127\.0\.0\.1:\([0-9]*\).*/\1/p') ;;
        bare)
            $PIN "$(dirname "$MBLAB")/bench/bare_mbap_server" 0 >"$WORK/server.out" 2>&1 &
            SERVER_PID=$!
            PORT=$(wait_line "$WORK/server.out" 's/^port=//p') ;;
        canned)
            $PIN "$TOOLS/canned_server" 0 >"$WORK/server.out" 2>&1 &
            SERVER_PID=$!
            PORT=$(wait_line "$WORK/server.out" 's/^port=//p') ;;
        libmodbus)
            PORT=$(free_port)
            $PIN "$TOOLS/libmodbus_server" "$PORT" >"$WORK/server.out" 2>&1 &
            SERVER_PID=$!
            wait_listening "$PORT" ;;
        pymodbus)
            PORT=$(free_port)
            $PIN /usr/bin/python3 "$HERE/pymodbus_server.py" "$PORT" >"$WORK/server.out" 2>&1 &
            SERVER_PID=$!
            wait_listening "$PORT" ;;
    esac
}
stop_server() {
    kill "$SERVER_PID" 2>/dev/null || true
    wait "$SERVER_PID" 2>/dev/null || true
    SERVER_PID=""
}
field() { sed -n "s/.*$1=\([0-9]*\).*/\1/p" <<<"$2"; }

SERVERS=${SERVERS:-mblab libmodbus pymodbus canned}
BASE=${BASE:+$(realpath "$BASE")}
[ -n "$BASE" ] && [[ " $SERVERS " != *" base "* ]] && SERVERS="$SERVERS base"
# "1/1core" runs the server and the load generator on core 0 only. Across two cores every round
# trip of a single connection pays two cross-core wake-ups (about 70 us in a VM), which hides
# what the servers themselves cost; on one core that cost is what remains.
CONNECTIONS=${CONNECTIONS:-1 1/1core 16 1000}
declare -A RUNS ROUND_RPS PAIRED
for round in $(seq "$ROUNDS"); do
    # Every other round runs the servers in the reverse order: a run is not always the one
    # after the same other server.
    order=$SERVERS
    [ $((round % 2)) -eq 0 ] && order=$(tr ' ' '\n' <<<"$SERVERS" | tac | tr '\n' ' ')
    for n in $CONNECTIONS; do
        for server in $order; do
            PIN=""
            [[ $n == */1core ]] && PIN="taskset -c 0"
            start_server "$server"
            if result=$($PIN "$TOOLS/server_load" 127.0.0.1 "$PORT" "${n%%/*}" "$RUN_SECONDS" 2>&1); then
                RUNS[$server.$n]+="$(field rps "$result") $(field p50_us "$result") $(field p99_us "$result")"$'\n'
                ROUND_RPS[$server.$n]=$(field rps "$result")
            else
                echo "$server, $n connections, round $round: $result" >&2
            fi
            stop_server
        done
        # mblab against each server in this round: runs seconds apart share the machine's state,
        # so these ratios hold still when the machine's speed drifts between rounds.
        for server in $SERVERS; do
            a=${ROUND_RPS[mblab.$n]:-0} b=${ROUND_RPS[$server.$n]:-0}
            [ "$a" -gt 0 ] && [ "$b" -gt 0 ] &&
                PAIRED[$server.$n]+="$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.4f", a / b }')"$'\n'
        done
        ROUND_RPS=()
    done
done

# The run with the median req/s of a server at a connection count: "rps p50 p99".
median_run() {
    local runs=${RUNS[$1]:-}
    [ -z "$runs" ] && { echo "0 - -"; return; }
    sort -n <<<"${runs%$'\n'}" | awk '{ line[NR] = $0 } END { print line[int((NR + 1) / 2)] }'
}
declare -A RPS P50 P99
for server in $SERVERS; do
    for n in $CONNECTIONS; do
        read -r "RPS[$server.$n]" "P50[$server.$n]" "P99[$server.$n]" < <(median_run "$server.$n")
    done
done

# The median of a server's per-round ratios, as "0.93x (0.88-0.97)": median, lowest, highest.
paired() {
    local ratios=${PAIRED[$1]:-}
    [ -z "$ratios" ] && { echo "-"; return; }
    sort -n <<<"${ratios%$'\n'}" |
        awk '{ r[NR] = $1 } END { printf "%.2fx (%.2f-%.2f)", r[int((NR + 1) / 2)], r[1], r[NR] }'
}

echo
echo "FC 03 x125, closed loop, median of $ROUNDS runs of ${RUN_SECONDS}s ($(nproc) cores; client and server share them)"
echo "(\"mblab / it\": the medians' ratio; \"paired\": the median, lowest and highest of the rounds' ratios)"
printf "%-10s %8s %10s %8s %8s %12s  %s\n" server conns "req/s" "p50 us" "p99 us" "mblab / it" paired
for n in $CONNECTIONS; do
    for server in $SERVERS; do
        rps=${RPS[$server.$n]}
        ratio="-"
        [ "$rps" -gt 0 ] && ratio=$(awk -v a="${RPS[mblab.$n]}" -v b="$rps" 'BEGIN { printf "%.2fx", a / b }')
        printf "%-10s %8s %10s %8s %8s %12s  %s\n" "$server" "$n" "$rps" "${P50[$server.$n]}" \
            "${P99[$server.$n]}" "$ratio" "$(paired "$server.$n")"
    done
done

[ -n "${SKIP_RSS:-}" ] && exit 0
# Resident memory of mblab serve, before and with 10,000 idle connections.
rss_kb() { sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$1/status"; }
PIN=""
start_server mblab
before=$(rss_kb "$SERVER_PID")
"$TOOLS/server_load" 127.0.0.1 "$PORT" 10000 --idle "$WORK/ready" &
client=$!
for _ in $(seq 600); do [ -f "$WORK/ready" ] && break; sleep 0.1; done
sleep 1
with=$(rss_kb "$SERVER_PID")
kill -TERM "$client"
wait "$client" || true
stop_server
echo
echo "mblab serve RSS: ${before} kB idle, ${with} kB with 10000 idle connections" \
    "($(( (with - before) * 1024 / 10000 )) bytes per connection)"
