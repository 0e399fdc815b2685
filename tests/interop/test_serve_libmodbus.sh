#!/bin/sh
# Interop: libmodbus's client (tests/interop/libmodbus_client.c, built here) against
# `mblab serve`, every function libmodbus has, with the session checked by tshark.
# Usage: test_serve_libmodbus.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
BUILD=$2
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-libmodbus.XXXXXX")
. "$HERE/serve_lib.sh"

CLIENT="$BUILD/serve_libmodbus_client"
# shellcheck disable=SC2046 # pkg-config prints several words on purpose
cc -std=c11 -O2 -Wall -Wextra -Werror -o "$CLIENT" "$HERE/libmodbus_client.c" \
    $(pkg-config --cflags --libs libmodbus) || fail "cannot build libmodbus_client.c"

start_serve
start_capture
"$CLIENT" "$SERVE_PORT" || fail "libmodbus client"
check_capture
stop_serve
echo "PASS"
