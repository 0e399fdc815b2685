"""Opens N idle connections to a server and holds them until stdin closes: plain TCP, or TLS
with a client certificate. Prints "ready N" once every connection is up (TLS: handshake done).

Usage: idle_tls_connections.py PORT N [CERT KEY CA]"""
import socket
import ssl
import sys

port, count = int(sys.argv[1]), int(sys.argv[2])
context = None
if len(sys.argv) > 3:
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.load_cert_chain(sys.argv[3], sys.argv[4])
    context.load_verify_locations(sys.argv[5])
held = []
for _ in range(count):
    sock = socket.create_connection(("127.0.0.1", port))
    if context is not None:
        sock = context.wrap_socket(sock, server_hostname="localhost")
    held.append(sock)
print(f"ready {len(held)}", flush=True)
sys.stdin.read()
