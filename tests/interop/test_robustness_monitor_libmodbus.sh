#!/bin/sh
# mblab fuzz --monitor against a server built on Debian's libmodbus 3.1.6 that serves many clients
# from one select() loop (libmodbus_select_server.c). modbus_reply() answers with a blocking
# send(): the slow-reader class (40000 reads of 125 registers on one connection, answers never
# read) fills that connection's send buffer, and the loop then waits in send() for a reader that
# never comes, serving nobody. The liveness check finds it (a finding: the verdict is FAIL) and
# the monitor, on a connection of its own, shows it: cycles missed while the slow reader holds
# the loop, none in the baseline before it.
# Usage: test_robustness_monitor_libmodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
. "$(dirname "$0")/robustness_monitor_lib.sh"
MBLAB=$1

cc -O1 -o "$WORK/libmodbus_select_server" "$(dirname "$0")/libmodbus_select_server.c" \
    $(pkg-config --cflags --libs libmodbus)
start_peer "$WORK/libmodbus_select_server" 240

fuzz_monitored --class slow-reader --baseline 1s --degraded-limit 5s
[ "$FUZZ_STATUS" = 1 ] || fail "exit status $FUZZ_STATUS, not 1 (a finding)"
expect_out "FINDING: the device does not answer the known-good read"
expect_out "case 1, slow-reader: 1 connection(s), 40000 FC 03 reads of 125 each, answers never read"
expect_out "MONITOR VERDICT: FAIL: the device stopped serving (1 finding(s))"
[ "$(missed_in baseline)" = 0 ] || fail "the monitor missed cycles in the baseline"
[ "$(missed_in 'malformed input')" -gt 0 ] || fail "the monitor missed nothing during the stall"
grep -q '<testcase classname="monitor" name="malformed input" time="[0-9.]*">' "$WORK/fuzz.xml" ||
    fail "no monitor phase in the JUnit report"
grep -q '<failure message="FAIL: the device stopped serving' "$WORK/fuzz.xml" ||
    fail "the JUnit report does not fail the monitor's verdict"
