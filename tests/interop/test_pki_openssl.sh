#!/bin/sh
# Interop: the files `mblab pki` writes, as Debian's openssl CLI sees them: the client
# certificates verify (or fail) against ca.pem for the reason their names give, the role
# extension is there as a UTF8String (an IA5String in client-ia5-role), and a TLS 1.2 handshake
# with mutual authentication succeeds with client-Operator and fails with client-foreign-ca.
# Also the command's own promises: mode 0600 files, no overwrite without --force, no '/' in a role.
# Usage: test_pki_openssl.sh MBLAB BUILD_DIR
set -eu
# Absolute: the checks below run inside the PKI directory.
MBLAB=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-pki.XXXXXX")
PKI=$WORK/pki
OID=1.3.6.1.4.1.50316.802.1
HERE=$(cd "$(dirname "$0")" && pwd)
. "$HERE/serve_lib.sh"

# --- the command ---
"$MBLAB" pki "$PKI" >"$WORK/pki.out" 2>"$WORK/pki.err" ||
    { cat "$WORK/pki.err" >&2; fail "mblab pki $PKI"; }
grep -q "^  mblab serve --listen mbaps://127.0.0.1:8802 --cert $PKI/server.pem" "$WORK/pki.out" ||
    fail "no serve line in the next: hint"
[ "$(stat -c %a "$PKI")" = 700 ] || fail "$PKI is mode $(stat -c %a "$PKI"), not 700"
files=0
for file in "$PKI"/*; do
    files=$((files + 1))
    mode=$(stat -c %a "$file")
    [ "$mode" = 600 ] || fail "$file is mode $mode, not 600"
done
[ "$files" = 30 ] || fail "$files files written, expected 30"

status=0
"$MBLAB" pki "$PKI" >"$WORK/again.out" 2>"$WORK/again.err" || status=$?
[ "$status" = 2 ] || fail "a second run without --force exited $status, not 2"
[ "$(wc -l <"$WORK/again.err")" = 1 ] || fail "a second run said: $(cat "$WORK/again.err")"
grep -q "exists already" "$WORK/again.err" || fail "a second run said: $(cat "$WORK/again.err")"
"$MBLAB" pki "$PKI" --force >/dev/null 2>"$WORK/force.err" ||
    fail "--force: $(cat "$WORK/force.err")"

status=0
"$MBLAB" pki "$WORK/slash" --role a/b >/dev/null 2>"$WORK/slash.err" || status=$?
[ "$status" = 2 ] || fail "--role a/b exited $status, not 2"
[ "$(wc -l <"$WORK/slash.err")" = 1 ] || fail "--role a/b said: $(cat "$WORK/slash.err")"
[ ! -e "$WORK/slash" ] || fail "--role a/b wrote $WORK/slash"

# --- openssl verify ---
cd "$PKI"
verify() {
    openssl verify -CAfile ca.pem -purpose sslclient "$1.pem" >"$WORK/verify.out" 2>&1
}
for name in client-Operator client-ReadOnly client-Administrator client-norole; do
    verify "$name" || fail "openssl verify $name: $(cat "$WORK/verify.out")"
done
verify_fails() {
    ! verify "$1" || fail "openssl verify accepted $1"
    grep -q "$2" "$WORK/verify.out" || fail "openssl verify $1: $(cat "$WORK/verify.out"), expected '$2'"
}
verify_fails client-expired "certificate has expired"
verify_fails client-foreign-ca "unable to get local issuer certificate"
verify_fails client-self-signed "self-signed certificate"
openssl verify -CAfile ca.pem -purpose sslserver server.pem >"$WORK/verify.out" 2>&1 ||
    fail "openssl verify server: $(cat "$WORK/verify.out")"
# The server certificates a client must refuse (conform-client's scenario 12), each for its reason.
server_fails() {
    ! openssl verify -CAfile ca.pem -purpose sslserver "$@" >"$WORK/verify.out" 2>&1 ||
        fail "openssl verify accepted $*"
}
server_fails server-expired.pem
grep -q "certificate has expired" "$WORK/verify.out" || fail "server-expired: $(cat "$WORK/verify.out")"
server_fails server-foreign-ca.pem
grep -q "unable to get local issuer certificate" "$WORK/verify.out" ||
    fail "server-foreign-ca: $(cat "$WORK/verify.out")"
server_fails -verify_ip 127.0.0.1 server-wrong-name.pem
grep -q "IP address mismatch" "$WORK/verify.out" || fail "server-wrong-name: $(cat "$WORK/verify.out")"

# --- the role extension as openssl prints and parses it ---
openssl x509 -in client-Operator.pem -noout -text >"$WORK/text" || fail "openssl x509 -text"
grep -q "$OID:" "$WORK/text" || fail "no $OID extension in openssl x509 -text"
if grep -q "$OID: critical" "$WORK/text"; then fail "the role extension is critical"; fi
openssl x509 -in server.pem -noout -ext subjectAltName >"$WORK/san" || fail "openssl x509 -ext"
for name in DNS:localhost "IP Address:127.0.0.1" "IP Address:0:0:0:0:0:0:0:1"; do
    grep -q "$name" "$WORK/san" || fail "server.pem names no $name: $(cat "$WORK/san")"
done

# role_type NAME: the ASN.1 type inside the role extension's OCTET STRING.
role_type() {
    offset=$(openssl asn1parse -in "$1.pem" | grep -A2 ":$OID\$" | sed -n 's/^ *\([0-9]*\):.*OCTET STRING.*/\1/p')
    [ -n "$offset" ] || fail "no role extension found by openssl asn1parse in $1.pem"
    openssl asn1parse -in "$1.pem" -strparse "$offset" | sed -n 's/.*prim: *\([A-Z0-9]*\) *:\(.*\)/\1 \2/p'
}
[ "$(role_type client-Operator)" = "UTF8STRING Operator" ] ||
    fail "client-Operator's role: $(role_type client-Operator)"
