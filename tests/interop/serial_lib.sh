# Shared by the test_serial_*.sh interop scripts (sourced, not run): a socat pseudo-terminal
# pair, `mblab serve` processes on its ends or on TCP, and cleanup by PID on exit.
# Needs MBLAB (path of the binary) and WORK (a scratch directory) set by the caller.

PIDS=""

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

cleanup() {
    for pid in $PIDS; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null
    rm -rf "$WORK"
}
trap cleanup EXIT

# start_pty_pair NAME: $WORK/NAME-a and $WORK/NAME-b, linked by socat (which does not emulate
# baud timing). A pty keeps the settings of its last user, which pyserial cannot always reopen:
# give each master a new pair.
start_pty_pair() {
    socat -d -d "pty,raw,echo=0,link=$WORK/$1-a" "pty,raw,echo=0,link=$WORK/$1-b" \
        2>"$WORK/socat-$1.err" &
    PIDS="$PIDS $!"
    for _ in $(seq 50); do
        [ -e "$WORK/$1-a" ] && [ -e "$WORK/$1-b" ] && return 0
        sleep 0.1
    done
    cat "$WORK/socat-$1.err" >&2
    fail "socat made no pty pair"
}

# start_mblab NAME ARGS...: runs `mblab ARGS...` in the background until it prints its
# "mblab serve: ..." line; NAME_PID holds its PID, $WORK/NAME.out its output.
start_mblab() {
    name=$1
    shift
    "$MBLAB" "$@" >"$WORK/$name.out" 2>"$WORK/$name.err" &
    pid=$!
    PIDS="$PIDS $pid"
    eval "${name}_PID=$pid"
    for _ in $(seq 100); do
        grep -q "^mblab serve: " "$WORK/$name.out" && return 0
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
    cat "$WORK/$name.err" >&2
    fail "mblab $* did not start"
}

# tcp_port NAME: the port NAME's `mblab serve` line says it listens on.
tcp_port() {
    sed -n 's/.* on \(rtu+\)\{0,1\}tcp:\/\/127\.0\.0\.1:\([0-9]*\).*/\2/p' "$WORK/$1.out"
}

# stop_mblab NAME: SIGTERM by PID; mblab must exit 0.
stop_mblab() {
    eval "pid=\$${1}_PID"
    kill -TERM "$pid"
    status=0
    wait "$pid" || status=$?
    [ "$status" -eq 0 ] || fail "mblab $1 exited $status after SIGTERM"
}
