#!/bin/sh
# Interop: mbpoll writes registers and coils to `mblab serve` and reads them back.
# Usage: test_serve_mbpoll.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-mbpoll.XXXXXX")
. "$HERE/serve_lib.sh"

# mbpoll addresses are 1-based: -r 101 is address 100.
mbpoll_run() {
    mbpoll -m tcp -p "$SERVE_PORT" -a 1 -1 -o 5 "$@" >"$WORK/mbpoll.out" 2>&1 ||
        { cat "$WORK/mbpoll.out" >&2; fail "mbpoll $*"; }
}
# write TYPE REFERENCE VALUE...
write() {
    type=$1
    reference=$2
    shift 2
    mbpoll_run -t "$type" -r "$reference" -- 127.0.0.1 "$@"
}
# expect_read WANT TYPE REFERENCE COUNT: the "[reference]: value" lines must read WANT.
expect_read() {
    want=$1
    mbpoll_run -t "$2" -r "$3" -c "$4" 127.0.0.1
    got=$(sed -n 's/^\[\([0-9]*\)\]:[[:space:]]*\(.*\)$/\1=\2/p' "$WORK/mbpoll.out" | tr '\n' ' ')
    [ "$got" = "$want" ] || fail "mbpoll read of $2 at $3: '$got', expected '$want'"
}

start_serve
# FC 10 then FC 03 (several values are written with FC 16 = 0x10).
write 4 101 1234 5678 42
expect_read "101=1234 102=5678 103=42 " 4 101 3
# One register written, then read back.
write 4 201 4321
expect_read "201=4321 " 4 201 1
# A signed 32-bit value in two registers.
write 4:int 211 -7
expect_read "211=-7 " 4:int 211 1
# Coils written, then read back (FC 01); then a single coil.
write 0 301 1 0 1 1
expect_read "301=1 302=0 303=1 304=1 " 0 301 4
write 0 302 1
expect_read "302=1 " 0 302 1
# FC 02 and FC 04: what the profile starts with.
expect_read "1=0 2=0 " 1 1 2
expect_read "1=0 2=0 " 3 1 2
stop_serve
echo "PASS"
