#!/usr/bin/env python3
"""A longer attack on `armjog sim` than the tests run: garbage, near-frames, truncated and
stalled frames, floods, slowloris trickles and idle connections against its Talos (ICD, crc16) and
Modbus servers, from several threads at once. Every hostile input is followed by a valid request
(on the same connection where that makes sense) and fresh-connection health checks run
throughout. Prints the figures: inputs tried per kind, outcomes, replies missing, whether the
process and its arm task survived, VmRSS and descriptors before and after.

    cargo build --release
    python3 benches/attack.py [--bin target/release/armjog] [--seconds 60] [--threads 6] [--json]

Standard library only. Linux (reads /proc/PID/status and /proc/PID/fd).
"""

import argparse
import collections
import json
import os
import random
import socket
import struct
import subprocess
import threading
import time

REPLY_BOUND = 5.0  # seconds a valid request may wait for its reply
HEADER_LEN = 10
MAX_PAYLOAD = 1024


# --- Talos (ICD wrapper, CRC-16/CCITT-FALSE) -------------------------------------------------


def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def talos_frame(ident, command, payload, corrupt=0):
    body = struct.pack(">IHHH", ident, 0, command, len(payload)) + bytes(payload)
    return body + struct.pack(">H", crc16(body) ^ corrupt)


def handshake(ident):
    return talos_frame(ident, 0x0000, b"\x00\x01")


# Request payload lengths the ICD fixes, for commands with one fixed length.
FIXED_LENGTHS = {0x0000: 2, 0x0001: 16, 0x0002: 4, 0x0003: 2, 0x0004: 0, 0x0005: 20,
                 0x0006: 3, 0x0007: 0, 0x0009: 0, 0x000A: 1}


def rand_bytes(rng, n):
    return bytes(rng.getrandbits(8) for _ in range(n))


def talos_garbage(kind, rng, valid_len):
    """(bytes, the tail a truncated frame lacks: empty for other kinds)."""
    gid = rng.getrandbits(31)
    if kind == "random":
        return rand_bytes(rng, rng.randrange(1, 512)), b""
    return talos_near_frame(kind, rng, valid_len, gid)


def talos_near_frame(kind, rng, valid_len, gid):
    if kind == "truncated_short":
        # A plausible frame missing no more bytes than the valid frame after it supplies.
        command = rng.choice([0x0000, 0x0002, 0x0003, 0x000A])
        frame = talos_frame(gid, command, rand_bytes(rng, FIXED_LENGTHS[command]))
        cut = len(frame) - rng.randrange(1, min(valid_len, len(frame) - HEADER_LEN) + 1)
        return frame[:cut], frame[cut:]
    if kind == "truncated_long":
        # A hardware operation announcing 500 payload bytes, of which 20 come (issue 9 item 6).
        frame = talos_frame(gid, 0x0008, bytes(500))
        return frame[:HEADER_LEN + 20], frame[HEADER_LEN + 20:]
    return talos_whole_near_frame(kind, rng, gid), b""


def talos_whole_near_frame(kind, rng, gid):
    if kind == "bad_checksum":
        command = rng.choice(list(FIXED_LENGTHS))
        payload = rand_bytes(rng, FIXED_LENGTHS[command])
        return talos_frame(gid, command, payload, corrupt=rng.randrange(1, 0x10000))
    if kind == "oversized_length":
        length = rng.randrange(MAX_PAYLOAD + 1, 0x10000)
        return struct.pack(">IHHH", gid, 0, rng.randrange(0, 0x12), length) + rand_bytes(rng, 32)
    if kind == "wrong_length":
        command = rng.choice(list(FIXED_LENGTHS))
        length = rng.choice([n for n in range(41) if n != FIXED_LENGTHS[command]])
        return talos_frame(gid, command, rand_bytes(rng, length))
    if kind == "unknown_command":
        return talos_frame(gid, rng.randrange(0x12, 0x8000), rand_bytes(rng, rng.randrange(41)))
    if kind == "reply_frame":
        return talos_frame(gid, 0x8000 | rng.getrandbits(15), rand_bytes(rng, rng.randrange(41)))
    raise ValueError(kind)


TALOS_KINDS = ["random", "bad_checksum", "oversized_length", "wrong_length", "unknown_command",
               "reply_frame", "truncated_short", "truncated_long"]


