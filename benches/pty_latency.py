#!/usr/bin/env python3
"""Release->STOP latency of the real console binary, measured end to end on a pty.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/pty_latency.py                    # 200 cycles, idle machine
    stress --cpu 2 & python3 benches/pty_latency.py   # the same with both cores busy
    python3 benches/pty_latency.py --cycles 500 --binary target/release/armjog
    python3 benches/pty_latency.py --size 400x120     # costly frames: does a key wait for one?

The script starts `armjog --talos 127.0.0.1:PORT --dialect ack --checksum xor8
--key-release events` on a pseudo-terminal and plays both of its peers itself, in one
single-threaded select loop (stdlib only):

- the terminal: it answers crossterm's kitty-protocol query (CSI ? u) and DA1 (CSI c), keeps the
  pty drained, and types kitty key events: Right arrow press (CSI 1;1:1 C), release
  (CSI 1;1:3 C);
- the Talos operator (the deployed dialect): it answers every frame with "ACK\\0" and stamps
  each frame it receives with time.perf_counter_ns().

One cycle: press, wait for the polar START (0x0003), hold 60-140 ms, write the release, and wait
for the polar STOP (0x0004). Latency = STOP frame received - release bytes written. It prints
p50, p90, p99 and max, and exits 1 if a cycle saw no STOP within 2 s.
"""

import argparse
import fcntl
import os
import pty
import random
import select
import signal
import socket
import struct
import sys
import tempfile
import termios
import time

PRESS_RIGHT = b"\x1b[1;1:1C"
RELEASE_RIGHT = b"\x1b[1;1:3C"
PRESS_Q = b"\x1b[113u"
RELEASE_Q = b"\x1b[113;1:3u"
KITTY_QUERY = b"\x1b[?u"
DA1_QUERY = b"\x1b[c"
ACK = b"ACK\x00"
POLAR_START = 0x0003
POLAR_STOP = 0x0004
HEADER = 10  # id u32, reserved u16, command u16, length u16
XOR8 = 1  # checksum bytes


def now_ns():
    return time.perf_counter_ns()


class Operator:
    """A loopback Talos operator in the ack dialect with the xor8 checksum."""

    def __init__(self):
        self.listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.listener.bind(("127.0.0.1", 0))
        self.listener.listen(4)
        self.listener.setblocking(False)
        self.port = self.listener.getsockname()[1]
        self.conns = {}  # socket -> bytearray

    def sockets(self):
        return [self.listener, *self.conns]

    def on_readable(self, sock, at_ns):
        """Returns [(at_ns, command)] for every complete frame read."""
        if sock is self.listener:
            conn, _ = self.listener.accept()
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            conn.setblocking(False)
            self.conns[conn] = bytearray()
            return []
        try:
            data = sock.recv(65536)
        except OSError:
            data = b""
        if not data:
            del self.conns[sock]
            sock.close()
            return []
        buf = self.conns[sock]
        buf.extend(data)
        frames = []
        while len(buf) >= HEADER:
            length = struct.unpack(">H", buf[8:10])[0]
            size = HEADER + length + XOR8
            if len(buf) < size:
                break
            command = struct.unpack(">H", buf[6:8])[0]
            del buf[:size]
            frames.append((at_ns, command))
            try:
                sock.sendall(ACK)
            except OSError:
                pass
        return frames


