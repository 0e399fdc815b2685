# Shared by the test_scan_*.sh interop tests; sourced after conform_interop.sh, not run.
# scan_peer MBLAB: `mblab scan` of the peer started with start_peer into $WORK/scanned.toml; what
# the peer holds is read before and after (after distinct values were written where the scan
# reads), and must not have changed; then `mblab conform` runs without the file and with it, and
# the file must leave fewer cases N/A.

# Holding registers, coils and input tables at both ends of the address space.
peer_snapshot() {
    target=tcp://127.0.0.1:$PEER_PORT
    for read in "holding 0 125" "holding 65411 125" "input 0 125" "coils 0 2000" \
        "coils 63536 2000" "discretes 0 2000"; do
        # shellcheck disable=SC2086 # the kind, address and count are three words
        "$1" read "$target" $read --json
    done
}

scan_peer() {
    target=tcp://127.0.0.1:$PEER_PORT
    "$1" write "$target" registers 0 4660 22136 39612 1 2 3 > /dev/null
    "$1" write "$target" registers 65530 7 8 9 > /dev/null
    "$1" write "$target" coils 0 1 0 1 1 > /dev/null
    peer_snapshot "$1" > "$WORK/before.json"
    "$1" scan "$target" -o "$WORK/scanned.toml" > "$WORK/scan.txt" 2>&1 || {
        cat "$WORK/scan.txt"
        echo "mblab scan failed" >&2
        exit 1
    }
    cat "$WORK/scan.txt" "$WORK/scanned.toml"
    peer_snapshot "$1" > "$WORK/after.json"
    cmp -s "$WORK/before.json" "$WORK/after.json" || {
        diff "$WORK/before.json" "$WORK/after.json" >&2 || true
        echo "the scan changed what the peer holds" >&2
        exit 1
    }
    set +e
    "$1" conform "$target" --json "$WORK/bare.json" > "$WORK/bare.txt" 2>&1
    "$1" conform "$target" --dut "$WORK/scanned.toml" --json "$WORK/declared.json" \
        > "$WORK/declared.txt" 2>&1
    set -e
    /usr/bin/python3 - "$WORK/bare.json" "$WORK/declared.json" <<'PY'
import json, sys
bare, declared = (json.load(open(path))["summary"] for path in sys.argv[1:])
print(f"N/A without the scanned file: {bare['not_applicable']}, with it: {declared['not_applicable']}")
if declared["not_applicable"] >= bare["not_applicable"]:
    sys.exit("the scanned file did not turn N/A cases into tests")
PY
}

# expect_line TEXT: the scanned file holds the line TEXT (a fixed string).
expect_line() {
    grep -qxF "$1" "$WORK/scanned.toml" || {
        echo "the scanned file lacks the line: $1" >&2
        exit 1
    }
}