def read_talos_reply(sock, want_id, bound):
    """The reply frame to `want_id`, or 'closed' / 'silent'."""
    deadline = time.monotonic() + bound
    buf = b""
    while True:
        while len(buf) >= HEADER_LEN:
            ident, _, command, length = struct.unpack(">IHHH", buf[:HEADER_LEN])
            total = HEADER_LEN + length + 2
            if len(buf) < total:
                break
            frame, buf = buf[:total], buf[total:]
            if ident == want_id | 1 and command & 0x8000:
                return frame
        left = deadline - time.monotonic()
        if left <= 0:
            return "silent"
        sock.settimeout(left)
        try:
            chunk = sock.recv(65536)
        except socket.timeout:
            return "silent"
        except OSError:
            return "closed"
        if not chunk:
            return "closed"
        buf += chunk


def handshake_ok(frame):
    if not isinstance(frame, bytes) or len(frame) < HEADER_LEN + 2:
        return False
    _, _, command, length = struct.unpack(">IHHH", frame[:HEADER_LEN])
    code = struct.unpack(">H", frame[HEADER_LEN:HEADER_LEN + 2])[0]
    return command == 0x8000 and length == 4 and code == 0


# --- Modbus TCP ------------------------------------------------------------------------------


def read_state(tid):
    return struct.pack(">HHHBBHH", tid, 0, 6, 1, 4, 0, 1)


def mbap(tid, pdu, protocol=0, unit=1, length=None):
    if length is None:
        length = len(pdu) + 1
    return struct.pack(">HHHB", tid, protocol, length & 0xFFFF, unit) + bytes(pdu)


EDGE_ADDRESSES = [0, 1, 100, 200, 219, 65534, 65535]
EDGE_COUNTS = [0, 1, 2, 0x7F, 0x80, 123, 124, 125, 126, 1968, 1969, 2000, 2001, 0x8000, 65535]


def edge(rng, values):
    return rng.choice(values) if rng.random() < 0.8 else rng.getrandbits(16)


def near_pdu(rng):
    fc = rng.choice([1, 2, 3, 4, 5, 6, 15, 16, 23, rng.getrandbits(8)])
    a, q = edge(rng, EDGE_ADDRESSES), edge(rng, EDGE_COUNTS)
    if fc in (1, 2, 3, 4, 5, 6):
        return struct.pack(">BHH", fc, a, q)
    if fc in (15, 16, 23):
        need = (q + 7) // 8 if fc == 15 else 2 * q
        count = min(need, 255) if rng.random() < 0.5 else rng.getrandbits(8)
        data = bytes(count if rng.random() < 0.7 else rng.randrange(48))
        if fc == 23:
            return struct.pack(">BHHHHB", fc, edge(rng, EDGE_ADDRESSES), edge(rng, EDGE_COUNTS),
                               a, q, count) + data
        return struct.pack(">BHHB", fc, a, q, count) + data
    return bytes([fc]) + rand_bytes(rng, rng.randrange(24))


def modbus_garbage(kind, rng):
    tid = rng.randrange(0xF000)
    if kind == "random":
        return rand_bytes(rng, rng.randrange(1, 512))
    if kind == "near_request":
        return mbap(tid, near_pdu(rng), unit=rng.choice([0, 1, 255, rng.getrandbits(8)]))
    if kind == "lying_length":
        pdu = near_pdu(rng)
        return mbap(tid, pdu, length=rng.choice([0, 1, 2, len(pdu), len(pdu) + 2, 254, 255,
                                                 65535, rng.getrandbits(16)]))
    if kind == "bad_protocol":
        return mbap(tid, near_pdu(rng), protocol=rng.randrange(1, 0x10000))
    if kind == "inconsistent_write":
        # FC 15/16/23 whose quantity and byte count disagree (the tokio-modbus panics).
        fc = rng.choice([15, 16, 23])
        if fc == 15:
            return mbap(tid, struct.pack(">BHHB", 15, 0, 2001, 1) + b"\xff")
        if fc == 16:
            return mbap(tid, struct.pack(">BHHB", 16, 200, 0x8000, 0))
        return mbap(tid, struct.pack(">BHHHHB", 23, 0, 1, 200, 0x8000, 0))
    if kind == "truncated":
        frame = mbap(tid, near_pdu(rng))
        return frame[: rng.randrange(1, len(frame))]
    raise ValueError(kind)


MODBUS_KINDS = ["random", "near_request", "lying_length", "bad_protocol", "inconsistent_write",
                "truncated"]


