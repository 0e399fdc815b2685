#!/bin/sh
# Interop: mbpoll (Modbus/TCP) through `mblab serve --gateway` to the reference device that
# `mblab serve --listen rtu://` runs on the other end of a socat pty pair. Units 1..10 are routed
# to the line; only unit 1 is there.
# Usage: test_serial_gateway.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-serial-gateway.XXXXXX")
. "$HERE/serial_lib.sh"

start_pty_pair line
start_mblab device serve reference --listen "rtu://$WORK/line-a?baud=19200"
start_mblab gateway serve --listen tcp://127.0.0.1:0 \
    --gateway "rtu://$WORK/line-b?baud=19200&units=1-10&timeout=300"
PORT=$(tcp_port gateway)
[ -n "$PORT" ] || fail "no port in: $(cat "$WORK/gateway.out")"

# mbpoll MBPOLL_ARGS...: output in $WORK/mbpoll.out, exit status in $STATUS.
mbpoll_run() {
    STATUS=0
    timeout 30 mbpoll -m tcp -p "$PORT" -1 -o 5 "$@" >"$WORK/mbpoll.out" 2>&1 || STATUS=$?
}

# mbpoll references are 1-based: -r 201 is holding register 200.
mbpoll_run -a 1 -r 201 127.0.0.1 4660 22136
[ "$STATUS" -eq 0 ] || { cat "$WORK/mbpoll.out" >&2; fail "mbpoll write through the gateway"; }
mbpoll_run -a 1 -r 201 -c 2 127.0.0.1
got=$(sed -n 's/^\[\([0-9]*\)\]:[[:space:]]*\(.*\)$/\1=\2/p' "$WORK/mbpoll.out" | tr '\n' ' ')
[ "$got" = "201=4660 202=22136 " ] || fail "read back through the gateway: '$got'"

# Unit 5 is routed but nothing answers: exception 0B after the 300 ms timeout.
mbpoll_run -a 5 -r 1 127.0.0.1
[ "$STATUS" -ne 0 ] && grep -q "Target device failed to respond" "$WORK/mbpoll.out" ||
    { cat "$WORK/mbpoll.out" >&2; fail "unit 5 should answer 0B"; }
# Unit 20 is not routed: exception 0A.
mbpoll_run -a 20 -r 1 127.0.0.1
[ "$STATUS" -ne 0 ] && grep -q "Gateway path unavailable" "$WORK/mbpoll.out" ||
    { cat "$WORK/mbpoll.out" >&2; fail "unit 20 should answer 0A"; }

stop_mblab gateway
stop_mblab device
echo "PASS"
