#!/bin/sh
# `--decode bytes` shows what is on the wire: tshark captures the client's exchanges with the
# reference device on loopback, and its dissection must agree with mblab's log byte for byte
# and field for field (transaction id, length, unit, function code, reference, counts,
# exception code). Capturing needs root or the wireshark group; without it the test fails with
# tshark's reason.
# Usage: test_client_tshark.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/client_interop.sh"

start_mblab_serve "$MBLAB"
start_capture "$MBLAB"

n=0
decode() {  # decode ARGS...: runs mblab with --decode bytes, keeps its log
    n=$((n + 1))
    "$MBLAB" "$@" --decode bytes > /dev/null 2> "$WORK/decode.$n" || true
}
decode read "$TARGET" holding 0 3
decode write "$TARGET" registers 100 1 2 3
decode read "$TARGET" coils 5 10 --unit 0
decode write "$TARGET" coils 5 1 0 1
decode read "$TARGET" input 7 2
decode write "$TARGET" register 9 0xBEEF
decode raw "$TARGET" 41 00
decode read "$TARGET" holding 0 1 --unit 255

LOGS=""
i=1
while [ "$i" -le "$n" ]; do LOGS="$LOGS $WORK/decode.$i"; i=$((i + 1)); done
# shellcheck disable=SC2086
LOGGED=$(cat $LOGS | grep -c '^[<>] [0-9A-F][0-9A-F] ')
wait_for_frames $((WARMUP + LOGGED))
stop_capture

tshark -r "$WORK/capture.pcapng" -o "mbtcp.tcp.port:$PORT" -Y mbtcp -T fields \
    -e tcp.payload -e mbtcp.trans_id -e mbtcp.prot_id -e mbtcp.len -e mbtcp.unit_id \
    -e modbus.func_code -e modbus.reference_num -e modbus.word_cnt -e modbus.bit_cnt \
    -e modbus.byte_cnt -e modbus.exception_code 2>/dev/null | tail -n +$((WARMUP + 1)) \
    > "$WORK/fields.tsv"
# shellcheck disable=SC2086
/usr/bin/python3 "$HERE/check_client_decode.py" "$WORK/fields.tsv" $LOGS
# The checker itself must see a difference: a log that lies about a quantity is refused.
sed 's/quantity 3$/quantity 4/' "$WORK/decode.1" > "$WORK/lie"
if /usr/bin/python3 "$HERE/check_client_decode.py" "$WORK/fields.tsv" "$WORK/lie" \
    $(echo "$LOGS" | cut -d' ' -f3-) 2> "$WORK/lie.err"; then
    echo "the checker accepted a wrong quantity" >&2
    exit 1
fi
cat "$WORK/lie.err"