def mbap_swallows_to_end(stream, valid_start):
    """Whether MBAP framing from the start swallows the valid request in a frame that ends
    exactly at the end of the stream (the server then rightly waits for more)."""
    at = 0
    while True:
        if at == valid_start:
            return False
        if at == len(stream):
            return True
        if at + 7 > len(stream):
            return False
        protocol, length = struct.unpack(">HH", stream[at + 2:at + 6])
        if protocol != 0 or not 1 <= length <= 254:
            return False
        at += 6 + length
        if at > len(stream):
            return False


def read_modbus_reply(sock, tid, bound):
    deadline = time.monotonic() + bound
    buf = b""
    while True:
        while len(buf) >= 7:
            length = struct.unpack(">H", buf[4:6])[0]
            if len(buf) < 6 + length:
                break
            frame, buf = buf[:6 + length], buf[6 + length:]
            if struct.unpack(">H", frame[:2])[0] == tid:
                return frame[7:]
        left = deadline - time.monotonic()
        if left <= 0:
            return "silent"
        sock.settimeout(left)
        try:
            chunk = sock.recv(65536)
        except socket.timeout:
            return "silent"
        except OSError:
            return "closed"
        if not chunk:
            return "closed"
        buf += chunk


def state_ok(pdu):
    return isinstance(pdu, bytes) and len(pdu) == 4 and pdu[0] == 4 and pdu[1] == 2


# --- The attack ------------------------------------------------------------------------------


class Tally:
    def __init__(self):
        self.lock = threading.Lock()
        self.counts = collections.Counter()

    def add(self, key, n=1):
        with self.lock:
            self.counts[key] += n


def connect(addr):
    sock = socket.create_connection(addr, timeout=REPLY_BOUND)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def send_all(sock, data, rng, writes=None):
    """Sends `data` in one write or in random pieces (their sizes appended to `writes`); False if
    the server closed first."""
    writes = [] if writes is None else writes
    try:
        if rng.random() < 0.5:
            writes.append(len(data))
            sock.sendall(data)
        else:
            at = 0
            while at < len(data):
                step = rng.randrange(1, 64)
                writes.append(min(step, len(data) - at))
                sock.sendall(data[at:at + step])
                at += step
        return True
    except OSError:
        return False


MISSING_LOG = None  # a file to which inputs whose valid request went unanswered are appended


def log_missing(proto, kind, data, writes, outcome):
    if MISSING_LOG is None:
        return
    with MISSING_LOG_LOCK:
        with open(MISSING_LOG, "a") as f:
            f.write(json.dumps({"protocol": proto, "kind": kind, "outcome": outcome,
                                "writes": writes, "input": data.hex()}) + "\n")


MISSING_LOG_LOCK = threading.Lock()


def talos_round(addr, rng, tally, ident):
    kind = rng.choice(TALOS_KINDS)
    valid = handshake(ident)
    while True:
        pieces = [talos_garbage(kind, rng, len(valid)) for _ in range(rng.randrange(1, 4))]
        garbage = b"".join(piece for piece, _ in pieces)
        stream, at = garbage + valid, 0
        # A truncated frame whose missing tail the next bytes happen to supply is a valid frame
        # (the server rightly carries it out, and the valid one loses its head): draw again.
        completed = False
        for piece, tail in pieces:
            at += len(piece)
            completed |= bool(tail) and stream[at:at + len(tail)] == tail
        if not completed:
            break
    tally.add(("talos", kind, "inputs"))
    writes = []
    with connect(addr) as sock:
        if not send_all(sock, garbage + valid, rng, writes):
            tally.add(("talos", kind, "closed before the valid frame was sent"))
            return
        reply = read_talos_reply(sock, ident, REPLY_BOUND)
    if handshake_ok(reply):
        tally.add(("talos", kind, "valid frame answered"))
    else:
        outcome = reply if isinstance(reply, str) else "wrong"
        tally.add(("talos", kind, "REPLY MISSING (%s)" % outcome))
        log_missing("talos", kind, garbage + valid, writes, outcome)


def modbus_round(addr, rng, tally, tid):
    kind = rng.choice(MODBUS_KINDS)
    garbage = b"".join(modbus_garbage(kind, rng) for _ in range(rng.randrange(1, 4)))
    stream = garbage + read_state(tid)
    swallowed = mbap_swallows_to_end(stream, len(garbage))
    tally.add(("modbus", kind, "inputs"))
    writes = []
    with connect(addr) as sock:
        if not send_all(sock, stream, rng, writes):
            tally.add(("modbus", kind, "closed on the garbage"))
            return
        reply = read_modbus_reply(sock, tid, 1.5 if swallowed else REPLY_BOUND)
    if state_ok(reply):
        tally.add(("modbus", kind, "valid read answered"))
    elif reply == "closed":
        tally.add(("modbus", kind, "closed on the garbage"))
    elif reply == "silent" and swallowed:
        tally.add(("modbus", kind, "valid read swallowed by a lying length (no reply due)"))
    else:
        outcome = reply if isinstance(reply, str) else "wrong: " + reply.hex()
        tally.add(("modbus", kind, "REPLY MISSING (%s)" % outcome))
        log_missing("modbus", kind, stream, writes, outcome)


