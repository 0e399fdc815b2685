#!/bin/sh
# The HTTP side of `mblab serve --http` under the inputs of the attack run that once ended it or
# took it over: a GET of /%FF, a 400 MB chunked body, 1 MB of '[', 500 slow clients while
# /metrics is scraped, a 1000-part Range. Prints serve's resident memory after each and the
# scrape times; no pass or fail (tests/integration/test_http_hardening.cpp holds the checks).
#
# Usage: bench/run_http_attack_figures.sh [MBLAB]   (default build/mblab)
set -u
WORK=$(mktemp -d "${TMPDIR:-/tmp}/mblab-http-attack.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
M=${1:-build/mblab}
$M serve --listen tcp://127.0.0.1:0 --http 127.0.0.1:0 > $WORK/serve.out 2>&1 &
PID=$!
sleep 1
URL=$(grep -o 'http://127.0.0.1:[0-9]*' $WORK/serve.out); TOKEN=$(grep -o 'token=[0-9a-f]*' $WORK/serve.out | cut -d= -f2)
rss() { grep VmRSS /proc/$PID/status | awk '{print $2}'; }
echo "serve RSS at start: $(rss) KiB"
curl -s -o /dev/null -w "GET /%FF: %{http_code}\n" "$URL/%FF"
python3 - "$URL" "$TOKEN" <<'PY'
import socket, sys, time
url, token = sys.argv[1], sys.argv[2]
port = int(url.rsplit(':', 1)[1])
s = socket.create_connection(('127.0.0.1', port))
s.sendall(('POST /api/units/1/faults HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nAuthorization: Bearer %s\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n' % (port, token)).encode())
chunk = b'100000\r\n' + b'[' * 0x100000 + b'\r\n'
sent = 0
s.settimeout(5)
try:
    for i in range(400):
        s.sendall(chunk); sent += 1
except Exception as e:
    pass
try:
    print('chunked 400 MB: answer', s.recv(200).split(b'\r\n')[0].decode(), '; MB taken before close:', sent)
except Exception as e:
    print('chunked: no answer', e)
PY
echo "serve RSS after 400 MB chunked: $(rss) KiB"
head -c 1000000 /dev/zero | tr '\0' '[' > $WORK/deep.json
curl -s -w " %{http_code}\n" -X PUT -H "Authorization: Bearer $TOKEN" -H 'Content-Type: application/json' --data-binary @$WORK/deep.json "$URL/api/units/1/coils/0"
echo "serve RSS after 1 MB of '[': $(rss) KiB"
python3 - "$URL" <<'PY' &
import socket, sys, time
port = int(sys.argv[1].rsplit(':', 1)[1])
conns = []
for i in range(500):
    c = socket.create_connection(('127.0.0.1', port)); c.sendall(b'GET /metrics HTTP/1.1\r\nHo'); conns.append(c)
for r in range(30):
    time.sleep(1)
    for c in conns:
        try: c.sendall(b'.')
        except Exception: pass
PY
SLOW=$!
sleep 2
for i in 1 2 3 4 5; do curl -s -o /dev/null -m 10 -w "scrape under 500 slow clients: %{http_code} in %{time_total} s\n" "$URL/metrics"; sleep 1; done
echo "serve RSS with 500 slow clients: $(rss) KiB"
R="Range: bytes=0-0"; i=1; while [ $i -lt 1000 ]; do R="$R,$i-$i"; i=$((i+1)); done
curl -s -o /dev/null -H "$R" -w "1000-part Range: %{http_code}, %{size_download} bytes\n" "$URL/"
curl -s -o /dev/null -w "no Range: %{http_code}, %{size_download} bytes\n" "$URL/"
kill $SLOW 2>/dev/null; kill $PID
