# Shared by the test_client_*.sh interop tests; sourced, not run. Builds on conform_interop.sh
# (WORK, start_peer, cleanup on exit).
. "$(dirname "$0")/conform_interop.sh"

# expect WHAT EXPECTED ACTUAL: stops the test with both texts when they differ.
expect() {
    if [ "$2" != "$3" ]; then
        printf 'FAIL %s\n--- expected\n%s\n--- got\n%s\n' "$1" "$2" "$3" >&2
        exit 1
    fi
    echo "ok $1"
}

# start_mblab_serve MBLAB [PROFILE]: the reference device (or the shipped PROFILE, e.g.
# sunspec-inverter) on an ephemeral port; sets PORT and TARGET.
start_mblab_serve() {
    start_peer "$1" serve "$(dirname "$0")/../../profiles/${2:-reference}.toml" \
        --listen tcp://127.0.0.1:0
    # Its first line: "mblab serve: reference profile on tcp://127.0.0.1:PORT, ..."
    PORT=$(echo "$PEER_PORT" | sed -n 's|.*tcp://127\.0\.0\.1:\([0-9]*\).*|\1|p')
    TARGET="tcp://127.0.0.1:$PORT"
}

# start_capture MBLAB [ADDRESS]: tshark capturing the mblab serve started above on loopback (root
# or the wireshark group; without it the test fails with tshark's reason). It returns once reads
# of holding ADDRESS (0) are in the file, WARMUP frames of them, so what follows is all captured.
# Sets TSHARK_PID; stop_capture ends it.
start_capture() {
    tshark -i lo -f "tcp port $PORT" -w "$WORK/capture.pcapng" > /dev/null 2> "$WORK/tshark.err" &
    TSHARK_PID=$!
    trap 'stop_capture; cleanup' EXIT
    for _ in $(seq 1 100); do
        if grep -q "Capturing on" "$WORK/tshark.err"; then break; fi
        if ! kill -0 "$TSHARK_PID" 2>/dev/null; then
            echo "tshark cannot capture here:" >&2
            cat "$WORK/tshark.err" >&2
            exit 1
        fi
        sleep 0.1
    done
    for _ in $(seq 1 20); do
        "$1" read "$TARGET" holding "${2:-0}" > /dev/null
        if [ "$(frames_captured)" -ge 2 ]; then break; fi
        sleep 0.5
    done
    # Every warm-up frame must be in the file before they are counted out: wait for the count to
    # settle on whole exchanges.
    WARMUP=0
    for _ in $(seq 1 50); do
        sleep 0.3
        now=$(frames_captured)
        if [ "$now" -eq "$WARMUP" ] && [ $((now % 2)) -eq 0 ] && [ "$now" -ge 2 ]; then break; fi
        WARMUP=$now
    done
}

stop_capture() {
    if [ -n "${TSHARK_PID:-}" ]; then
        kill -INT "$TSHARK_PID" 2>/dev/null || true
        wait "$TSHARK_PID" || true
    fi
    TSHARK_PID=""
}

# Modbus frames in the capture so far (dumpcap writes each packet as it comes).
frames_captured() {
    tshark -r "$WORK/capture.pcapng" -o "mbtcp.tcp.port:$PORT" -Y mbtcp 2>/dev/null | wc -l
}

# wait_for_frames N: until the capture holds N Modbus frames (at most 20 s; a busy machine may
# start capturing, or write packets, a little late).
wait_for_frames() {
    for _ in $(seq 1 200); do
        if [ "$(frames_captured)" -ge "$1" ]; then return 0; fi
        sleep 0.1
    done
    echo "the capture holds $(frames_captured) Modbus frames, expected $1" >&2
    exit 1
}