def health_check(talos, modbus, ident, tid):
    """A fresh connection's valid request to each server: (talos ok, modbus ok, arm alive)."""
    try:
        with connect(talos) as sock:
            sock.sendall(handshake(ident))
            talos_ok = handshake_ok(read_talos_reply(sock, ident, REPLY_BOUND))
    except OSError:
        talos_ok = False
    try:
        with connect(modbus) as sock:
            sock.sendall(read_state(tid))
            reply = read_modbus_reply(sock, tid, REPLY_BOUND)
        modbus_ok = state_ok(reply)
        # Exception 04 (server device failure) is what a dead arm task answers.
        arm_dead = isinstance(reply, bytes) and len(reply) == 2 and reply[1] == 4
    except OSError:
        modbus_ok, arm_dead = False, False
    return talos_ok, modbus_ok, not arm_dead and (talos_ok or modbus_ok)


def flood(addr, stop, tally, proto):
    rng = random.Random(7)
    chunk = rand_bytes(rng, 65536)
    while not stop.is_set():
        try:
            with connect(addr) as sock:
                tally.add((proto, "flood", "connections"))
                while not stop.is_set():
                    sock.sendall(chunk)
                    # Accepted by the kernel: a server that closed may never have read them.
                    tally.add((proto, "flood", "bytes written"), len(chunk))
        except OSError:
            pass


def slowloris(addr, stop, tally, proto, frame):
    while not stop.is_set():
        try:
            with connect(addr) as sock:
                tally.add((proto, "slowloris", "connections"))
                for byte in frame:
                    if stop.is_set():
                        return
                    sock.sendall(bytes([byte]))
                    tally.add((proto, "slowloris", "bytes"))
                    time.sleep(0.2)
        except OSError:
            pass


def proc_status(pid):
    out = {}
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "VmHWM", "Threads"):
                out[key] = int(value.split()[0])
    out["fds"] = len(os.listdir("/proc/%d/fd" % pid))
    return out


