#!/bin/sh
# mblab conform against pymodbus 3.0's asyncio server (Debian's python3-pymodbus): the verdicts
# must be the truth about it, failures included. Usage: test_conform_pymodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
MBLAB=$1

start_peer /usr/bin/python3 "$(dirname "$0")/pymodbus_conform_server.py" --lifetime 240
run_conform "$MBLAB" 1

# Policy 2.1: every test passes except 9.1.3, where pymodbus sends nothing back for a length
# field that promises more bytes than come; it serves no FC 5B. Ping depends on the machine.
# Extended suites, as measured on pymodbus 3.0.0rc1:
#   devid.5/7  individual access to an absent object answers no objects, stream access from one
#              answers no objects instead of restarting; devid.8 MEI 0x0F is served as 0x0E
#   diag.1     FC 08/00 with two data words closes the connection; diag.5 unknown sub-function
#              answers 04 instead of 01
#   fc05.2     coil value 0x1234 is accepted; fc0F.5 a byte count that disagrees is accepted
#   fc10.4/10.5/17.5  a quantity or byte count that disagrees closes the connection
#   mbap.5     protocol id 1 is answered (as protocol id 0)
#   mbap.7/8   a request split over segments closes the connection
#   mbap.10    a bare function code closes the connection
check_verdicts --others PASS,N/A \
    7.2='PASS|NOT RUN' 7.3.1=PASS 7.4.1=PASS 7.5.1=PASS 7.5.2=PASS 7.6.1=PASS 7.7.1=PASS \
    7.8.1=PASS 7.9.1=PASS 7.10.1=PASS 7.11.1=PASS 7.12.1=PASS 7.13.1=N/A 7.13.2=N/A \
    9.1.1=PASS 9.1.2=PASS 9.1.3=FAIL 9.1.4=PASS \
    devid.1=PASS devid.2=PASS devid.5=FAIL devid.7=FAIL devid.8=FAIL \
    diag.1=FAIL diag.5=FAIL \
    fc01.2=PASS fc05.1=PASS fc05.2=FAIL fc0F.2=PASS fc0F.5=FAIL fc10.2=PASS fc10.4=FAIL \
    fc10.5=FAIL fc16.1=PASS fc17.1=PASS fc17.5=FAIL \
    exc.1=PASS exc.3=PASS exc.8=PASS \
    mbap.1=PASS mbap.5=FAIL mbap.6=PASS mbap.7=FAIL mbap.8=FAIL mbap.10=FAIL

grep -q "9.1.3   Improper message length answers exception 03  (no answer from unit 0: timeout after 2000 ms (request 1 on this connection)" \
    "$WORK/console.txt"
