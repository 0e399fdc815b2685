# Shared by the scripts that grade a peer client with `mblab conform-client` (sourced, not run).

# expect_verdicts OUT STATUS WANT PATTERN...: the run whose console report is in OUT ended with
# STATUS 1 and gave exactly the verdicts WANT ("tcp.1 PASS tcp.2 N/A ... "), and for each PATTERN
# (the bytes that decided a FAIL) a line of OUT matches it. Exits with FAIL otherwise.
expect_verdicts() {
    out=$1 status=$2 want=$3
    shift 3
    cat "$out"
    [ "$status" = 1 ] || { echo "FAIL: exit status $status, expected 1"; exit 1; }
    verdicts=$(sed -nE 's/^  (PASS|FAIL|N\/A) +(tcp\.[0-9.A-F]+) .*/\2 \1/p' "$out" | tr '\n' ' ')
    [ "$verdicts" = "$want" ] || { printf 'FAIL: verdicts\n%s\nexpected\n%s\n' "$verdicts" "$want"; exit 1; }
    for decided in "$@"; do
        grep -q "$decided" "$out" || { echo "FAIL: no line matches: $decided"; exit 1; }
    done
}
