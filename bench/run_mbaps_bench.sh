#!/usr/bin/env bash
# What Modbus/TCP Security costs (docs/security.md "Benchmark"), side by side in one run:
#   1. answers/s of FC 03 x125 reads over tcp:// and mbaps:// (mblab load --no-tests against one
#      mblab serve of each) at 1 and 16 connections;
#   2. full and resumed TLS handshakes per second, measured by openssl s_time against mblab serve
#      and, for scale, against openssl s_server with the same certificates;
#   3. the server's memory per idle connection, tcp:// and mbaps://, from its RSS before and after
#      N idle connections (bench/idle_tls_connections.py).
#   bench/run_mbaps_bench.sh [MBLAB] [SECONDS]     (default build/mblab, 5 s per measurement)
# Environment: IDLE (connections for the memory figure, default 500); ROUNDS (default 1): the
# answers/s are the median of that many rounds; BASE=OTHER_MBLAB adds a row per connection count
# from another build (its own servers and client) in the same rounds, so before and after a change
# share the machine's moment.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
mblab=${1:-$here/../build/mblab}
seconds=${2:-5}
idle=${IDLE:-500}
rounds=${ROUNDS:-1}
base=${BASE:-}
[[ -x $mblab ]] || { echo "run_mbaps_bench: no mblab binary at $mblab" >&2; exit 2; }
[[ -z $base || -x $base ]] || { echo "run_mbaps_bench: no mblab binary at BASE=$base" >&2; exit 2; }

work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT

"$mblab" pki "$work/pki" >/dev/null
pki=$work/pki
client=(--cert "$pki/client-Administrator.pem" --key "$pki/client-Administrator.key" --ca "$pki/ca.pem")

