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

# start_mblab_serve MBLAB: the reference device on an ephemeral port; sets PORT and TARGET.
start_mblab_serve() {
    start_peer "$1" serve "$(dirname "$0")/../../profiles/reference.toml" \
        --listen tcp://127.0.0.1:0
    # Its first line: "mblab serve: reference profile on tcp://127.0.0.1:PORT, ..."
    PORT=$(echo "$PEER_PORT" | sed -n 's|.*tcp://127\.0\.0\.1:\([0-9]*\).*|\1|p')
    TARGET="tcp://127.0.0.1:$PORT"
}
