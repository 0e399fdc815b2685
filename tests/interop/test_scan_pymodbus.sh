#!/bin/sh
# mblab scan against pymodbus 3.0's asyncio server (Debian's python3-pymodbus): the DUT file it
# writes declares what the server holds, changes nothing there, and leaves conform fewer N/A.
# Usage: test_scan_pymodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
. "$(dirname "$0")/scan_interop.sh"
MBLAB=$1

start_peer /usr/bin/python3 "$(dirname "$0")/pymodbus_conform_server.py" --lifetime 240
scan_peer "$MBLAB"

# 65536 addresses of each kind from 0, any unit id; FC 08/00 closes the connection on two words
# (no limit an exception shows), no FC 5B.
expect_line "unit = 1  # learned by mblab scan: 1 of the 3 units that answered FC 03"
expect_line "registers = 65536  # learned by mblab scan: FC 03 answered 0..65535, each address read once in whole reads"
expect_line "coils = 65536  # learned by mblab scan: FC 01 answered 0..65535, each address read once in whole reads"
expect_line "input_registers = 65536  # learned by mblab scan: FC 04 answered 0..65535, each address read once in whole reads"
expect_line "# echo_max_words: FC 08/00 echoed 1 data word; 2 got no answer where INSTR 5.7.1 expects exception 03: no limit to declare"
expect_line "# object_messaging: FC 5B get attribute (CTP 7.13.1's request) answered exception 01"
expect_line '# device identification (FC 2B/0E): vendor name "pymodbus", product code "PM", revision "3.0.0"'
