# Shared by the test_conform_*.sh interop tests; sourced, not run.
# start_peer CMD...: runs a server that prints its port on its first line of stdout, waits
# (at most 20 s) for that line, and sets PEER_PID and PEER_PORT. The peer is killed on exit.
set -eu

WORK=$(mktemp -d)
PEER_PID=""
cleanup() {
    if [ -n "$PEER_PID" ]; then kill "$PEER_PID" 2>/dev/null || true; fi
    rm -rf "$WORK"
}
trap cleanup EXIT

start_peer() {
    "$@" > "$WORK/peer.out" 2> "$WORK/peer.err" &
    PEER_PID=$!
    for _ in $(seq 1 200); do
        PEER_PORT=$(head -n 1 "$WORK/peer.out" 2>/dev/null || true)
        if [ -n "$PEER_PORT" ]; then return 0; fi
        if ! kill -0 "$PEER_PID" 2>/dev/null; then break; fi
        sleep 0.1
    done
    echo "the peer did not start: $*" >&2
    cat "$WORK/peer.err" >&2
    exit 1
}

# The peers' data maps: 65536 addresses of each kind from 0, any unit id; nothing else declared.
# DUT_UNIT (default 0) is the unit id tested; serial framings need an address from 1.
write_dut() {
    echo "unit = ${DUT_UNIT:-0}" > "$WORK/dut.toml"
    cat >> "$WORK/dut.toml" <<'TOML'
registers = 65536
max_read = 125
coils = 65536
discrete_inputs = 65536
input_registers = 65536
TOML
}

# run_conform MBLAB EXPECTED_STATUS [SCHEME|URL]: runs every shipped suite against the peer, reached
# as SCHEME://127.0.0.1:PORT (default tcp) or at URL (one with "://"). DUT_EXTRA holds more lines
# for the DUT file.
run_conform() {
    write_dut
    if [ -n "${DUT_EXTRA:-}" ]; then printf '%s\n' "$DUT_EXTRA" >> "$WORK/dut.toml"; fi
    case "${3:-tcp}" in
        *://*) target=$3 ;;
        *) target="${3:-tcp}://127.0.0.1:$PEER_PORT" ;;
    esac
    set +e
    "$1" conform "$target" --dut "$WORK/dut.toml" --json "$WORK/report.json" \
        > "$WORK/console.txt" 2>&1
    status=$?
    set -e
    cat "$WORK/console.txt"
    if [ "$status" != "$2" ]; then
        echo "mblab conform exited $status, expected $2" >&2
        exit 1
    fi
}

check_verdicts() {
    /usr/bin/python3 "$(dirname "$0")/check_conform_verdicts.py" "$WORK/report.json" "$@"
}
