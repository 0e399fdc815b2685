#!/bin/sh
# mblab's client against pymodbus's asyncio server, and pymodbus's client against the values
# mblab wrote: what one side writes, the other reads back.
# Usage: test_client_pymodbus.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/client_interop.sh"

start_peer /usr/bin/python3 "$HERE/pymodbus_conform_server.py" --lifetime 120
TARGET="tcp://127.0.0.1:$PEER_PORT"
PEER="/usr/bin/python3 $HERE/client_pymodbus_peer.py $PEER_PORT"


# mblab writes, pymodbus reads.
"$MBLAB" write "$TARGET" registers 10 7 0x0102 65535 > /dev/null
expect "pymodbus reads what mblab wrote" "$(printf '7\n258\n65535')" "$($PEER read-holding 10 3)"
"$MBLAB" write "$TARGET" coils 5 1 0 1 1 > /dev/null
expect "pymodbus reads the coils mblab wrote" "$(printf '1\n0\n1\n1')" "$($PEER read-coils 5 4)"
"$MBLAB" write "$TARGET" registers 40 -2 --type i16 > /dev/null
expect "a typed value mblab wrote" "65534" "$($PEER read-holding 40 1)"

# pymodbus writes, mblab reads.
$PEER write-holding 20 1 2 3
expect "mblab reads what pymodbus wrote" "$(printf 'address      raw     u16
20 (0x0014)  0x0001  1
21 (0x0015)  0x0002  2
22 (0x0016)  0x0003  3')" "$("$MBLAB" read "$TARGET" holding 20 3)"
$PEER write-float 30 3.5
expect "mblab reads a float pymodbus wrote" "$(printf 'address      raw            f32
30 (0x001E)  0x4060 0x0000  3.5')" "$("$MBLAB" read "$TARGET" holding 30 1 --type f32)"
$PEER write-coils 50 0 1 1
expect "mblab reads coils pymodbus wrote" "$(printf 'address      raw  value
50 (0x0032)  0    off
51 (0x0033)  1    on
52 (0x0034)  1    on')" "$("$MBLAB" read "$TARGET" coils 50 3)"

# Device identification across pymodbus's answer.
expect "devid against pymodbus" "$(printf '0x00  vendor name           pymodbus
0x01  product code          PM
0x02  major minor revision  3.0.0')" "$("$MBLAB" devid "$TARGET" | tail -n 3)"

# An exception pymodbus answers is shown by name, exit status 1.
set +e
"$MBLAB" raw "$TARGET" 41 00 > "$WORK/raw.out" 2> "$WORK/raw.err"
status=$?
set -e
expect "an unknown function code is exit status 1" "1" "$status"
expect "and named" "mblab raw: exception 01 illegal function: the device does not support function 0x41" \
    "$(cat "$WORK/raw.err")"
