#!/bin/sh
# mblab conform over rtu:// against pymodbus 3.0's serial server (ModbusSerialServer, RTU framer)
# on a socat pty pair: the serial suite judged against a slave nobody here wrote, set up as a
# device on a multi-drop line is (its one address 1, other addresses ignored, 0 a broadcast).
# Usage: test_conform_pymodbus_serial.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
MBLAB=$1

socat "pty,raw,echo=0,link=$WORK/pty-a" "pty,raw,echo=0,link=$WORK/pty-b" 2>"$WORK/socat.err" &
SOCAT_PID=$!
trap 'kill $SOCAT_PID 2>/dev/null || true; cleanup' EXIT
for _ in $(seq 50); do
    [ -e "$WORK/pty-a" ] && [ -e "$WORK/pty-b" ] && break
    sleep 0.1
done
[ -e "$WORK/pty-b" ] || { cat "$WORK/socat.err" >&2; echo "socat made no pty pair" >&2; exit 1; }

start_peer /usr/bin/python3 "$(dirname "$0")/pymodbus_conform_server.py" \
    --serial "$WORK/pty-a" --baud 19200 --unit 1 --lifetime 240
DUT_UNIT=1 DUT_EXTRA="other_address = 7" run_conform "$MBLAB" 1 "rtu://$WORK/pty-b"

# As measured on pymodbus 3.0.0: the PDU verdicts of test_conform_pymodbus_rtu.sh, and two
# that differ on a real line. pymodbus's RTU framer ignores the line's silences: it keeps bytes it
# could not frame (a function code it does not know, a byte count past the frame) and the next
# request lands behind them, so the case after such a timeout gets no answer either (exc.3 after
# exc.2's 0x7F, fc10.5 after fc10.4, fc17.6 after fc17.5); over rtu+tcp:// the reconnect after a
# timeout clears that buffer. The serial suite: other addresses and broadcasts are handled as
# Modbus over Serial Line V1.02 2.2 rules (ser.1-ser.5 PASS); a frame with a bad CRC is dropped
# but the bus communication error count (FC 08 sub-function 0C) stays 0 (ser.6 FAIL); a request
# broken by a 50 ms silence is joined up and answered instead of discarded (ser.9 FAIL, 2.5.1.1).
check_verdicts --others PASS,N/A \
    7.2='PASS|N/A' 9.1.1=FAIL 9.1.3=N/A \
    devid.5=FAIL devid.7=FAIL devid.8=FAIL \
    diag.1=FAIL diag.5=FAIL exc.1=FAIL exc.2=FAIL exc.3=FAIL \
    fc05.2=FAIL fc0F.5=FAIL fc10.4=FAIL fc10.5=FAIL fc17.5=FAIL fc17.6=FAIL \
    ser.1=PASS ser.2=PASS ser.3=PASS ser.4=PASS ser.5=PASS ser.6=FAIL ser.7=PASS ser.8=N/A \
    ser.9=FAIL ser.10=PASS

grep -q "ser.9   A request broken by a silence.*was answered" "$WORK/console.txt"
grep -q "went from 0 to 0, not 1" "$WORK/console.txt"
