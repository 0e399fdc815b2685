#!/usr/bin/env bash
# User-space instructions per FC 03 x125 request, under callgrind: a figure that does not move
# with the machine's load, for changes too small for the throughput benchmarks to see.
#
# Each server runs under `valgrind --tool=callgrind --dump-instr=yes`; server_load warms it for 2 s, then, while
# server_load runs again, the counters are zeroed and SECONDS later dumped. Requests are counted
# as the server's calls to send() in the dumped window (one answer per request with one request
# in flight per connection), not by server_load, whose window is not the dump's.
#
# Usage: bench/run_instruction_count.sh [MBLAB] [CONNECTIONS] [SECONDS]  (defaults: build/mblab, 16, 5)
#   SERVERS="mblab canned" to choose (mblab, canned; base with BASE=path-to-another-mblab)
#   TLS=1: over mbaps:// (a lab PKI from `mblab pki`), the load from each build's own `mblab load`
#   (server_load speaks no TLS); the canned server has no TLS and is left out.
# Needs valgrind (apt-get install valgrind).
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
MBLAB=$(realpath "${1:-build/mblab}")
CONNECTIONS=${2:-16}
SECONDS_RUN=${3:-5}
TLS=${TLS:-}
if [ -n "$TLS" ]; then
    SERVERS=${SERVERS:-"mblab${BASE:+ base}"} WARM=4 SETTLE=2
else
    SERVERS=${SERVERS:-"mblab canned${BASE:+ base}"} WARM=2 SETTLE=0.5
fi
command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 2; }

WORK=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$WORK"' EXIT
cc -std=c11 -O2 -Wall -Wextra -o "$WORK/server_load" "$HERE/server_load.c"
cc -std=c11 -O2 -Wall -Wextra -o "$WORK/canned_server" "$HERE/canned_server.c"

# The port a server printed: mblab's "listening on tcp://127.0.0.1:PORT" (or mbaps://), canned's
# "port=PORT".
port_of() {
    sed -nE 's/.* on [a-z]+:\/\/127\.0\.0\.1:([0-9]+).*/\1/p; s/^port=([0-9]+)$/\1/p' "$1" | head -1
}
if [ -n "$TLS" ]; then
    "$MBLAB" pki "$WORK/pki" >/dev/null
    SERVE_TLS=(--cert "$WORK/pki/server.pem" --key "$WORK/pki/server.key" --ca "$WORK/pki/ca.pem")
fi
# load BINARY PORT SECONDS: closed-loop FC 03 x125 reads on CONNECTIONS connections.
load() {
    if [ -z "$TLS" ]; then
        "$WORK/server_load" 127.0.0.1 "$2" "$CONNECTIONS" "$3" >/dev/null
        return
    fi
    "$1" load "mbaps://127.0.0.1:$2" --cert "$WORK/pki/client-Administrator.pem" \
        --key "$WORK/pki/client-Administrator.key" --ca "$WORK/pki/ca.pem" --no-tests \
        --duration "$3s" --connections "$CONNECTIONS" --mix fc3:125=100 --threads 1 >/dev/null 2>&1 ||
        true  # its verdict (slow answers from a server under callgrind) is not the figure here
}

# How often send() ran in a callgrind dump made with --dump-instr=yes: the count of its first
# instruction. (Call arcs would not do: a server's main loop never returns, and the arcs from it
# lose their counts when the counters are zeroed.) Names are compressed to "(id)" after their
# first use.
sends_in() {
    awk '
        /^c?fn=/ {
            called = /^cfn=/
            id = $1; sub(/^c?fn=/, "", id); name = $0; sub(/^c?fn=\([0-9]+\) ?/, "", name)
            if (name != "") names[id] = name
            if (!called) first = (names[id] ~ /^(send|sendto|__libc_send|__send)$/)
            next
        }
        first && /^(0x|\+|-)/ { total += $NF; first = 0 }
        END { print total + 0 }' "$1"
}

echo "== user-space instructions per FC 03 x125 request ($CONNECTIONS connections${TLS:+, mbaps://}, ${SECONDS_RUN} s, callgrind)"
printf '%-8s %12s %16s %14s\n' server requests instructions per_request
for server in $SERVERS; do
    case $server in
        mblab | base)
            binary=$MBLAB
            [ "$server" = base ] && binary=$(realpath "$BASE")
            if [ -n "$TLS" ]; then
                cmd=("$binary" serve --listen mbaps://127.0.0.1:0 "${SERVE_TLS[@]}" --idle-timeout 0 --max-connections 20000)
            else
                cmd=("$binary" serve --listen tcp://127.0.0.1:0 --idle-timeout 0 --max-connections 20000)
            fi ;;
        canned) binary="" cmd=("$WORK/canned_server" 0) ;;
        *) echo "unknown server $server" >&2; exit 2 ;;
    esac
    out="$WORK/$server.out"
    valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file="$WORK/$server.cg" "${cmd[@]}" >"$out" 2>"$WORK/$server.err" &
    pid=$!
    port=""
    for _ in $(seq 150); do
        port=$(port_of "$out")
        [ -n "$port" ] && break
        sleep 0.2
    done
    [ -n "$port" ] || { echo "$server did not start: $(tail -2 "$WORK/$server.err")" >&2; exit 1; }
    # Warmed first (over TLS the handshakes under callgrind take seconds).
    load "$binary" "$port" "$WARM"
    # Zeroed and dumped while the load runs: a server idle in epoll_wait would take the command
    # only at its next request.
    load "$binary" "$port" $((SECONDS_RUN + 3)) &
    load=$!
    sleep "$SETTLE"
    callgrind_control -z "$pid" >/dev/null 2>&1
    sleep "$SECONDS_RUN"
    callgrind_control -d "$pid" >/dev/null 2>&1
    wait "$load"
    kill "$pid"
    wait "$pid" 2>/dev/null || true
    dump=$(ls "$WORK/$server.cg".* | sort -t. -k3 -n | tail -1)
    instructions=$(callgrind_annotate "$dump" 2>/dev/null | awk '/PROGRAM TOTALS/ { gsub(",", "", $1); print $1; exit }')
    requests=$(sends_in "$dump")
    [ "$requests" -gt 0 ] || { echo "$server: no send() counted in $dump" >&2; exit 1; }
    printf '%-8s %12d %16d %14d\n' "$server" "$requests" "$instructions" $((instructions / requests))
done
