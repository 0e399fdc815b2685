#!/bin/sh
# Every command in docs/security.md's plain code blocks runs exactly as printed, in order, in a
# scratch directory with this build's mblab first on PATH: a line ending in " &" starts a server
# (waited for until it prints its banner, stopped at the end), every other line must exit 0.
# Usage: test_security_doc.sh MBLAB BUILD_DIR
set -eu
MBLAB=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
DOC="$HERE/../../docs/security.md"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-security-doc.XXXXXX")
PIDS=""
cleanup() {
    for pid in $PIDS; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$WORK"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
mkdir "$WORK/bin"
ln -s "$MBLAB" "$WORK/bin/mblab"
PATH="$WORK/bin:$PATH"
cd "$WORK"

# The lines of ``` blocks without a language (```toml blocks are profile text, not commands).
awk '/^```/ { if (block) { block = 0; plain = 0 } else { block = 1; plain = ($0 == "```") } next }
     block && plain' "$DOC" >"$WORK/commands"
[ -s "$WORK/commands" ] || fail "no commands found in $DOC"
n=0
while IFS= read -r line; do
    case $line in mblab\ *) ;; *) continue ;; esac
    n=$((n + 1))
    case $line in
    *" &")
        sh -c "exec ${line% &}" >"$WORK/bg$n.out" 2>"$WORK/bg$n.err" &
        PIDS="$PIDS $!"
        for _ in $(seq 100); do
            grep -q "stop with Ctrl-C" "$WORK/bg$n.out" 2>/dev/null && break
            sleep 0.1
        done
        grep -q "stop with Ctrl-C" "$WORK/bg$n.out" || fail "did not start: $line: $(cat "$WORK/bg$n.err")"
        ;;
    *)
        sh -c "$line" >"$WORK/out$n" 2>&1 </dev/null || fail "exit $?: $line: $(cat "$WORK/out$n")"
        ;;
    esac
    echo "ok: $line"
done <"$WORK/commands"
echo "PASS ($n commands)"