[ "$(role_type client-ia5-role)" = "IA5STRING Administrator" ] ||
    fail "client-ia5-role's role: $(role_type client-ia5-role)"
[ "$(openssl asn1parse -in client-two-roles.pem | grep -c ":$OID\$")" = 2 ] ||
    fail "client-two-roles has not two role extensions"
! openssl asn1parse -in client-norole.pem | grep -q ":$OID\$" || fail "client-norole has a role"

# --- a TLS 1.2 handshake with mutual authentication ---
# Port 0: s_server prints the port it got ("ACCEPT 127.0.0.1:PORT"), so runs never race for one.
# TLS 1.2: a refused client certificate then fails the handshake itself, where TLS 1.3 would
# report it only at the client's first read. -www: the server never reads its stdin, whose end
# would stop it after the first connection.
openssl s_server -accept 127.0.0.1:0 -cert server.pem -key server.key -CAfile ca.pem \
    -Verify 1 -verify_return_error -tls1_2 -www >"$WORK/server.out" 2>&1 </dev/null &
OTHER_PID=$!
port=""
for _ in $(seq 50); do
    port=$(sed -n 's/^ACCEPT 127\.0\.0\.1:\([0-9]*\)$/\1/p' "$WORK/server.out")
    [ -n "$port" ] && break
    kill -0 "$OTHER_PID" 2>/dev/null || fail "openssl s_server: $(cat "$WORK/server.out")"
    sleep 0.1
done
[ -n "$port" ] || fail "openssl s_server printed no port: $(cat "$WORK/server.out")"

handshake() {
    echo | timeout 10 openssl s_client -connect "127.0.0.1:$port" -cert "$1.pem" -key "$1.key" \
        -CAfile ca.pem -verify_return_error -verify_ip 127.0.0.1 >"$WORK/client.out" 2>&1
}
handshake client-Operator || fail "handshake with client-Operator: $(tail -5 "$WORK/client.out")"
grep -q "Verify return code: 0 (ok)" "$WORK/client.out" ||
    fail "client-Operator did not verify the server: $(tail -5 "$WORK/client.out")"
# refused NAME: the server ends the handshake with an alert (not a timeout).
refused() {
    status=0
    handshake "$1" || status=$?
    [ "$status" != 0 ] || fail "the server accepted $1"
    [ "$status" != 124 ] || fail "the handshake with $1 timed out"
    grep -q "alert" "$WORK/client.out" || fail "no alert for $1: $(tail -5 "$WORK/client.out")"
}
refused client-foreign-ca
refused client-self-signed
refused client-expired
handshake client-norole || fail "handshake with client-norole (TLS accepts it; the role is NULL)"
kill "$OTHER_PID"
OTHER_PID=""

# --- docs/security.md's three commands: mblab serve over mbaps and mblab read with the files ---
"$MBLAB" serve --listen mbaps://127.0.0.1:0 --cert server.pem --key server.key --ca ca.pem \
    >"$WORK/serve.out" 2>"$WORK/serve.err" &
SERVE_PID=$!
port=""
for _ in $(seq 100); do
    port=$(sed -n 's/.* on mbaps:\/\/127\.0\.0\.1:\([0-9]*\).*/\1/p' "$WORK/serve.out")
    [ -n "$port" ] && break
    kill -0 "$SERVE_PID" 2>/dev/null || break
    sleep 0.1
done
[ -n "$port" ] || fail "mblab serve mbaps:// did not start: $(cat "$WORK/serve.err")"
# read_as NAME: mblab read of 4 holding registers with client-NAME's certificate; sets $status.
read_as() {
    status=0
    timeout 20 "$MBLAB" read "mbaps://127.0.0.1:$port" holding 0 4 --cert "client-$1.pem" \
        --key "client-$1.key" --ca ca.pem >"$WORK/read.out" 2>"$WORK/read.err" || status=$?
    [ "$status" != 124 ] || fail "mblab read as $1 timed out"
}
read_as Operator
[ "$status" = 0 ] || fail "mblab read as Operator exited $status: $(cat "$WORK/read.err")"
[ "$(grep -c '^[0-3] (0x000[0-3])' "$WORK/read.out")" = 4 ] ||
    fail "mblab read as Operator printed: $(cat "$WORK/read.out")"
for name in norole expired foreign-ca self-signed two-roles ia5-role; do
    read_as "$name"
    [ "$status" != 0 ] || fail "mblab serve let client-$name read"
done

echo "PASS"
