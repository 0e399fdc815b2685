# Shared by the scripts that grade a peer client with `mblab conform-client` (sourced, not run).

# expect_verdicts OUT STATUS NOT_PASSED PATTERN...: the run whose console report is in OUT ended
# with STATUS 1 and its TCP scenarios (all 21 of them) passed but those NOT_PASSED names with
# their verdicts ("tcp.2 N/A tcp.3 FAIL ..."), and for each PATTERN (the bytes that decided a
# FAIL) a line of OUT matches it. Exits with FAIL otherwise.
expect_verdicts() {
    expect_scenarios tcp 21 "$@"
}

# expect_line_verdicts OUT STATUS NOT_PASSED PATTERN...: the same for a serial line's 12.
expect_line_verdicts() {
    expect_scenarios ser 12 "$@"
}

expect_scenarios() {
    kind=$1 total=$2 out=$3 status=$4 not_passed=" $5 "
    shift 5
    cat "$out"
    [ "$status" = 1 ] || { echo "FAIL: exit status $status, expected 1"; exit 1; }
    seen=$(sed -nE "s/^  (PASS|FAIL|N\/A) +($kind\.[0-9.A-F]+) .*/\2 \1/p" "$out")
    [ "$(echo "$seen" | wc -l)" = "$total" ] ||
        { echo "FAIL: not $total $kind scenarios:"; echo "$seen"; exit 1; }
    echo "$seen" | while read -r id verdict; do
        case "$not_passed" in
            *" $id "*) want=$(echo "$not_passed" | sed -E "s/.* $id ([^ ]+) .*/\1/") ;;
            *) want=PASS ;;
        esac
        [ "$verdict" = "$want" ] || { echo "FAIL: $id $verdict, expected $want"; exit 1; }
    done || exit 1
    for decided in "$@"; do
        grep -q "$decided" "$out" || { echo "FAIL: no line matches: $decided"; exit 1; }
    done
}
