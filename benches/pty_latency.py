#!/usr/bin/env python3
"""Release->STOP latency of the real console binary, measured end to end on a pty.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/pty_latency.py --table            # THE table: armjog vs the floors, at rest
                                                      # and under `stress --cpu 2` (started here)
    python3 benches/pty_latency.py --table --compare /work/armjog-baseline  # before/after too
    python3 benches/pty_latency.py --table --repeat 5 --cycles 100   # medians over 5 runs
    python3 benches/pty_latency.py                    # 200 cycles, idle machine
    stress --cpu 2 & python3 benches/pty_latency.py   # the same with both cores busy
    python3 benches/pty_latency.py --cycles 500 --binary target/release/armjog
    python3 benches/pty_latency.py --size 400x120     # costly frames: does a key wait for one?
    python3 benches/pty_latency.py --compare /tmp/armjog-old  # A/B, cycles alternate
    python3 benches/pty_latency.py --compare floor    # against the machine's own floor
    python3 benches/pty_latency.py --compare floor-rs # against the compiled floor
    python3 benches/pty_latency.py --compare floor-exec # the Python floor as its own process
    python3 benches/pty_latency.py --table --rest 2   # each press after some 2 s at rest

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
p50, p90, p99 and max, and the STARTs that came after a release was written (a refresh that
overtook the release), with those that came later than the run's fastest press->START (so were
decided after the release bytes were on the pty); it exits 1 if a cycle saw no STOP within 2 s
or a START decided after a release, or one after the release's STOP (motion again with no
key down). How long a console rested before a press sets what the press costs: each console
rests while the others run their cycles, so the more consoles, the colder its caches when its
key comes; `--rest` adds a technician's pause, and the summary gives the median rest.
With --compare, a second binary runs beside the first and the cycles alternate between them, so both see the same
machine load (on a shared machine the load, not the binary, dominates the tail otherwise).
`--compare floor` runs a minimal stand-in instead (a Python child that turns each key event
into one frame): what is left of the tail there is the machine's and the harness's, not armjog's.
`--compare floor-rs` runs the compiled stand-in (`benches/pty_floor/floor.rs`, built here with
rustc into target/pty_floor/): one blocking read of the pty, one frame written, no runtime.
`--compare floor-exec` runs the same Python stand-in exec'd as its own interpreter: the forked
`floor` shares this script's pages, which this script keeps warm, so after a pause it may pay
less to wake than a program started on its own does (see FLOOR_EXEC).
`--compare` may be given more than once.

`--table` runs every console side by side (the binary, any `--compare`s, and the three floors) in
two phases, at rest and under `stress --cpu 2` (the script starts and ends stress itself; it
must be installed), and prints p50/p90/p99/max of release->STOP and press->START with each
console's ratio to each floor, p50 and p99. Under load one run's ratios move from run to run by
more than most changes move them: `--repeat N` runs each phase N times and adds, per phase, each
console's median p50 and p99 and the median (and range) of its per-run ratios.
"""

import argparse
import fcntl
import os
import pty
import random
import select
import signal
import shutil
import socket
import statistics
import subprocess
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


FLOOR = "floor"
FLOOR_RS = "floor-rs"
# The Python stand-in again, but exec'd as an interpreter of its own rather than forked from
# this script: a forked child shares its heap and the interpreter's code with this script,
# which keeps touching them (on this VM a page untouched for 0.5 s costs some 10 us to touch
# again), as no console started on its own does. The gap varies from run to run (see
# docs/development.md).
FLOOR_EXEC = "floor-exec"
FLOORS = (FLOOR, FLOOR_RS, FLOOR_EXEC)
FLOOR_SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pty_floor", "floor.rs")


def compiled_floor():
    """The compiled floor's program, built (again, when its source is newer) with rustc."""
    out_dir = os.path.join("target", "pty_floor")
    program = os.path.join(out_dir, "floor")
    if not os.path.exists(program) or os.path.getmtime(program) < os.path.getmtime(FLOOR_SOURCE):
        os.makedirs(out_dir, exist_ok=True)
        subprocess.run(
            ["rustc", "-O", "--edition", "2024", FLOOR_SOURCE, "-o", program], check=True
        )
    return os.path.abspath(program)


def frame(command):
    """An ack-dialect request frame with no payload and the xor8 checksum."""
    header = struct.pack(">IHHH", 0, 0, command, 0)
    checksum = 0
    for b in header:
        checksum ^= b
    return header + bytes([checksum])