# serve BINARY URL: starts BINARY serve on an ephemeral port, sets $port and $pid.
serve() {
    local out=$work/serve.$RANDOM
    local security=()
    [[ $2 == mbaps://* ]] && security=(--cert "$pki/server.pem" --key "$pki/server.key" --ca "$pki/ca.pem")
    "$1" serve --listen "$2" "${security[@]}" --max-connections 0 >"$out" 2>/dev/null &
    pid=$!
    pids+=("$pid")
    for _ in $(seq 100); do
        port=$(sed -nE 's/.* on [a-z]+:\/\/127\.0\.0\.1:([0-9]+).*/\1/p' "$out")
        [[ -n $port ]] && return 0
        sleep 0.1
    done
    echo "run_mbaps_bench: $1 serve $2 did not start" >&2
    exit 1
}
serve "$mblab" mbaps://127.0.0.1:0
tls_port=$port tls_pid=$pid
serve "$mblab" tcp://127.0.0.1:0
plain_port=$port plain_pid=$pid
if [[ -n $base ]]; then
    serve "$base" mbaps://127.0.0.1:0
    base_tls_port=$port
    serve "$base" tcp://127.0.0.1:0
    base_plain_port=$port
fi

answers() {  # BINARY TARGET CONNECTIONS [ARGS...]
    local binary=$1 target=$2 connections=$3
    shift 3
    "$binary" load "$target" --no-tests --duration "${seconds}s" --connections "$connections" \
        --mix fc3:125=100 --threads 1 --json "$work/load.json" "$@" >/dev/null 2>&1 || true
    python3 -c 'import json,sys; print(round(json.load(open(sys.argv[1]))["nodes"][0]["requests_per_s"]))' "$work/load.json"
}
median() { printf '%s\n' "$@" | sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }

declare -A plain_runs tls_runs round_costs
builds=(mblab)
[[ -n $base ]] && builds+=(base)
for ((round = 1; round <= rounds; round++)); do
    # Every other round runs the builds in the reverse order: a build is not always the one that
    # runs first, on a machine whose speed drifts from one run to the next.
    order=("${builds[@]}")
    ((round % 2 == 0)) && mapfile -t order < <(printf '%s\n' "${builds[@]}" | tac)
    for connections in 1 16; do
        for build in "${order[@]}"; do
            if [[ $build == base ]]; then
                binary=$base p=$base_plain_port t=$base_tls_port
            else
                binary=$mblab p=$plain_port t=$tls_port
            fi
            key=$build/$connections
            plain=$(answers "$binary" "tcp://127.0.0.1:$p" "$connections")
            tls=$(answers "$binary" "mbaps://localhost:$t" "$connections" "${client[@]}")
            plain_runs[$key]+=" $plain"
            tls_runs[$key]+=" $tls"
            # The round's own cost: its tcp:// and mbaps:// runs are seconds apart.
            round_costs[$key]+=" $(python3 -c "print(round(100 * (1 - $tls / $plain), 1))")"
        done
    done
done

echo "== answers/s, FC 03 x125, ${seconds} s each, median of $rounds round(s)"
echo "(TLS cost: from the medians; by round: the median, lowest and highest of each round's own)"
printf '%-8s %-12s %12s %12s %8s  %s\n' build connections tcp:// mbaps:// "TLS cost" "by round"
for connections in 1 16; do
    for build in "${builds[@]}"; do
        key=$build/$connections
        # shellcheck disable=SC2086 # the runs are words on purpose
        plain=$(median ${plain_runs[$key]})
        # shellcheck disable=SC2086
        tls=$(median ${tls_runs[$key]})
        # shellcheck disable=SC2086
        by_round=$(printf '%s\n' ${round_costs[$key]} | sort -n |
            awk '{ v[NR] = $1 } END { printf "%.1f%% (%.1f-%.1f)", v[int((NR + 1) / 2)], v[1], v[NR] }')
        printf '%-8s %-12s %12s %12s %7.1f%%  %s\n' "$build" "$connections" "$plain" "$tls" \
            "$(python3 -c "print(100 * (1 - $tls / $plain))")" "$by_round"
    done
done

handshakes() {  # PORT -new|-reuse [-tls1_2]
    openssl s_time -connect "127.0.0.1:$1" "${@:2}" -time "$seconds" \
        -cert "$pki/client-Administrator.pem" -key "$pki/client-Administrator.key" \
        -CAfile "$pki/ca.pem" 2>/dev/null |
        sed -nE 's/^([0-9]+) connections in ([0-9.]+) real seconds.*/\1 \2/p' | tail -1 |
        awk '{ printf "%.0f", $1 / $2 }'
}
# -www: s_server answers each connection by itself; without it, it reads its stdin, which a
# background job does not have, and ends after the first connection.
openssl s_server -accept 127.0.0.1:0 -cert "$pki/server.pem" -key "$pki/server.key" \
    -CAfile "$pki/ca.pem" -Verify 1 -verify_return_error -naccept 1000000 -www \
    >"$work/s_server.out" 2>&1 &
pids+=($!)
s_server_port=
for _ in $(seq 100); do
    s_server_port=$(sed -nE 's/^ACCEPT .*:([0-9]+)\s*$/\1/p' "$work/s_server.out" 2>/dev/null | head -1 || true)
    [[ -n $s_server_port ]] && break
    sleep 0.1
done
echo
# s_time ends a connection before a TLS 1.3 session ticket comes, so resumption is timed on 1.2.
echo "== TLS handshakes per second (openssl s_time, ${seconds} s each; client certificate sent)"
printf '%-22s %12s %12s %16s\n' server "full TLS 1.3" "full TLS 1.2" "resumed TLS 1.2"
row() {
    printf '%-22s %12s %12s %16s\n' "$1" "$(handshakes "$2" -new)" "$(handshakes "$2" -new -tls1_2)" \
        "$(handshakes "$2" -reuse -tls1_2)"
}
row "mblab serve" "$tls_port"
[[ -n $s_server_port ]] && row "openssl s_server" "$s_server_port"

rss_kib() { sed -nE 's/^VmRSS:\s+([0-9]+) kB/\1/p' "/proc/$1/status"; }
per_connection() {  # PID PORT [CERT KEY CA]
    local pid=$1 port=$2
    shift 2
    local before after
    before=$(rss_kib "$pid")
    coproc HOLD { python3 "$here/idle_tls_connections.py" "$port" "$idle" "$@"; }
    read -r _ready _count <&"${HOLD[0]}"
    sleep 0.5
    after=$(rss_kib "$pid")
    exec {HOLD[1]}>&-
    wait "$HOLD_PID" 2>/dev/null || true
    python3 -c "print(f'{($after - $before) * 1024 / $idle:.0f}')"
}
echo
echo "== server memory per idle connection ($idle connections, RSS difference)"
printf '%-10s %10s\n' listen "bytes"
printf '%-10s %10s\n' tcp:// "$(per_connection "$plain_pid" "$plain_port")"
printf '%-10s %10s\n' mbaps:// "$(per_connection "$tls_pid" "$tls_port" "$pki/client-Administrator.pem" \
    "$pki/client-Administrator.key" "$pki/ca.pem")"
