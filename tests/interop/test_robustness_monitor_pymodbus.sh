#!/bin/sh
# mblab fuzz --monitor against pymodbus 3.0's asyncio server (Debian's python3-pymodbus,
# pymodbus_conform_server.py). Its one event loop decodes and answers every request in Python and
# hands the answers to asyncio's transport, which buffers them without blocking: no slow reader
# can hold it in a send. But pipelined requests keep that loop busy: the slow-reader class's 8
# connections with 4000 reads of 125 registers each take it seconds (about 2 s here), during which
# the monitor, on a connection of its own, misses its cycles; then it comes back by itself,
# without a restart: DEGRADED. The check's --timeout of 5 s outlasts the busy loop, so the
# liveness check sees a device that answers late rather than none (with the default 1 s it is a
# finding, and FAIL, on a slow enough machine).
# Usage: test_robustness_monitor_pymodbus.sh MBLAB BUILD_DIR
. "$(dirname "$0")/conform_interop.sh"
. "$(dirname "$0")/robustness_monitor_lib.sh"
MBLAB=$1

start_peer /usr/bin/python3 "$(dirname "$0")/pymodbus_conform_server.py" --lifetime 240

fuzz_monitored --cases 300 --timeout 5s
expect_out "no finding: the device served every liveness check"
expect_lost_under_malformed "DEGRADED: the monitor was lost for"
expect_out "and came back unaided"
