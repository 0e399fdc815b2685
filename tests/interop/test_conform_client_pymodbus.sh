#!/bin/sh
# `mblab conform-client` grading pymodbus 3.0's ModbusTcpClient (Debian 12's python3-pymodbus),
# a client nobody here wrote: its verdicts are the ones docs/client-conformance.md records, each
# FAIL decided by the bytes the reason quotes.
# Over Modbus/TCP and over RTU on a pty pair.
# Usage: test_conform_client_pymodbus.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/conform_client_lib.sh"
/usr/bin/python3 -c 'import pymodbus' 2>/dev/null ||
    { echo "FAIL: python3-pymodbus is not installed (scripts/install-deps.sh)"; exit 1; }
out=$(mktemp)
trap 'rm -f "$out"' EXIT
# pymodbus 3.0 gives up connecting within a short timeout on a loaded machine: 1 s.
"$MBLAB" conform-client --client-timeout 1s --client-retries 0 -- /usr/bin/python3 \
    "$HERE/pymodbus_read_client.py" '{host}' '{port}' '{unit}' '{address}' '{count}' 1 0 >"$out"
status=$?
want="tcp.2 N/A tcp.3 FAIL tcp.4 FAIL tcp.5.1 FAIL tcp.5.3 FAIL tcp.10 FAIL tcp.11 N/A"
expect_verdicts "$out" "$status" "$want" \
    'tcp.3 .*took the decoy 40100 from 5A 5B 00 00 00 07 01 03 04 9C A4 9C A5' \
    'tcp.4 .*reported an error instead of discarding' \
    'tcp.5.1 .*took the decoy 40100 from 00 01 00 00 00 07 01 04 04 9C A4 9C A5' \
    'tcp.5.3 .*took the decoy 40100 from 00 01 00 00 00 09 01 03 04 9C A4 9C A5 DE AD' \
    'tcp.10 .*took the decoy 40100 from 00 01 00 00 00 05 01 03 02 9C A4'

# ModbusSerialClient (RTU, even parity) on a pty pair: after another slave's answer its framer
# drops what it read and the call ends in "No Response received" though its own answer follows
# [SER 2.4.1].
"$MBLAB" conform-client --listen 'rtu:///dev/ptmx?baud=19200' --client-timeout 1s \
    --client-retries 0 -- /usr/bin/python3 "$HERE/pymodbus_read_client.py" '{device}' '{baud}' \
    '{unit}' '{address}' '{count}' 1 0 >"$out"
expect_line_verdicts "$out" $? "ser.4 FAIL ser.9 N/A" \
    'ser.4 .*reported an error instead of discarding.*No Response received'
echo "pymodbus under conform-client: as recorded"