def start_sim(binary, log_dir, fd_limit=None):
    env = dict(os.environ, ARMJOG_LOG_DIR=log_dir)
    command = [binary, "sim", "--talos-listen", "127.0.0.1:0", "--modbus-listen", "127.0.0.1:0"]
    if fd_limit:
        # The shell lowers the limit, then becomes the sim: the child pid is the sim's.
        command = ["sh", "-c", 'ulimit -n %d && exec "$0" "$@"' % fd_limit] + command
    proc = subprocess.Popen(
        command,
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL, env=env,
        text=True)
    talos = modbus = None
    while talos is None or modbus is None:
        line = proc.stdout.readline()
        if not line:
            raise SystemExit("armjog sim exited before printing its addresses")
        if "talos operator" in line or "kinova modbus" in line:
            host, port = line.split()[2].rsplit(":", 1)
            if "talos" in line:
                talos = (host, int(port))
            else:
                modbus = (host, int(port))
    return proc, talos, modbus


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bin", default="target/release/armjog")
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--threads", type=int, default=6, help="attacking threads per protocol")
    parser.add_argument("--idle", type=int, default=50, help="idle connections held per server")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--fd-limit", type=int,
                        help="run the sim with this open-file limit (below 2 x --idle + ~20 exhausts it)")
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--missing-log", help="append each unanswered input (hex, write sizes) here")
    args = parser.parse_args()
    global MISSING_LOG
    MISSING_LOG = args.missing_log

    log_dir = "/tmp/armjog-attack-logs"
    proc, talos, modbus = start_sim(args.bin, log_dir, args.fd_limit)
    tally = Tally()
    try:
        # Warm up, then the baseline.
        for n in range(200):
            health_check(talos, modbus, 0x20202020 + 2 * n, n)
        time.sleep(0.5)
        before = proc_status(proc.pid)

        stop = threading.Event()
        idle = [connect(a) for a in (talos, modbus) for _ in range(args.idle)]
        workers = []

        def attacker(proto, seed):
            rng = random.Random(seed)
            n = 0
            while not stop.is_set():
                n += 1
                if proto == "talos":
                    ident = 0xA77A0000 | ((seed & 0xFF) << 8) | (0x20 + (n * 2) % 0x40)
                    talos_round(talos, rng, tally, ident)
                else:
                    modbus_round(modbus, rng, tally, 0xF000 + (n % 0x0FFF))

        for i in range(args.threads):
            workers.append(threading.Thread(target=attacker, args=("talos", args.seed * 100 + i)))
            workers.append(threading.Thread(target=attacker, args=("modbus", args.seed * 100 + 50 + i)))
        workers.append(threading.Thread(target=flood, args=(talos, stop, tally, "talos")))
        workers.append(threading.Thread(target=flood, args=(modbus, stop, tally, "modbus")))
        workers.append(threading.Thread(
            target=slowloris, args=(talos, stop, tally, "talos", talos_frame(9, 0x0008, bytes(1000)))))
        workers.append(threading.Thread(
            target=slowloris, args=(modbus, stop, tally, "modbus", mbap(9, bytes([16, 0, 0, 0, 123, 246]) + bytes(246)))))
        for w in workers:
            w.start()

        started = time.monotonic()
        checks = collections.Counter()
        peak = dict(before)
        rss_series = []
        n = 0
        while time.monotonic() - started < args.seconds:
            n += 1
            t_ok, m_ok, arm_ok = health_check(talos, modbus, 0x30303030 + 2 * (n % 1000), 0xE000 + n % 0x1000)
            checks["health checks"] += 1
            checks["talos health check failed"] += not t_ok
            checks["modbus health check failed"] += not m_ok
            checks["arm task dead"] += not arm_ok
            status = proc_status(proc.pid)
            peak = {k: max(peak[k], status[k]) for k in peak}
            rss_series.append((time.monotonic() - started, status["VmRSS"]))
            time.sleep(0.5)
        stop.set()
        for w in workers:
            w.join(timeout=REPLY_BOUND + 2)
        for sock in idle:
            sock.close()
        elapsed = time.monotonic() - started

        # Connections close asynchronously: give the server time to drop them.
        deadline = time.monotonic() + 10
        after = proc_status(proc.pid)
        while after["fds"] > before["fds"] and time.monotonic() < deadline:
            time.sleep(0.2)
            after = proc_status(proc.pid)
        final = health_check(talos, modbus, 0x40404040, 0xEFFF)
        alive = proc.poll() is None
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()

    totals = collections.Counter()
    for (proto, kind, what), value in tally.counts.items():
        if what == "inputs":
            totals["%s inputs tried" % proto] += value
        elif what.startswith("REPLY MISSING"):
            totals["%s replies missing" % proto] += value
    report = {
        "seconds": round(elapsed, 1),
        "totals": dict(totals),
        "inputs": {"%s %s: %s" % k: v for k, v in sorted(tally.counts.items())},
        "health": dict(checks),
        "process alive at the end": alive,
        "final fresh-connection check (talos, modbus, arm)": final,
        "before (after warm-up)": before,
        "peak during": peak,
        "after": after,
        # A leak grows with the run; a plateau is the allocator keeping its peak.
        "VmRSS by quarter of the run (kB)": [
            next((kb for t, kb in rss_series if t >= elapsed * q / 4), rss_series[-1][1] if rss_series else 0)
            for q in (1, 2, 3, 4)],
    }
    if args.json:
        print(json.dumps(report, indent=1))
        return
    print("attack on %s for %.1f s, %d attacking threads per protocol, %d idle connections per server"
          % (args.bin, elapsed, args.threads, args.idle))
    for key, value in report["inputs"].items():
        print("  %-80s %d" % (key, value))
    for key, value in sorted(totals.items()):
        print("  %-80s %d" % (key, value))
    for key, value in report["health"].items():
        print("  %-80s %d" % (key, value))
    print("  process alive at the end: %s; final check talos/modbus/arm: %s" % (alive, final))
    print("  VmRSS by quarter of the run: %s kB" % report["VmRSS by quarter of the run (kB)"])
    for label in ("before (after warm-up)", "peak during", "after"):
        s = report[label]
        print("  %-24s VmRSS %6d kB  VmHWM %6d kB  threads %3d  fds %4d"
              % (label, s["VmRSS"], s["VmHWM"], s["Threads"], s["fds"]))


if __name__ == "__main__":
    main()
