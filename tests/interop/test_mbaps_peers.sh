#!/bin/sh
# Interop for Modbus/TCP Security (mbaps://) with peers nobody here wrote:
#  - Debian's openssl s_client against `mblab serve`: MBAP bytes in, the answer's bytes out (one
#    request, and 3000 pipelined in one burst); TLS 1.1, no client certificate and a foreign CA
#    refused.
#  - pymodbus 3.0's TLS client (MBAP framing) against `mblab serve`: roles enforced; its default
#    bare-PDU framing refused with the reason logged.
#  - pymodbus 3.0's TLS server against `mblab read mbaps://`.
# Usage: test_mbaps_peers.sh MBLAB BUILD_DIR
set -eu
MBLAB=$1
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-mbaps.XXXXXX")
. "$HERE/serve_lib.sh"
PEER_PID=""
trap '[ -n "$PEER_PID" ] && kill "$PEER_PID" 2>/dev/null; cleanup' EXIT

PKI="$WORK/pki"
"$MBLAB" pki "$PKI" >/dev/null || fail "mblab pki"

start_serve_tls "$PKI"

# s_client -quiet prints only what the server sends; the request is FC 03, holding 0..1.
s_client() {
    timeout 10 openssl s_client -quiet -connect "127.0.0.1:$SERVE_PORT" -CAfile "$PKI/ca.pem" \
        -verify_return_error "$@"
}
request() { printf '\000\001\000\000\000\006\001\003\000\000\000\002'; sleep 1; }

answer=$(request | s_client -cert "$PKI/client-Operator.pem" -key "$PKI/client-Operator.key" \
    2>"$WORK/s_client.err" | od -An -tx1 | tr -d ' \n')
[ "$answer" = "00010000000701030453454d49" ] ||
    fail "openssl s_client: expected 00010000000701030453454d49, got '$answer' ($(cat "$WORK/s_client.err"))"
echo "ok: openssl s_client with client-Operator gets the MBAP answer"

# Requests 1.5 s apart: between them the server's session rests and gives its record buffers back
# (docs/security.md), and each next record must take them again (TLS 1.3 and TLS 1.2).
paced() {
    for t in 1 2 3; do
        printf "\\000\\00$t\\000\\000\\000\\006\\001\\003\\000\\000\\000\\002"
        sleep 1.5
    done
}
for version in -tls1_3 -tls1_2; do
    answers=$(paced | s_client "$version" -cert "$PKI/client-Operator.pem" \
        -key "$PKI/client-Operator.key" 2>"$WORK/paced.err" | od -An -tx1 | tr -d ' \n')
    expected=""
    for t in 1 2 3; do expected="${expected}000${t}0000000701030453454d49"; done
    [ "$answers" = "$expected" ] ||
        fail "openssl s_client $version, requests 1.5 s apart: got '$answers' ($(cat "$WORK/paced.err"))"
    echo "ok: openssl s_client $version gets every answer to requests 1.5 s apart"
done

# 3000 pipelined requests in one burst (36 kB: more than one read of a TLS record's worth takes,
# and more than the server queues at once, so it pauses reading and reads again): every answer
# comes back, in order.
burst() {
    /usr/bin/python3 -c 'import sys
for t in range(3000):
    sys.stdout.buffer.write(bytes([t >> 8, t & 255, 0, 0, 0, 6, 1, 3, 0, 0, 0, 2]))'
    sleep 3
}
burst | s_client -cert "$PKI/client-Operator.pem" -key "$PKI/client-Operator.key" \
    2>"$WORK/burst.err" >"$WORK/burst.out" || true
/usr/bin/python3 - "$WORK/burst.out" <<'PY' || fail "openssl s_client burst: $(cat "$WORK/burst.err")"
import sys
data = open(sys.argv[1], "rb").read()
answers = [data[i:i + 13] for i in range(0, len(data), 13)]
if len(data) != 3000 * 13:
    sys.exit(f"{len(data)} bytes of answers, not {3000 * 13}")
for t, answer in enumerate(answers):
    if answer[:2] != bytes([t >> 8, t & 255]) or answer[2:9] != bytes([0, 0, 0, 7, 1, 3, 4]):
        sys.exit(f"answer {t} is {answer.hex(' ')}")
PY
echo "ok: openssl s_client's 3000 pipelined requests in one burst are all answered, in order"

for version in -tls1 -tls1_1; do
    if request | s_client "$version" -cipher 'DEFAULT:@SECLEVEL=0' \
        -cert "$PKI/client-Operator.pem" -key "$PKI/client-Operator.key" \
        >"$WORK/old.out" 2>"$WORK/old.err"; then
        [ -s "$WORK/old.out" ] && fail "openssl s_client $version got an answer"
    fi
    [ -s "$WORK/old.out" ] && fail "openssl s_client $version got bytes: $(od -An -tx1 "$WORK/old.out")"
    echo "ok: openssl s_client $version is refused"
