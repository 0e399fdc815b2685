#!/usr/bin/env bash
# The load generator's own ceiling (docs/load.md "Benchmark"). Against one reference server
# (`mblab serve`), in the same run:
#   1. a minimal C epoll client (bench/load_epoll_client.c: closed loop, one FC 03 request)
#      and `mblab load --no-tests` with the same request, 16 connections each, in alternating
#      rounds; mblab load's median answers/s must be at least 90 % of the C client's median;
#   2. mblab load's answers/s and latency at 1, 16, 256 and 1000 connections, and at 16
#      connections with --pipeline 8 (the C client's rate beside each, for scale).
# Prints a table; exits 1 when the 90 % goal is missed.
#
#   bench/run_load_bench.sh [MBLAB] [SECONDS]
#     MBLAB    the mblab binary (default: build/mblab beside this script's repository)
#     SECONDS  length of each measurement (default 5)
# Environment: QUANTITY (registers per FC 03 read, default 125), ROUNDS (default 5),
# PORT (default 15020).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
mblab=${1:-$here/../build/mblab}
seconds=${2:-5}
quantity=${QUANTITY:-125}
rounds=${ROUNDS:-5}
port=${PORT:-15020}
[[ -x $mblab ]] || { echo "run_load_bench: no mblab binary at $mblab" >&2; exit 2; }

work=$(mktemp -d)
server_pid=
cleanup() {
    if [[ -n $server_pid ]]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
    rm -rf "$work"
}
trap cleanup EXIT

cc -O2 -o "$work/load_epoll_client" "$here/load_epoll_client.c"

"$mblab" serve --listen "tcp://127.0.0.1:$port" --max-connections 0 --max-outstanding 64 \
    >"$work/serve.out" 2>&1 &
server_pid=$!
for _ in $(seq 50); do
    grep -q "stop with Ctrl-C" "$work/serve.out" 2>/dev/null && break
    sleep 0.1
done
grep -q "stop with Ctrl-C" "$work/serve.out" || { cat "$work/serve.out" >&2; exit 2; }

# answers/s of the C client: CONNECTIONS [PIPELINE]
c_client() { "$work/load_epoll_client" 127.0.0.1 "$port" "$1" "$seconds" "$quantity" "${2:-1}"; }

# answers/s p50 p99 p99.9 (ms) of mblab load: CONNECTIONS [PIPELINE]
mblab_load() {
    "$mblab" load "tcp://127.0.0.1:$port" --no-tests --connections "$1" --pipeline "${2:-1}" \
        --mix "fc3:$quantity" --duration "${seconds}s" --json "$work/load.json" >/dev/null
    /usr/bin/python3 - "$work/load.json" <<'PY'
import json, sys
node = json.load(open(sys.argv[1]))["nodes"][0]
l = node["latency_ms"]
print(f'{node["requests_per_s"]:.0f} {l["p50"]:.3f} {l["p99"]:.3f} {l["p99_9"]:.3f} {node["failures"]["total"]}')
PY
}

c_rates=()
m_rates=()
echo "round  C epoll client (answers/s)  mblab load (answers/s)   [16 connections, FC 03 x $quantity]"
for round in $(seq "$rounds"); do
    # Alternate who goes first, so a change in the machine's load favours neither.
    if (( round % 2 )); then
        c=$(c_client 16)
        read -r m _ <<<"$(mblab_load 16)"
    else
        read -r m _ <<<"$(mblab_load 16)"
        c=$(c_client 16)
    fi
    printf "%5s  %26s  %22s\n" "$round" "$c" "$m"
    c_rates+=("$c")
    m_rates+=("$m")
done
# The goal is judged on the medians, which one lucky or unlucky round does not move.
read -r median_c median_m best_c best_m ratio < <(/usr/bin/python3 - "${c_rates[*]}" "${m_rates[*]}" <<'PY'
import statistics, sys
c = [float(x) for x in sys.argv[1].split()]
m = [float(x) for x in sys.argv[2].split()]
mc, mm = statistics.median(c), statistics.median(m)
print(f"{mc:.0f} {mm:.0f} {max(c):.0f} {max(m):.0f} {100 * mm / mc:.1f}")
PY
)
echo "median: C $median_c, mblab load $median_m: $ratio % of the C client (goal: at least 90 %)"
echo "best:   C $best_c, mblab load $best_m"

echo
echo "connections  pipeline  mblab answers/s  p50 ms  p99 ms  p99.9 ms  failures  C client answers/s"
for setting in "1 1" "16 1" "256 1" "1000 1" "16 8"; do
    read -r conns depth <<<"$setting"
    read -r rate p50 p99 p999 failures <<<"$(mblab_load "$conns" "$depth")"
    c=$(c_client "$conns" "$depth")
    printf "%11s  %8s  %15s  %6s  %6s  %8s  %8s  %18s\n" "$conns" "$depth" "$rate" "$p50" "$p99" \
        "$p999" "$failures" "$c"
done

/usr/bin/python3 -c "import sys; sys.exit(0 if $median_m >= 0.9 * $median_c else 1)"
