#!/bin/bash
# mblab(1) renders with man -l without a troff warning, has a section per command, and names every
# option each command's --help lists.
#   test_man.sh MBLAB_BINARY MAN_PAGE
set -euo pipefail
mblab=$1
page=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
# man renders hyphens as U+2010 outside the C locale, and options are searched for as typed.
export LC_ALL=C

errors=$(mktemp)
trap 'rm -f "$errors"' EXIT
text=$(MANWIDTH=100 man --warnings -l "$page" 2>"$errors")
[ ! -s "$errors" ] || fail "man -l warns: $(cat "$errors")"
for command in conform conform-client serve load read write diag devid raw watch sunspec pki fuzz scan "profile import-csv"; do
    upper=$(tr a-z A-Z <<<"${command%% *}")
    grep -q "^MBLAB $upper\$" <<<"$text" || fail "no section MBLAB $upper"
    # shellcheck disable=SC2086 # "profile import-csv" is a command and its subcommand
    for option in $("$mblab" $command --help |
        sed -nE 's/^ +((-[A-Za-z]),)?(--[A-Za-z][-A-Za-z0-9]*).*/\2 \3/p'); do
        case $option in -h | --help) continue ;; esac
        grep -qe "$option\\b" <<<"$text" || fail "mblab $command $option is not in the man page"
    done
done
echo "man page: ok"