done

for name in "" client-foreign-ca client-expired client-self-signed; do
    set -- 
    [ -n "$name" ] && set -- -cert "$PKI/$name.pem" -key "$PKI/$name.key"
    request | s_client "$@" >"$WORK/neg.out" 2>"$WORK/neg.err" || true
    [ -s "$WORK/neg.out" ] && fail "openssl s_client ${name:-without a certificate} got an answer"
    grep -qi "alert" "$WORK/neg.err" || fail "openssl s_client ${name:-without a certificate}: no TLS alert: $(cat "$WORK/neg.err")"
    echo "ok: openssl s_client ${name:-without a certificate} is refused with an alert"
done

/usr/bin/python3 "$HERE/pymodbus_tls_client.py" "$SERVE_PORT" "$PKI" mbap || fail "pymodbus TLS client (MBAP)"
/usr/bin/python3 "$HERE/pymodbus_tls_client.py" "$SERVE_PORT" "$PKI" bare-pdu || fail "pymodbus TLS client (bare PDU)"
sleep 0.2
grep -q "refused a TLS client: it sent a bare PDU without the MBAP header" "$WORK/serve.err" ||
    fail "serve did not log the bare-PDU refusal: $(cat "$WORK/serve.err")"
echo "ok: serve logs why it refused the bare-PDU client"
grep -q "refused a TLS client: the client's certificate was refused: certificate has expired" "$WORK/serve.err" ||
    fail "serve did not log the expired certificate: $(cat "$WORK/serve.err")"
stop_serve

# Certificates made by the openssl CLI, not by mblab pki: an RSA CA, an RSA server certificate and
# a client whose role extension the CLI writes as ASN1:UTF8String.
O="$WORK/openssl-pki"
mkdir "$O"
(
    cd "$O"
    openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.pem -days 2 -subj /CN=cli-ca \
        -addext basicConstraints=critical,CA:TRUE -addext keyUsage=keyCertSign
    openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr -subj /CN=cli-server
    printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\nextendedKeyUsage=serverAuth\n' >server.ext
    openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 \
        -extfile server.ext -out server.pem
    openssl req -newkey rsa:2048 -nodes -keyout client.key -out client.csr -subj /CN=cli-client
    printf 'extendedKeyUsage=clientAuth\n1.3.6.1.4.1.50316.802.1=ASN1:UTF8String:Operator\n' >client.ext
    openssl x509 -req -in client.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 \
        -extfile client.ext -out client.pem
) >"$WORK/openssl-pki.log" 2>&1 || fail "openssl CLI PKI: $(cat "$WORK/openssl-pki.log")"
start_serve_tls "$O"
"$MBLAB" write "mbaps://localhost:$SERVE_PORT" register 40 7 --cert "$O/client.pem" \
    --key "$O/client.key" --ca "$O/ca.pem" -v >"$WORK/cli.out" 2>"$WORK/cli.err" ||
    fail "mblab write with openssl CLI certificates: $(cat "$WORK/cli.err")"
grep -q "we presented role Operator" "$WORK/cli.err" || fail "role of the CLI certificate: $(cat "$WORK/cli.err")"
echo "ok: certificates made by the openssl CLI serve and connect, the role read as Operator"
stop_serve

# pymodbus as the server, our client against it.
PEER_PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
/usr/bin/python3 "$HERE/pymodbus_tls_server.py" "$PEER_PORT" "$PKI" >"$WORK/peer.log" 2>&1 &
PEER_PID=$!
for _ in $(seq 100); do
    "$MBLAB" read "mbaps://localhost:$PEER_PORT" holding 0 2 --cert "$PKI/client-Operator.pem" \
        --key "$PKI/client-Operator.key" --ca "$PKI/ca.pem" --json >"$WORK/read.json" 2>"$WORK/read.err" && break
    sleep 0.1
done
/usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); sys.exit([v["value"] for v in d["values"]] != [100, 101])' "$WORK/read.json" ||
    fail "mblab read from pymodbus's TLS server: $(cat "$WORK/read.json" "$WORK/read.err")"
echo "ok: mblab read mbaps:// reads pymodbus's TLS server"
if "$MBLAB" read "mbaps://localhost:$PEER_PORT" holding 0 2 --cert "$PKI/client-Operator.pem" \
    --key "$PKI/client-Operator.key" --ca "$PKI/foreign-ca.pem" 2>"$WORK/foreign.err"; then
    fail "mblab read trusted a server signed by another CA"
fi
grep -q "the server.s certificate was refused: " "$WORK/foreign.err" ||
    fail "the refusal of the server's certificate does not say why: $(cat "$WORK/foreign.err")"
echo "ok: mblab read refuses a server its --ca did not sign: $(cat "$WORK/foreign.err")"
echo "PASS"
