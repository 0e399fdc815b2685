#!/bin/sh
# A client that sends its last request and at once ends its side (FIN, or TLS close_notify), then
# reads until the server closes: socat does exactly that when its input ends. Nobody here wrote it.
#  - Modbus/TCP: each connection must be answered and closed by the server, with no idle timeout
#    to end it. (socat's FIN comes a moment after the request, so this does not reproduce the race
#    of a FIN read together with the request; ServerSession.ClosesAfterAnsweringARequestWhoseFin-
#    CameWithIt, in the integration tests, does.)
#  - mbaps:// over TLS 1.3, where each direction closes on its own (RFC 8446 6.1): an answer the
#    device still owes when close_notify comes (a 300 ms delay fault) is sent, then the server's
#    close_notify.
#  - mbaps:// over TLS 1.2, which answers close_notify at once and discards pending writes
#    (RFC 5246 7.2.1): no answer, and the session ends without waiting for the delay.
# A hang would show as `timeout` ending socat (status 124).
# Usage: test_serve_half_close.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-half-close.XXXXXX")
. "$HERE/serve_lib.sh"
command -v socat >/dev/null || fail "socat is not installed"

REQUEST='\000\001\000\000\000\006\001\003\000\000\000\002'
ANSWER=00010000000701030453454d49

start_serve --idle-timeout 0
runs=40
for run in $(seq "$runs"); do
    status=0
    # shellcheck disable=SC2059 # the request is the format: printf turns its escapes to bytes
    got=$(printf "$REQUEST" | timeout 10 socat -t 30 - "TCP:127.0.0.1:$SERVE_PORT" 2>"$WORK/socat.err" |
        od -An -tx1 | tr -d ' \n') || status=$?
    [ "$got" = "$ANSWER" ] || fail "connection $run: expected $ANSWER, got '$got' ($(cat "$WORK/socat.err"))"
    # socat exits when the server closes; `timeout` would end it first on a hang.
    [ "$status" -eq 0 ] || fail "connection $run was answered but not closed by the server (status $status)"
done
echo "ok: $runs connections that sent a request and their FIN at once were answered and closed"
stop_serve

PKI="$WORK/pki"
"$MBLAB" pki "$PKI" >/dev/null || fail "mblab pki"
# The reference device, with FC 03 answered after 300 ms.
{
    cat "$HERE/../../profiles/reference.toml"
    printf '\n[[unit.faults]]\naction = "delay"\ndelay_ms = 300\nfunctions = [3]\n'
} >"$WORK/delayed.toml"
start_serve_tls "$PKI" "$WORK/delayed.toml"

# tls_request VERSION: the request, close_notify as socat's input ends, and what came back.
tls_request() {
    # shellcheck disable=SC2059
    printf "$REQUEST" | timeout 10 socat -d -d -t 30 - "OPENSSL:127.0.0.1:$SERVE_PORT,cert=$PKI/client-Operator.pem,key=$PKI/client-Operator.key,cafile=$PKI/ca.pem,commonname=localhost,openssl-min-proto-version=$1,openssl-max-proto-version=$1" \
        2>"$WORK/tls.err" | od -An -tx1 | tr -d ' \n'
}

got=$(tls_request TLS1.3) || fail "TLS 1.3: socat failed or hung: $(cat "$WORK/tls.err")"
grep -q "SSL proto version used: TLSv1.3" "$WORK/tls.err" || fail "TLS 1.3 was not used: $(cat "$WORK/tls.err")"
[ "$got" = "$ANSWER" ] ||
    fail "TLS 1.3: the answer owed at close_notify: expected $ANSWER, got '$got' ($(cat "$WORK/tls.err"))"
echo "ok: over TLS 1.3 the answer still owed when the client's close_notify came was sent"

got=$(tls_request TLS1.2) || fail "TLS 1.2: socat failed or hung: $(cat "$WORK/tls.err")"
grep -q "SSL proto version used: TLSv1.2" "$WORK/tls.err" || fail "TLS 1.2 was not used: $(cat "$WORK/tls.err")"
[ -z "$got" ] || fail "TLS 1.2: a write after close_notify was answered: '$got'"
echo "ok: over TLS 1.2 close_notify was answered at once, the pending answer discarded"
stop_serve
echo "PASS"
