#!/bin/sh
# Interop: pymodbus 3.0 masters against `mblab serve` on serial links: RTU and ASCII on a socat
# pty pair at 9600 and 115200 baud, and RTU frames over TCP (rtu+tcp://). Each writes registers
# and coils and reads them back.
# Usage: test_serial_pymodbus.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-serial-pymodbus.XXXXXX")
. "$HERE/serial_lib.sh"

EXPECTED="registers [4660, 65535, 255, 7, 65280]
coils [True, False, True, True, False, False, True, True, True, True]"

# master KIND WHERE NUMBER: runs the pymodbus master and checks what it read back.
master() {
    got=$(timeout 60 /usr/bin/python3 "$HERE/pymodbus_serial_master.py" "$@" 2>&1) ||
        fail "pymodbus $1 master: $got"
    [ "$got" = "$EXPECTED" ] || fail "pymodbus $1 master read back: $got"
}

for baud in 9600 115200; do
    start_pty_pair "rtu$baud"
    start_mblab rtu serve reference --listen "rtu://$WORK/rtu$baud-a?baud=$baud"
    master rtu "$WORK/rtu$baud-b" "$baud"
    stop_mblab rtu
    # Pseudo-terminals take only 8 data bits ([SER]'s ASCII default is 7).
    start_pty_pair "ascii$baud"
    start_mblab ascii serve reference --listen "ascii://$WORK/ascii$baud-a?baud=$baud&data=8"
    master ascii "$WORK/ascii$baud-b" "$baud"
    stop_mblab ascii
done

start_mblab rtutcp serve reference --listen rtu+tcp://127.0.0.1:0
PORT=$(tcp_port rtutcp)
[ -n "$PORT" ] || fail "no port in: $(cat "$WORK/rtutcp.out")"
master rtu+tcp 127.0.0.1 "$PORT"
stop_mblab rtutcp
echo "PASS"
