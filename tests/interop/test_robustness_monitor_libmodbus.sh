#!/bin/sh
# mblab fuzz --monitor against a server built on Debian's libmodbus 3.1.6 that serves many clients
# from one select() loop, as libmodbus's manual describes (bench/libmodbus_server.c, the
# benchmark's). modbus_reply() answers with a blocking
# send(): the slow-reader class (40000 reads of 125 registers on one connection, answers never
# read) fills that connection's send buffer, and the loop then waits in send() for a reader that
# never comes, serving nobody. The liveness check finds it (a finding: the verdict is FAIL) and
# the monitor, on a connection of its own, shows it: cycles missed while the slow reader holds
# the loop, none in the baseline before it.
# Usage: test_robustness_monitor_libmodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
. "$(dirname "$0")/robustness_monitor_lib.sh"
MBLAB=$1

cc -O1 -o "$WORK/libmodbus_server" "$(dirname "$0")/../../bench/libmodbus_server.c" \
    $(pkg-config --cflags --libs libmodbus)
# It takes its port rather than printing one: a free one, printed for start_peer, then exec'd into
# so that the peer's pid is the server's.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
start_peer sh -c 'echo "$1"; exec "$2" "$1"' sh "$port" "$WORK/libmodbus_server"

fuzz_monitored --class slow-reader --baseline 1s --degraded-limit 5s
expect_out "FINDING: the device does not answer the known-good read"
expect_out "case 1, slow-reader: 1 connection(s), 40000 FC 03 reads of 125 each, answers never read"
expect_lost_under_malformed "FAIL: the device stopped serving (1 finding(s))"
