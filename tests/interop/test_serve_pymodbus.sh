#!/bin/sh
# Interop: pymodbus 3.0's TCP client against `mblab serve`, every function code it has, with the
# session captured by tshark and checked by Wireshark's Modbus/TCP dissector.
# Usage: test_serve_pymodbus.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-pymodbus.XXXXXX")
. "$HERE/serve_lib.sh"

start_serve
start_capture
/usr/bin/python3 "$HERE/pymodbus_client.py" "$SERVE_PORT" || fail "pymodbus client"
check_capture
stop_serve
echo "PASS"
