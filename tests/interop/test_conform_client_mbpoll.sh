#!/bin/sh
# `mblab conform-client` grading mbpoll (libmodbus 3.1.6 on Debian 12), a client nobody here
# wrote: its verdicts are the ones docs/client-conformance.md records, each FAIL decided by the
# bytes the reason quotes.
# Over Modbus/TCP and over RTU on a pty pair.
# Usage: test_conform_client_mbpoll.sh MBLAB_BINARY [BUILD_DIR]
MBLAB=$1
. "$(dirname "$0")/conform_client_lib.sh"
command -v mbpoll >/dev/null || { echo "FAIL: mbpoll is not installed (scripts/install-deps.sh)"; exit 1; }
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$MBLAB" conform-client --client-timeout 300ms --client-retries 0 -- \
    mbpoll -m tcp -a '{unit}' -0 -r '{address}' -c '{count}' -t 4 -1 -o 0.3 -p '{port}' '{host}' >"$out"
status=$?
want="tcp.2 N/A tcp.3 FAIL tcp.4 FAIL tcp.5.3 FAIL tcp.11 N/A"
# The bytes that decide: an error on another transaction id, the values of unit 2's answer and of
# a frame whose MBAP length counts two bytes past its registers.
expect_verdicts "$out" "$status" "$want" \
    'tcp.3 .*reported an error instead of discarding' \
    'tcp.4 .*took the decoy 40100 from 00 01 00 00 00 07 02 03 04 9C A4 9C A5' \
    'tcp.5.3 .*took the decoy 40100 from 00 01 00 00 00 09 01 03 04 9C A4 9C A5 DE AD'

# Over RTU on a pty pair (even parity, as the line's default): libmodbus underneath reports
# another slave's answer as an error instead of waiting on for its own [SER 2.4.1].
"$MBLAB" conform-client --listen 'rtu:///dev/ptmx?baud=19200' --client-timeout 300ms \
    --client-retries 0 -- mbpoll -m rtu -a '{unit}' -0 -r '{address}' -c '{count}' -t 4 -1 \
    -o 0.3 -b '{baud}' -P even '{device}' >"$out"
expect_line_verdicts "$out" $? "ser.4 FAIL ser.9 N/A" \
    'ser.4 .*reported an error instead of discarding.*Response not from requested slave'
echo "mbpoll under conform-client: as recorded"
