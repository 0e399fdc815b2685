# Shared by the test_robustness_monitor_*.sh interop tests; sourced, not run (after
# conform_interop.sh, which starts the peer).
# fuzz_monitored ARGS...: mblab fuzz against the peer with the essential-function monitor on
# holding register 50, every 100 ms within 50 ms; the console in $WORK/fuzz.out, the JUnit report
# in $WORK/fuzz.xml, the exit status in FUZZ_STATUS.
fuzz_monitored() {
    FUZZ_STATUS=0
    "$MBLAB" fuzz "tcp://127.0.0.1:$PEER_PORT" --writable 0:10 \
        --monitor register=50,period=100,budget=50 --report-dir "$WORK/report" \
        --junit "$WORK/fuzz.xml" "$@" > "$WORK/fuzz.out" 2>&1 || FUZZ_STATUS=$?
}

fail() {
    echo "FAIL: $1" >&2
    cat "$WORK/fuzz.out" >&2
    exit 1
}

expect_out() {
    grep -qF -- "$1" "$WORK/fuzz.out" || fail "expected the line: $1"
}

# missed_in PHASE: the cycles the monitor missed in that phase, from its console line.
missed_in() {
    sed -n "s/^  $1 *[0-9]* cycles, *\([0-9]*\) missed.*/\1/p" "$WORK/fuzz.out"
}

# expect_lost_under_malformed VERDICT_TEXT: exit status 1, the verdict line beginning so, the
# monitor held through the baseline and missed cycles during the malformed input, and the JUnit
# report's monitor suite failing that phase and the verdict.
expect_lost_under_malformed() {
    [ "$FUZZ_STATUS" = 1 ] || fail "exit status $FUZZ_STATUS, not 1"
    expect_out "MONITOR VERDICT: $1"
    [ "$(missed_in baseline)" = 0 ] || fail "the monitor missed cycles in the baseline"
    [ "$(missed_in 'malformed input')" -gt 0 ] || fail "the monitor missed nothing meanwhile"
    grep -q '<testcase classname="monitor" name="malformed input" time="[0-9.]*">$' \
        "$WORK/fuzz.xml" || fail "the JUnit report does not fail the malformed-input phase"
    grep -qF "<failure message=\"$1" "$WORK/fuzz.xml" ||
        fail "the JUnit report does not fail the monitor's verdict"
}