def percentile(sorted_values, p):
    i = round((len(sorted_values) - 1) * p)
    return sorted_values[min(i, len(sorted_values) - 1)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default="target/release/armjog")
    parser.add_argument("--cycles", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--size", default="120x40", help="terminal COLSxROWS; a large one makes frames costly"
    )
    args = parser.parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"{args.binary} not found: run `cargo build --release` first")
    random.seed(args.seed)

    op = Operator()
    log_dir = tempfile.mkdtemp(prefix="armjog-pty-")
    argv = [
        args.binary,
        "--talos", f"127.0.0.1:{op.port}",
        "--dialect", "ack",
        "--checksum", "xor8",
        "--key-release", "events",
        "--positions", os.path.join(log_dir, "positions.json"),
    ]
    pid, master = pty.fork()
    if pid == 0:
        os.environ["ARMJOG_LOG_DIR"] = log_dir
        os.environ["TERM"] = "xterm-256color"
        os.execv(args.binary, argv)
    cols, rows = (int(n) for n in args.size.split("x"))
    fcntl.ioctl(master, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))

    screen = bytearray()  # the tail of the console's output, for the queries

    def drain_pty():
        nonlocal screen
        try:
            data = os.read(master, 65536)
        except OSError:
            return False
        if not data:
            return False
        screen.extend(data)
        if KITTY_QUERY in screen:
            os.write(master, b"\x1b[?1u")
        if DA1_QUERY in screen:
            os.write(master, b"\x1b[?62;c")
        screen = screen[-8:]
        return True

    latencies = []
    failures = 0
    state = "connecting"
    handshake_at = None
    next_at = 0.0
    deadline = 0.0
    release_ns = 0
    started = time.monotonic()

    while True:
        t = time.monotonic()
        if state == "connecting" and handshake_at and t - handshake_at > 1.0:
            state, next_at = "idle", t
        if state == "connecting" and t - started > 10:
            sys.exit("the console did not handshake within 10 s")
        if state == "idle" and t >= next_at:
            if len(latencies) + failures >= args.cycles:
                break
            os.write(master, PRESS_RIGHT)
            state, deadline = "pressed", t + 2.0
        elif state == "held" and t >= next_at:
            release_ns = now_ns()
            os.write(master, RELEASE_RIGHT)
            state, deadline = "released", t + 2.0
        elif state in ("pressed", "released") and t >= deadline:
            failures += 1
            print(f"cycle {len(latencies) + failures}: no {'START' if state == 'pressed' else 'STOP'} within 2 s", file=sys.stderr)
            os.write(master, RELEASE_RIGHT)
            state, next_at = "idle", t + 0.5

        wake = {"idle": next_at, "held": next_at}.get(state, deadline)
        timeout = max(0.0, min(wake - time.monotonic(), 0.05)) if state != "connecting" else 0.05
        readable, _, _ = select.select([master, *op.sockets()], [], [], timeout)
        at_ns = now_ns()
        for r in readable:
            if r == master:
                if not drain_pty():
                    sys.exit("the console exited during the run")
                continue
            for frame_ns, command in op.on_readable(r, at_ns):
                if command == 0x0000 and handshake_at is None:
                    handshake_at = time.monotonic()
                elif state == "pressed" and command == POLAR_START:
                    state, next_at = "held", time.monotonic() + random.uniform(0.06, 0.14)
                elif state == "released" and command == POLAR_STOP and frame_ns >= release_ns:
                    latencies.append((frame_ns - release_ns) / 1e6)
                    state, next_at = "idle", time.monotonic() + random.uniform(0.05, 0.1)

    os.write(master, PRESS_Q + RELEASE_Q)
    end = time.monotonic() + 3
    while time.monotonic() < end:
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        readable, _, _ = select.select([master, *op.sockets()], [], [], 0.05)
        for r in readable:
            if r == master:
                drain_pty()
            else:
                op.on_readable(r, now_ns())
    else:
        os.kill(pid, signal.SIGTERM)
        os.waitpid(pid, 0)

    values = sorted(latencies)
    if not values:
        sys.exit("no cycle completed")
    print(
        f"release->STOP over {len(values)} cycles: p50 {percentile(values, 0.5):.3f} ms, "
        f"p90 {percentile(values, 0.9):.3f} ms, p99 {percentile(values, 0.99):.3f} ms, "
        f"max {values[-1]:.3f} ms; {failures} without a STOP"
    )
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
