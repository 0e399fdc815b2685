#!/bin/sh
# `mblab conform-client` grading a small libmodbus 3.1.6 client (libmodbus_read_client.c, built
# here against Debian's libmodbus-dev) over Modbus/TCP and over RTU on a pty pair: its verdicts
# are the ones docs/client-conformance.md records, each FAIL decided by what the reason quotes.
# Usage: test_conform_client_libmodbus.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/conform_client_lib.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
client="$work/libmodbus_read_client"
cc -std=c11 -O2 -Wall -Wextra -Werror -o "$client" "$HERE/libmodbus_read_client.c" \
    $(pkg-config --cflags --libs libmodbus) || { echo "FAIL: cannot build libmodbus_read_client.c"; exit 1; }

# libmodbus checks the transaction id and the unit only to report an error, and reads a frame by
# the length its function code implies, so extra bytes after it go unseen.
"$MBLAB" conform-client --client-timeout 300ms --client-retries 0 -- \
    "$client" tcp '{host}' '{port}' '{unit}' '{address}' '{count}' >"$work/tcp.txt"
expect_verdicts "$work/tcp.txt" $? "tcp.2 N/A tcp.3 FAIL tcp.4 FAIL tcp.5.3 FAIL tcp.11 N/A" \
    'tcp.3 .*reported an error instead of discarding.*Invalid data' \
    'tcp.4 .*took the decoy 40100 from 00 01 00 00 00 07 02 03 04 9C A4 9C A5' \
    'tcp.5.3 .*took the decoy 40100 from 00 01 00 00 00 09 01 03 04 9C A4 9C A5 DE AD' \
    'tcp.6.02 .*an error naming the code'

# On a line it gives up at another slave's answer instead of waiting on for its own.
"$MBLAB" conform-client --listen 'rtu:///dev/ptmx?baud=19200' --client-timeout 300ms \
    --client-retries 0 -- "$client" rtu '{device}' '{baud}' '{unit}' '{address}' '{count}' \
    >"$work/rtu.txt"
expect_line_verdicts "$work/rtu.txt" $? "ser.4 FAIL ser.9 N/A" \
    'ser.4 .*reported an error instead of discarding.*Response not from requested slave' \
    'ser.6.04 .*an error naming the code'
echo "the libmodbus client under conform-client: as recorded"
