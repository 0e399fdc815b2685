#!/bin/sh
# `mblab sunspec` against `mblab serve sunspec-inverter`, captured on loopback by tshark and read
# back by its Modbus/TCP dissector: the marker read at 40000 is answered "SunS", each model's
# header read is answered with the id and length the scan printed, every read stays within 125
# registers, and the chain ends with 0xFFFF and length 0 where the scan said (SunSpec Modbus
# specification: the marker, the model headers, the end model).
# Usage: test_sunspec_tshark.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
HERE=$(dirname "$0")
. "$HERE/client_interop.sh"

start_mblab_serve "$MBLAB" sunspec-inverter
start_capture "$MBLAB" 40000

"$MBLAB" sunspec "$TARGET" --json > "$WORK/scan.json"
"$MBLAB" sunspec "$TARGET" --decode bytes > /dev/null 2> "$WORK/decode.log"
REQUESTS=$(grep -c '^> [0-9A-F][0-9A-F] ' "$WORK/decode.log")
# The scan, then the logged run: the same reads twice.
wait_for_frames $((WARMUP + 4 * REQUESTS))
stop_capture

# A request's fields, and the answer's registers on the answer's line (tshark matches them).
tshark -r "$WORK/capture.pcapng" -o "mbtcp.tcp.port:$PORT" -Y mbtcp -T fields \
    -e tcp.dstport -e mbtcp.trans_id -e modbus.func_code -e modbus.reference_num \
    -e modbus.word_cnt -e modbus.regval_uint16 2>/dev/null | tail -n +$((WARMUP + 1)) \
    > "$WORK/fields.tsv"
/usr/bin/python3 - "$WORK/fields.tsv" "$WORK/scan.json" "$PORT" "$REQUESTS" <<'PY'
import json
import sys

fields, scan_file, port, logged = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
scan = json.load(open(scan_file))["sunspec"]
requests, answers = {}, {}
order = []
for line in open(fields):
    dst, tid, fc, ref, count, values = (line.rstrip("\n").split("\t") + [""] * 6)[:6]
    if dst == port:
        requests[tid] = (int(fc), int(ref), int(count))
        order.append(tid)
    else:
        answers[tid] = [int(v) for v in values.split(",") if v]
half = len(order) // 2
assert len(order) == 2 * logged, f"{len(order)} requests captured, {2 * logged} expected"
first = order[:half]  # the scan whose --json output is checked

def answer(address, count):
    for tid in first:
        if requests[tid] == (3, address, count):
            return answers.get(tid)
    sys.exit(f"FAIL: no read of {count} registers at {address} in the capture")

for tid in first:
    fc, ref, count = requests[tid]
    if fc != 3 or not 1 <= count <= 125:
        sys.exit(f"FAIL: request {tid}: FC {fc} of {count} registers at {ref}")
if requests[first[0]][1:] != (40000, 2) or answer(40000, 2) != [0x5375, 0x6E53]:
    sys.exit(f"FAIL: the first read is {requests[first[0]]}, answered {answers.get(first[0])}")
for model in scan["models"]:
    header = answer(model["address"], 2)
    if header != [model["id"], model["length"]]:
        sys.exit(f"FAIL: model {model['id']} at {model['address']}: the wire says {header}")
if answer(scan["end"], 2) != [0xFFFF, 0]:
    sys.exit(f"FAIL: the end model at {scan['end']}: the wire says {answer(scan['end'], 2)}")
print(f"ok: {half} reads, the marker, {len(scan['models'])} model headers and the end "
      f"model at {scan['end']} as tshark reads them")
PY
