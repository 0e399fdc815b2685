#!/bin/sh
# Write throughput of `mblab serve --state` with and without --durable: FC 06 and FC 16 (10
# registers) answers/s from `mblab load`, closed loop, 1 and 16 connections.
# Usage: bench/run_durable_bench.sh [MBLAB] [SECONDS]   (defaults: build/mblab, 5)
set -eu
MBLAB=$(realpath "${1:-$(dirname "$0")/../build/mblab}")
SECONDS_PER_RUN=${2:-5}
WORK=$(mktemp -d "${TMPDIR:-/var/tmp}/mblab-durable.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
PORT=15731
printf '%-8s %-10s %6s %12s\n' mix mode conns answers/s
for mix in fc6 fc16:10; do
    for mode in state durable; do
        for conns in 1 16; do
            rm -f "$WORK"/s.json*
            extra=""
            [ "$mode" = durable ] && extra="--durable"
            "$MBLAB" serve --listen tcp://127.0.0.1:$PORT --state "$WORK/s.json" $extra \
                >"$WORK/serve.log" 2>&1 &
            pid=$!
            sleep 0.5
            rate=$("$MBLAB" load tcp://127.0.0.1:$PORT --mix "$mix=100" --connections "$conns" \
                --duration "${SECONDS_PER_RUN}s" 2>&1 | sed -n 's/.*in [0-9.]* s (\([0-9]*\) answers\/s).*/\1/p')
            kill -TERM "$pid"
            wait "$pid" || true
            printf '%-8s %-10s %6s %12s\n' "$mix" "$mode" "$conns" "$rate"
        done
    done
done
