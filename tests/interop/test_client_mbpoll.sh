#!/bin/sh
# mblab's client and mbpoll (libmodbus) on the same reference device (`mblab serve`): what mbpoll
# writes `mblab read` reads back, and what `mblab write` writes mbpoll reads, typed values
# included in both word orders.
# Usage: test_client_mbpoll.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/client_interop.sh"

start_mblab_serve "$MBLAB"

# mbpoll ARGS...: one poll, zero-based references, only the value lines ("[10]: 7" -> "10 7").
mbpoll_run() {
    mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -o 3 "$@" 127.0.0.1 | sed -n 's/^\[\([0-9]*\)\]:[[:space:]]*/\1 /p'
}
mbpoll_write() {
    mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -o 3 "$@" > "$WORK/mbpoll.out"
    grep -q "^Written" "$WORK/mbpoll.out"
}

# mbpoll writes, mblab reads.
mbpoll_write -r 300 -t 4 127.0.0.1 -- 11 22 33
expect "mblab reads registers mbpoll wrote" "$(printf 'address       raw     u16
300 (0x012C)  0x000B  11
301 (0x012D)  0x0016  22
302 (0x012E)  0x0021  33')" "$("$MBLAB" read "$TARGET" holding 300 3)"
mbpoll_write -r 310 -t 4:float -B 127.0.0.1 -- 3.5 -1000
expect "mblab reads floats mbpoll wrote, high word first" "$(printf 'address       raw            f32
310 (0x0136)  0x4060 0x0000  3.5
312 (0x0138)  0xC47A 0x0000  -1000')" "$("$MBLAB" read "$TARGET" holding 310 2 --type f32)"
mbpoll_write -r 320 -t 4:int 127.0.0.1 -- -123456
expect "mblab reads an int mbpoll wrote, low word first" "$(printf 'address       raw            i32
320 (0x0140)  0x1DC0 0xFFFE  -123456')" \
    "$("$MBLAB" read "$TARGET" holding 320 1 --type i32 --word-order little)"
mbpoll_write -r 40 -t 0 127.0.0.1 -- 1 0 1
expect "mblab reads coils mbpoll wrote" "$(printf 'address      raw  value
40 (0x0028)  1    on
41 (0x0029)  0    off
42 (0x002A)  1    on')" "$("$MBLAB" read "$TARGET" coils 40 3)"

# mblab writes, mbpoll reads.
"$MBLAB" write "$TARGET" registers 400 5 6 > /dev/null
expect "mbpoll reads registers mblab wrote" "$(printf '400 5\n401 6')" \
    "$(mbpoll_run -r 400 -c 2 -t 4)"
"$MBLAB" write "$TARGET" registers 410 2.25 --type f32 > /dev/null
expect "mbpoll reads a float mblab wrote" "410 2.25" "$(mbpoll_run -r 410 -c 1 -t 4:float -B)"
"$MBLAB" write "$TARGET" registers 420 2.25 --type f32 --word-order little > /dev/null
expect "mbpoll reads a low-word-first float" "420 2.25" "$(mbpoll_run -r 420 -c 1 -t 4:float)"
"$MBLAB" write "$TARGET" coil 50 on > /dev/null
expect "mbpoll reads a coil mblab wrote" "50 1" "$(mbpoll_run -r 50 -c 1 -t 0)"
