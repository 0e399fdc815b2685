#!/bin/sh
# mblab scan against a server built on Debian's libmodbus 3.1.6 (libmodbus_server.c): the DUT file
# it writes declares what the server holds, changes nothing there, and leaves conform fewer N/A.
# Usage: test_scan_libmodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
. "$(dirname "$0")/scan_interop.sh"
MBLAB=$1

cc -O1 -o "$WORK/libmodbus_server" "$(dirname "$0")/libmodbus_server.c" \
    $(pkg-config --cflags --libs libmodbus)
start_peer "$WORK/libmodbus_server" 240
scan_peer "$MBLAB"

# 65536 addresses of each kind from 0; FC 07 gets no answer, FC 08, 0B, 0C, 14, 18 and 2B are
# refused with 01, and so is FC 5B.
expect_line "registers = 65536  # learned by mblab scan: FC 03 answered 0..65535, each address read once in whole reads"
expect_line "discrete_inputs = 65536  # learned by mblab scan: FC 02 answered 0..65535, each address read once in whole reads"
expect_line "max_read = 125  # learned by mblab scan: FC 03 of 125 registers (the most [APP] 6.3 allows) answered at 0"
expect_line "# function codes served: 01 02 03 04 11"
expect_line "# answered exception 01 (not served): 08 0B 0C 14 18 2B"
expect_line "# no answer: 07"
expect_line "# echo_max_words: FC 08 is not served (exception 01)"
expect_line "# device identification (FC 2B/0E): not answered (exception 01 (illegal function))"
