# Shared by the test_serve_*.sh interop scripts (sourced, not run): starts `mblab serve` on a free
# port, optionally captures its traffic with tshark, and cleans up by PID on exit.
# Needs MBLAB (path of the binary) and WORK (a scratch directory) set by the caller.

SERVE_PID=""
SERVE_PORT=""
CAPTURE_PID=""
# Any other process the script starts (a peer's server), killed on exit too.
OTHER_PID=""

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

cleanup() {
    [ -n "$CAPTURE_PID" ] && kill "$CAPTURE_PID" 2>/dev/null
    [ -n "$SERVE_PID" ] && kill "$SERVE_PID" 2>/dev/null
    [ -n "$OTHER_PID" ] && kill "$OTHER_PID" 2>/dev/null
    wait 2>/dev/null
    rm -rf "$WORK"
}
trap cleanup EXIT

# start_serve [ARGS...]: the reference device on 127.0.0.1 and an ephemeral port (read from the
# line mblab prints), so parallel test runs never race for a port.
start_serve() {
    "$MBLAB" serve --listen tcp://127.0.0.1:0 "$@" >"$WORK/serve.out" 2>"$WORK/serve.err" &
    SERVE_PID=$!
    wait_for_serve tcp
}

# start_serve_tls PKI [ARGS...]: the same over mbaps://, with the server files of the PKI
# directory (as `mblab pki` or the openssl CLI wrote them: server.pem, server.key, ca.pem).
start_serve_tls() {
    pki=$1
    shift
    "$MBLAB" serve --listen mbaps://127.0.0.1:0 --cert "$pki/server.pem" --key "$pki/server.key" \
        --ca "$pki/ca.pem" "$@" >"$WORK/serve.out" 2>"$WORK/serve.err" &
    SERVE_PID=$!
    wait_for_serve mbaps
}

# wait_for_serve SCHEME: SERVE_PORT from the line `mblab serve` prints once it listens.
wait_for_serve() {
    for _ in $(seq 100); do
        SERVE_PORT=$(sed -n "s/.* on $1:\/\/127\.0\.0\.1:\([0-9]*\).*/\1/p" "$WORK/serve.out")
        [ -n "$SERVE_PORT" ] && return 0
        kill -0 "$SERVE_PID" 2>/dev/null || break
        sleep 0.1
    done
    cat "$WORK/serve.err" >&2
    fail "mblab serve $1:// did not start"
}

# stop_serve: SIGTERM by PID; mblab must exit 0.
stop_serve() {
    kill -TERM "$SERVE_PID"
    status=0
    wait "$SERVE_PID" || status=$?
    SERVE_PID=""
    [ "$status" -eq 0 ] || fail "mblab serve exited $status after SIGTERM"
}

# start_capture: tshark on lo for the server's port, into $WORK/session.pcapng.
# MBLAB_SKIP_CAPTURE=1 skips it where capturing is not allowed.
start_capture() {
    [ "${MBLAB_SKIP_CAPTURE:-0}" = 1 ] && return 0
    command -v tshark >/dev/null || fail "tshark is not installed (MBLAB_SKIP_CAPTURE=1 skips the capture)"
    tshark -i lo -f "tcp port $SERVE_PORT" -w "$WORK/session.pcapng" >"$WORK/tshark.err" 2>&1 &
    CAPTURE_PID=$!
    for _ in $(seq 100); do
        if grep -q "Capturing on" "$WORK/tshark.err"; then
            sleep 1  # the line comes a little before the capture filter is in place
            return 0
        fi
        kill -0 "$CAPTURE_PID" 2>/dev/null || break
        sleep 0.1
    done
    cat "$WORK/tshark.err" >&2
    fail "tshark did not start capturing"
}

# check_capture: Wireshark's Modbus/TCP dissector must find nothing malformed and no error.
check_capture() {
    [ "${MBLAB_SKIP_CAPTURE:-0}" = 1 ] && return 0
    sleep 1  # let the last packets reach the capture file
    kill -INT "$CAPTURE_PID"
    wait "$CAPTURE_PID" 2>/dev/null
    CAPTURE_PID=""
    frames=$(tshark -r "$WORK/session.pcapng" -d "tcp.port==$SERVE_PORT,mbtcp" -Y mbtcp 2>/dev/null | wc -l)
    [ "$frames" -gt 0 ] || { cat "$WORK/tshark.err" >&2; fail "the capture holds no Modbus/TCP frames"; }
    bad=$(tshark -r "$WORK/session.pcapng" -d "tcp.port==$SERVE_PORT,mbtcp" \
        -Y "_ws.malformed || _ws.expert.severity>=error" 2>&1 | grep -v '^Running as user' || true)
    [ -z "$bad" ] || fail "tshark flags frames of the session:
$bad"
    echo "tshark: $frames Modbus/TCP frames, none malformed"
}
