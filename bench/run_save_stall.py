#!/usr/bin/env python3
"""Reads answered while `mblab serve --state` saves the reference profile's state every 250 ms.

Usage: bench/run_save_stall.py MBLAB. One client reads one register in a closed loop for 5 s and
prints how many reads took over 2 ms, the median, p99.9 and the slowest."""
import re, socket, subprocess, sys, signal, time, tempfile, os
binary = sys.argv[1]
d = tempfile.mkdtemp(dir="/var/tmp")
p = subprocess.Popen([binary, "serve", "--listen", "tcp://127.0.0.1:0", "--state", d + "/s.json", "--save-interval", "0.25"], stdout=subprocess.PIPE, text=True)
port = int(re.search(r":(\d+),", p.stdout.readline()).group(1))
s = socket.create_connection(("127.0.0.1", port)); s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
req = bytes.fromhex("000100000006010300000001")
lat = []
end = time.monotonic() + 5
while time.monotonic() < end:
    t = time.perf_counter(); s.sendall(req); s.recv(64); lat.append(time.perf_counter() - t)
lat.sort()
over = sum(1 for x in lat if x > 0.002)
print(f"{binary}: {over} reads over 2 ms; {len(lat)} reads in 5 s with a save every 250 ms; p50 {lat[len(lat)//2]*1e3:.3f} ms, p99.9 {lat[int(len(lat)*0.999)]*1e3:.2f} ms, max {lat[-1]*1e3:.2f} ms")
p.send_signal(signal.SIGTERM); p.wait()
