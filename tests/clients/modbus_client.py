#!/usr/bin/env python3
"""A small Modbus/TCP client (FC 03) for the tests of `mblab conform-client`.

Without --defect it follows the Messaging on TCP/IP Implementation Guide V1.0b, 4.4.1.1: an
answer under another transaction id or from another unit is discarded and the wait goes on, an
exception is an error, a timeout is retried --retries times on the same connection, a closed
connection is opened again for the next try. Each --defect breaks one of those rules on purpose,
as clients in the field do, so the tests can show that the examiner finds exactly that one.

With --pipeline it sends two requests at once (COUNT registers at ADDRESS, then the COUNT after
them), pairs the answers with them by transaction id and prints the values in request order.

Given an rtu:///DEVICE?baud=N URL for HOST (PORT is then ignored) it is an RTU master on that
serial device instead (Modbus over Serial Line V1.02): a frame with a bad CRC or from another
slave address is discarded and the response timer keeps running (2.4.1), and a request to
address 0 is a broadcast, answered by none, after which it waits the turnaround delay.

With --poll S it polls as a PLC does, for `mblab conform-client --attach`: one transaction
(a new connection each), then S seconds of rest, over and over until it is stopped.

usage: modbus_client.py HOST PORT UNIT ADDRESS COUNT [--timeout S] [--retries N] [--defect D]
                        [--pipeline] [--poll S]
"""
import argparse
import os
import select
import socket
import struct
import sys
import termios
import time
import tty
import urllib.parse

DEFECTS = ["stale", "ignore-tid", "exception-zero", "no-timeout", "retry-forever", "wrong-unit",
           "fifo", "wrong-slave", "broadcast-wait"]

TURNAROUND = 0.1  # Modbus over Serial Line V1.02, 2.4.1: typically 100 to 200 ms
SILENCE = 0.01    # a pty passes bytes at once: a pause this long ends an RTU frame


def show(pdu, defect, count):
    """Prints the answer's values, or the error it is; the exit status."""
    if pdu[0] == 0x83:
        if defect == "exception-zero":
            print(" ".join("0" for _ in range(count)))
            return 0
        print("error: exception %02X" % pdu[1])
        return 1
    if pdu[0] != 3 or pdu[1] != 2 * count or len(pdu) != 2 + 2 * count:
        print("error: bad answer " + pdu.hex())
        return 1
    print(" ".join(str(v) for v in struct.unpack(">%dH" % count, pdu[2:])))
    return 0


def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return struct.pack("<H", crc)