def floor_console(port):
    """The least a console can do, in this process: raw pty, a START frame on each press and a
    STOP frame on each release. Its latency is the floor the machine and the harness set."""
    import tty

    tty.setraw(0)
    sock = socket.create_connection(("127.0.0.1", port))
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    sock.sendall(frame(0x0000))
    while True:
        readable, _, _ = select.select([0, sock], [], [])
        if sock in readable and not sock.recv(4096):
            os._exit(0)
        if 0 in readable:
            data = os.read(0, 4096)
            if not data or PRESS_Q in data:
                os._exit(0)
            if RELEASE_RIGHT in data:
                sock.sendall(frame(POLAR_STOP))
            elif PRESS_RIGHT in data:
                sock.sendall(frame(POLAR_START))


def percentile(sorted_values, p):
    i = round((len(sorted_values) - 1) * p)
    return sorted_values[min(i, len(sorted_values) - 1)]


class Console:
    """One console binary on its own pty, with its own operator and cycle state."""

    def __init__(self, binary, size, log_dir):
        self.binary = binary
        floor_program = compiled_floor() if binary == FLOOR_RS else None
        self.op = Operator()
        argv = [
            binary,
            "--talos", f"127.0.0.1:{self.op.port}",
            "--dialect", "ack",
            "--checksum", "xor8",
            "--key-release", "events",
            "--positions", os.path.join(log_dir, f"positions-{self.op.port}.json"),
        ]
        self.pid, self.master = pty.fork()
        if self.pid == 0:
            if binary == FLOOR:
                floor_console(self.op.port)
            if binary == FLOOR_EXEC:
                script = os.path.abspath(__file__)
                os.execv(sys.executable, [sys.executable, script, FLOOR_CHILD, str(self.op.port)])
            if binary == FLOOR_RS:
                import tty

                tty.setraw(0)
                os.execv(floor_program, [floor_program, str(self.op.port)])
            os.environ["ARMJOG_LOG_DIR"] = log_dir
            os.environ["TERM"] = "xterm-256color"
            os.execv(binary, argv)
        cols, rows = (int(n) for n in size.split("x"))
        fcntl.ioctl(self.master, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
        self.screen = bytearray()
        self.handshake_at = None
        self.state = "connecting"
        self.latencies = []
        self.failures = 0
        self.release_ns = 0
        # STARTs that reached the operator after the release was written: a refresh that
        # overtook the release (each is a fault; the STOP still follows).
        self.starts_after_release = []
        # press->START of every cycle, ms: the least time a key takes to become a frame.
        self.press_ns = 0
        self.press_to_start = []
        # STARTs after the release's STOP and before the next press.
        self.starts_after_stop = 0
        # How long the console was idle (STOP to the next press), ms.
        self.stop_ns = 0
        self.idle_before_press = []

    def fds(self):
        return [self.master, *self.op.sockets()]

    def drain_pty(self):
        """Reads the console's output and answers its terminal queries; False once it exited."""
        try:
            data = os.read(self.master, 65536)
        except OSError:
            return False
        if not data:
            return False
        self.screen.extend(data)
        if KITTY_QUERY in self.screen:
            os.write(self.master, b"\x1b[?1u")
        if DA1_QUERY in self.screen:
            os.write(self.master, b"\x1b[?62;c")
        self.screen = self.screen[-8:]
        return True

    def on_readable(self, fd, at_ns):
        """Returns the frames' commands read from `fd` (a socket of this console's operator)."""
        return [command for _, command in self.op.on_readable(fd, at_ns)]

    def quit(self):
        os.write(self.master, PRESS_Q + RELEASE_Q)
        end = time.monotonic() + 3
        while time.monotonic() < end:
            done, _ = os.waitpid(self.pid, os.WNOHANG)
            if done:
                return
            readable, _, _ = select.select(self.fds(), [], [], 0.05)
            for r in readable:
                if r == self.master:
                    self.drain_pty()
                else:
                    self.op.on_readable(r, now_ns())
        os.kill(self.pid, signal.SIGTERM)
        os.waitpid(self.pid, 0)

    def summary(self):
        values = sorted(self.latencies)
        if not values:
            return f"{self.binary}: no cycle completed; {self.failures} without a STOP"
        return (
            f"{self.binary}: release->STOP over {len(values)} cycles: "
            f"p50 {percentile(values, 0.5):.3f} ms, p90 {percentile(values, 0.9):.3f} ms, "
            f"p99 {percentile(values, 0.99):.3f} ms, max {values[-1]:.3f} ms; "
            f"{self.failures} without a STOP; "
            + self.press_summary()
            + "; "
            f"{len(self.starts_after_release)} STARTs after the release"
            + (f" ({', '.join(f'{v:.1f}' for v in self.starts_after_release)} ms after it)"
               if self.starts_after_release else "")
            + f", {len(self.starts_decided_after_release())} of them decided after it"
            f" (later than the fastest press->START, {self.fastest_press_to_start():.3f} ms)"
            f"; {self.starts_after_stop} STARTs after the STOP"
        )

    def press_summary(self):
        values = sorted(self.press_to_start)
        if not values:
            return "no press->START"
        idle = sorted(self.idle_before_press)
        return (
            f"press->START p50 {percentile(values, 0.5):.3f} ms, "
            f"p99 {percentile(values, 0.99):.3f} ms"
            + (f" (idle {percentile(idle, 0.5):.0f} ms before a press, median)" if idle else "")
        )

    def fastest_press_to_start(self):
        return min(self.press_to_start, default=0.0)

    def starts_decided_after_release(self):
        """STARTs that came later after the release than any key ever took to become a frame:
        decided after the release bytes were on the pty. An earlier one may have been decided
        before them, on its way while they were written."""
        fastest = self.fastest_press_to_start()
        return [v for v in self.starts_after_release if v > fastest]


def run_cycles(binaries, cycles, size, seed, rest=0.0):
    """Runs `cycles` press/release cycles on each binary, alternating; returns the consoles.
    Each turn waits 50-100 ms plus `rest` / the consoles' number after a STOP, so a console
    rests about `rest` s longer between its STOP and its next press, the other consoles'
    cycles running meanwhile: how long a console has been idle sets what its press costs (the
    summary gives the median idle before a press)."""
    random.seed(seed)
    log_dir = tempfile.mkdtemp(prefix="armjog-pty-")
    consoles = [Console(b, size, log_dir) for b in binaries]
    owner = {}
    turn = 0  # index of the console whose cycle runs
    next_at = 0.0
    deadline = 0.0
    started = time.monotonic()

    def done():
        return all(len(c.latencies) + c.failures >= cycles for c in consoles)

    while True:
        t = time.monotonic()
        for c in consoles:
            if c.state == "connecting" and c.handshake_at and t - c.handshake_at > 2.0:
                c.state = "ready"
        if any(c.state == "connecting" for c in consoles):
            if t - started > 10:
                sys.exit("a console did not handshake within 10 s")
            next_at = t
        else:
            c = consoles[turn]
            if c.state == "ready" and t >= next_at:
                if done():
                    break
                c.press_ns = now_ns()
                if c.stop_ns:
                    c.idle_before_press.append((c.press_ns - c.stop_ns) / 1e6)
                os.write(c.master, PRESS_RIGHT)
                c.state, deadline = "pressed", t + 2.0
            elif c.state == "held" and t >= next_at:
                # Frames the console sent before the release are taken first, so a START
                # counted after it was sent after the release bytes were on the pty.
                while select.select(c.op.sockets()[1:], [], [], 0)[0]:
                    for r in select.select(c.op.sockets()[1:], [], [], 0)[0]:
                        c.op.on_readable(r, now_ns())
                c.release_ns = now_ns()
                os.write(c.master, RELEASE_RIGHT)
                c.state, deadline = "released", t + 2.0
            elif c.state in ("pressed", "released") and t >= deadline:
                c.failures += 1
                missing = "START" if c.state == "pressed" else "STOP"
                print(f"{c.binary}: no {missing} within 2 s", file=sys.stderr)
                os.write(c.master, RELEASE_RIGHT)
                c.state, next_at = "ready", t + 0.5
                turn = (turn + 1) % len(consoles)

        c = consoles[turn]
        wake = next_at if c.state in ("ready", "held") else deadline
        timeout = max(0.0, min(wake - time.monotonic(), 0.05))
        fds = []
        for console in consoles:
            for fd in console.fds():
                owner[fd] = console
                fds.append(fd)
        readable, _, _ = select.select(fds, [], [], timeout)
        at_ns = now_ns()
        for r in readable:
            console = owner[r]
            if r == console.master:
                if not console.drain_pty():
                    sys.exit(f"{console.binary} exited during the run")
                continue
            for command in console.on_readable(r, at_ns):
                if command == 0x0000 and console.state == "connecting":
                    # The last handshake counts, and the console is ready 2 s after it: one
                    # this script answered too late (busy starting the others) is tried again
                    # 1.5 s later, and a press before the link is up is rightly refused.
                    console.handshake_at = time.monotonic()
                elif console.state == "pressed" and command == POLAR_START:
                    console.press_to_start.append((at_ns - console.press_ns) / 1e6)
                    console.state = "held"
                    next_at = time.monotonic() + random.uniform(0.06, 0.14)
                elif console.state == "released" and command == POLAR_START:
                    console.starts_after_release.append((at_ns - console.release_ns) / 1e6)
                elif (
                    console.state == "released"
                    and command == POLAR_STOP
                    and at_ns >= console.release_ns
                ):
                    console.latencies.append((at_ns - console.release_ns) / 1e6)
                    console.stop_ns = at_ns
                    console.state = "ready"
                    next_at = time.monotonic() + random.uniform(0.05, 0.1) + rest / len(consoles)
                    turn = (turn + 1) % len(consoles)
                elif console.state == "ready" and command == POLAR_START:
                    # Motion started again after the STOP with no key down: always a fault.
                    console.starts_after_stop += 1

    for c in consoles:
        c.quit()
    return consoles


def failed(consoles):
    return any(
        c.failures or not c.latencies or c.starts_decided_after_release() or c.starts_after_stop
        for c in consoles
    )


def stats(values):
    values = sorted(values)
    if not values:
        return None
    return [percentile(values, 0.5), percentile(values, 0.9), percentile(values, 0.99), values[-1]]


METRICS = (
    ("release->STOP", lambda c: c.latencies),
    ("press->START", lambda c: c.press_to_start),
)


def ratios(consoles, values_of):
    """{(console, floor): (p50 ratio, p99 ratio)} of one run, for one metric; None where the
    floor's figure is zero."""
    out = {}
    for f in (c for c in consoles if c.binary in FLOORS):
        base = stats(values_of(f))
        for c in consoles:
            row = stats(values_of(c))
            if row and base:
                out[(c.binary, f.binary)] = tuple(
                    row[i] / base[i] if base[i] > 0 else None for i in (0, 2)
                )
    return out


def print_table(title, consoles):
    """One phase's table: each console's percentiles and its ratio to each floor."""
    floors = [c for c in consoles if c.binary in FLOORS]
    print(f"\n{title}")
    for metric, values_of in METRICS:
        ratio_heads = "".join(f" {'p50/' + f.binary:>12} {'p99/' + f.binary:>12}" for f in floors)
        print(f"  {metric + ' (ms)':<32} {'n':>4} {'p50':>7} {'p90':>7} {'p99':>7} {'max':>7}{ratio_heads}")
        to_floors = ratios(consoles, values_of)
        for c in consoles:
            row = stats(values_of(c))
            if row is None:
                print(f"  {c.binary:<32} no cycle completed")
                continue
            cells = "".join(
                f" {x:>11.2f}x" if x is not None else f" {'-':>12}"
                for f in floors
                for x in to_floors.get((c.binary, f.binary), (None, None))
            )
            print(
                f"  {c.binary:<32} {len(values_of(c)):>4} "
                + " ".join(f"{v:>7.3f}" for v in row)
                + cells
            )


def print_repeats(title, runs):
    """Over several runs of a phase: each console's median p50 and p99, and the median of its
    per-run ratios to each floor with their range. A ratio taken within one run compares
    consoles that shared the load; its median over runs is steadier than any one run's."""
    floors = [b for b in runs[0]["binaries"] if b in FLOORS]
    print(f"\n{title}")
    for metric, _ in METRICS:
        heads = "".join(f" {'p50/' + f:>20} {'p99/' + f:>20}" for f in floors)
        print(f"  {metric + ' (ms), median of runs':<44} {'p50':>7} {'p99':>7}{heads}")
        for binary in runs[0]["binaries"]:
            p50s = [r["stats"][metric][binary][0] for r in runs if r["stats"][metric].get(binary)]
            p99s = [r["stats"][metric][binary][2] for r in runs if r["stats"][metric].get(binary)]
            if not p50s:
                print(f"  {binary:<44} no cycle completed")
                continue
            cells = ""
            for f in floors:
                for i in (0, 1):
                    values = sorted(
                        r["ratios"][metric][(binary, f)][i]
                        for r in runs
                        if r["ratios"][metric].get((binary, f), (None, None))[i] is not None
                    )
                    cells += (
                        f" {statistics.median(values):>6.2f}x ({values[0]:.2f}-{values[-1]:.2f})"
                        if values
                        else f" {'-':>20}"
                    )
            print(
                f"  {binary:<44} {statistics.median(p50s):>7.3f} "
                f"{statistics.median(p99s):>7.3f}{cells}"
            )


def table(args, binaries):
    """Both phases, each with every console and the three floors; exit 1 if any cycle failed.
    With `--repeat N` each phase runs N times (its load kept up between runs), and a table of
    the medians over the runs follows the runs' own."""
    consoles_in = binaries + [FLOOR_RS, FLOOR, FLOOR_EXEC]
    cpus = os.cpu_count()
    phases = [("at rest", None), ("under stress --cpu 2", ["stress", "--cpu", "2"])]
    if args.phase != "both":
        phases = [phases[0] if args.phase == "rest" else phases[1]]
    # Said before a phase runs, not after the first one's minutes.
    for _, load in phases:
        if load and not shutil.which(load[0]):
            sys.exit("stress not found: apt-get install stress")
    any_failed = False
    for name, load in phases:
        stress = None
        if load:
            # Its own session, so its workers end with it (by its process group).
            stress = subprocess.Popen(
                load, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
            )
            time.sleep(1.0)
        runs = []
        try:
            for run in range(args.repeat):
                consoles = run_cycles(
                    consoles_in, args.cycles, args.size, args.seed + run, args.rest
                )
                load_avg = os.getloadavg()[0]
                print_table(
                    f"{name}: {args.cycles} cycles each, alternating, {args.size}, {cpus} cores, "
                    f"rest {args.rest:g} s, load average {load_avg:.2f} at the end"
                    + (f" (run {run + 1} of {args.repeat})" if args.repeat > 1 else ""),
                    consoles,
                )
                for c in consoles:
                    print(f"    {c.summary()}")
                any_failed |= failed(consoles)
                runs.append({
                    "binaries": [c.binary for c in consoles],
                    "stats": {m: {c.binary: stats(v(c)) for c in consoles} for m, v in METRICS},
                    "ratios": {m: ratios(consoles, v) for m, v in METRICS},
                })
        finally:
            if stress:
                os.killpg(stress.pid, signal.SIGTERM)
                stress.wait()
        if args.repeat > 1:
            print_repeats(f"{name}: medians over {args.repeat} runs (range of the ratios)", runs)
    sys.exit(1 if any_failed else 0)


# The argument that makes this script the exec'd floor's child: `FLOOR_CHILD PORT`.
FLOOR_CHILD = "--floor-child"


def main():
    if len(sys.argv) == 3 and sys.argv[1] == FLOOR_CHILD:
        floor_console(int(sys.argv[2]))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default="target/release/armjog")
    parser.add_argument(
        "--compare",
        action="append",
        default=[],
        help="another binary, or floor / floor-exec / floor-rs; cycles alternate between them "
        "(repeatable)",
    )
    parser.add_argument("--cycles", type=int, default=200, help="cycles per binary")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--rest",
        type=float,
        default=0.0,
        help="s more each console rests before a press (a technician's pause; a press after "
        "a long rest finds the caches cold)",
    )
    parser.add_argument(
        "--size", default="120x40", help="terminal COLSxROWS; a large one makes frames costly"
    )
    parser.add_argument(
        "--table",
        action="store_true",
        help="at rest and under stress --cpu 2, against the three floors: the whole table",
    )
    parser.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="with --table: runs of each phase; more than one adds the medians over the runs "
        "(under load one run's ratios move more than most changes do)",
    )
    parser.add_argument(
        "--phase",
        choices=["both", "rest", "stress"],
        default="both",
        help="with --table: only the phase at rest, or only the one under stress",
    )
    args = parser.parse_args()
    if args.repeat < 1:
        sys.exit(f"--repeat {args.repeat}: at least 1 run")
    binaries = [args.binary] + args.compare
    for binary in binaries:
        if binary not in FLOORS and not os.access(binary, os.X_OK):
            sys.exit(f"{binary} not found: run `cargo build --release` first")
    if args.table:
        table(args, [b for b in binaries if b not in FLOORS])
    consoles = run_cycles(binaries, args.cycles, args.size, args.seed, args.rest)
    for c in consoles:
        print(c.summary())
    sys.exit(1 if failed(consoles) else 0)


if __name__ == "__main__":
    main()