def open_line(url):
    parts = urllib.parse.urlparse(url)
    baud = int(urllib.parse.parse_qs(parts.query).get("baud", ["19200"])[0])
    fd = os.open(parts.path, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    speed = getattr(termios, "B%d" % baud)
    attrs[4] = attrs[5] = speed
    termios.tcsetattr(fd, termios.TCSANOW, attrs)
    return fd


def read_frame(fd, deadline):
    """The bytes of one frame: from the first byte until the line goes quiet."""
    data = b""
    while True:
        wait = SILENCE if data else (None if deadline is None else deadline - time.monotonic())
        if wait is not None and wait <= 0:
            raise socket.timeout()
        ready, _, _ = select.select([fd], [], [], wait)
        if not ready:
            if data:
                return data
            raise socket.timeout()
        data += os.read(fd, 256)


def line_client(args, unit, address, count):
    fd = open_line(args.host)
    request = struct.pack(">BBHH", unit, 3, address, count)
    tries = 0
    while True:
        tries += 1
        os.write(fd, request + crc16(request))
        if unit == 0 and args.defect != "broadcast-wait":
            time.sleep(TURNAROUND)
            print("broadcast sent")
            return 0
        deadline = None if args.defect == "no-timeout" else time.monotonic() + args.timeout
        try:
            while True:
                frame = read_frame(fd, deadline)
                if len(frame) < 5 or crc16(frame[:-2]) != frame[-2:]:
                    continue
                if frame[0] == unit or args.defect == "wrong-slave":
                    break
        except socket.timeout:
            if args.defect == "retry-forever" or tries <= args.retries:
                continue
            print("error: no answer within %.3f s" % args.timeout)
            return 1
        return show(frame[1:-2], args.defect, count)


class Closed(Exception):
    pass


def read_exact(sock, size, deadline):
    data = b""
    while len(data) < size:
        if deadline is None:
            sock.settimeout(None)
        else:
            left = deadline - time.monotonic()
            if left <= 0:
                raise socket.timeout()
            sock.settimeout(left)
        chunk = sock.recv(size - len(data))
        if not chunk:
            raise Closed()
        data += chunk
    return data


def pipelined(args, unit, address, count):
    """Two requests outstanding; with the defect "fifo" answers are paired by arrival."""
    sock = socket.create_connection((args.host, int(args.port)), timeout=args.timeout)
    asked = {1: address, 2: address + count}
    sock.sendall(b"".join(struct.pack(">HHHBBHH", tid, 0, 6, unit, 3, first, count)
                          for tid, first in asked.items()))
    deadline = time.monotonic() + args.timeout
    values = {}
    try:
        for arrival in (1, 2):
            their_tid, _, length, _ = struct.unpack(">HHHB", read_exact(sock, 7, deadline))
            pdu = read_exact(sock, length - 1, deadline)
            tid = arrival if args.defect == "fifo" else their_tid
            values[tid] = struct.unpack(">%dH" % count, pdu[2:2 + 2 * count])
    except (socket.timeout, Closed, struct.error):
        print("error: no answers")
        return 1
    print(" ".join(str(v) for tid in sorted(asked) for v in values.get(tid, ())))
    return 0


def main():
    args = parse()
    if args.poll is None:
        return transaction(args)
    while True:
        try:
            transaction(args)
        except OSError as error:  # refused or reset between the examiner's scenarios
            print("error: %s" % error)
        sys.stdout.flush()
        time.sleep(args.poll)


def parse():
    parser = argparse.ArgumentParser()
    for name in ["host", "port", "unit", "address", "count"]:
        parser.add_argument(name)
    parser.add_argument("--timeout", type=float, default=1.0)
    parser.add_argument("--retries", type=int, default=0)
    parser.add_argument("--defect", choices=DEFECTS)
    parser.add_argument("--pipeline", action="store_true")
    parser.add_argument("--poll", type=float)
    return parser.parse_args()


def transaction(args):
    unit, address, count = int(args.unit), int(args.address), int(args.count)
    if args.host.startswith("rtu://"):
        return line_client(args, unit, address, count)
    if args.pipeline:
        return pipelined(args, unit, address, count)
    defect = args.defect
    sock = None
    tid = 0
    sent = set()
    tries = 0
    while True:
        tries += 1
        if sock is None:
            sock = socket.create_connection((args.host, int(args.port)), timeout=args.timeout)
        tid = (tid + 1) & 0xFFFF
        sent.add(tid)
        sock.sendall(struct.pack(">HHHBBHH", tid, 0, 6, unit, 3, address, count))
        deadline = None if defect == "no-timeout" else time.monotonic() + args.timeout
        try:
            while True:
                head = read_exact(sock, 7, deadline)
                their_tid, _, length, their_unit = struct.unpack(">HHHB", head)
                pdu = read_exact(sock, length - 1, deadline)
                tid_ok = their_tid == tid
                if defect == "ignore-tid":
                    tid_ok = True
                elif defect == "stale":
                    tid_ok = their_tid in sent
                unit_ok = their_unit == unit or defect == "wrong-unit"
                if tid_ok and unit_ok:
                    break
        except socket.timeout:
            if defect == "retry-forever" or tries <= args.retries:
                continue
            print("error: no answer within %.3f s" % args.timeout)
            return 1
        except Closed:
            sock.close()
            sock = None
            if tries <= args.retries:
                continue
            print("error: the connection closed")
            return 1
        if sock is not None:
            sock.close()
        return show(pdu, defect, count)


if __name__ == "__main__":
    sys.exit(main())
