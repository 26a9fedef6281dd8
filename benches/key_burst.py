#!/usr/bin/env python3
"""What one key costs a console's thread, syscall by syscall (needs root and `perf`).

Usage (from the repository root, after `cargo build --release`):

    python3 benches/key_burst.py                          # armjog and the Python floor
    python3 benches/key_burst.py --compare /tmp/armjog-old --cycles 80   # before/after too
    python3 benches/key_burst.py --show 3     # and each console's 3 commonest bursts, call by call

It runs `benches/pty_latency.py` (armjog, any `--compare`s, and `--compare floor-exec`), traces the syscalls of
each console's thread that reads the keys (`perf record -e raw_syscalls:*`), and cuts the trace
into bursts: a burst starts when the thread wakes for a key (the exit of the wait that slept
before the read of the key's bytes) and ends when it next sleeps. For each console it prints the
median, in µs, of: wake to the read, the read, the read's end to the frame's write, the write
(the kernel's loopback delivery included), the write's end to the next sleep, and the whole
burst. Under `stress --cpu 2` the key's receiver shares the core with the console, so the whole
burst, not only the time to the write, is what it waits for (see docs/architecture.md).

The tracing itself costs each syscall a few µs: compare consoles in one run, not with other
figures.
"""

import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time

READ, WRITE, SENDTO = 0, 1, 44
# Names for `--show`: the calls a console's key burst makes (x86-64 numbers).
NAMES = {0: "read", 1: "write", 7: "poll", 20: "writev", 23: "select", 44: "sendto",
         45: "recvfrom", 202: "futex", 232: "epoll_wait", 270: "pselect6", 281: "epoll_pwait",
         441: "epoll_pwait2"}
# A wait that took longer than this slept (the thread was not running through it).
SLEPT_NS = 20_000
# The shortest Talos frame (a 10-byte header and a checksum).
FRAME_MIN = 11
LINE = re.compile(
    r"^\s*\S+\s+(\d+)\s+\[\d+\]\s+([\d.]+):\s+raw_syscalls:sys_(enter|exit):\s+NR\s+(-?\d+)\s*(.*)$"
)


def syscalls(lines):
    """(nr, first arg, enter ns, exit ns, return) per syscall, in order, per thread."""
    open_calls, done = {}, {}
    for line in lines:
        m = LINE.match(line)
        if not m:
            continue
        tid, t, kind, nr, rest = int(m[1]), int(float(m[2]) * 1e9), m[3], int(m[4]), m[5]
        if kind == "enter":
            arg = rest.strip("() ").split(",")[0] if rest.startswith("(") else "0"
            open_calls[tid] = (nr, int(arg or "0", 16), t)
        elif tid in open_calls:
            enr, arg, start = open_calls.pop(tid)
            ret = int(rest.split("=")[-1]) if "=" in rest else 0
            if enr == nr:
                done.setdefault(tid, []).append((nr, arg, start, t, ret))
    return done


def is_frame_write(call, key_fd):
    """A frame's write: a sendto, or a write of a frame's size (an eventfd's is 8 bytes)."""
    nr, fd, _, _, ret = call
    return fd != key_fd and (nr == SENDTO and ret > 0 or nr == WRITE and ret >= FRAME_MIN)


def bursts(calls):
    """Per key read: (wake->read, read, read->write, write, write->sleep, whole) in ns, and the
    calls from the wake to the sleep (names and return values)."""
    out = []
    for i, (nr, fd, start, end, ret) in enumerate(calls):
        if nr != READ or ret <= 0:
            continue
        # The wake: the last call before the read that slept (or the read, when it blocked).
        wake = end if end - start > SLEPT_NS else None
        if wake is None:
            for prev in reversed(calls[max(0, i - 20) : i]):
                if prev[3] - prev[2] > SLEPT_NS:
                    wake = prev[3]
                    break
        if wake is None:
            continue
        write = next(
            (c for c in calls[i + 1 : i + 40] if is_frame_write(c, fd)),
            None,
        )
        if write is None:
            continue
        after = calls[calls.index(write) + 1 :]
        sleep = next((c for c in after[:80] if c[3] - c[2] > SLEPT_NS), None)
        if sleep is None:
            continue
        read_start = start if wake != end else end
        first = next(k for k in range(i, -1, -1) if calls[k][3] == wake) if wake != end else i
        last = calls.index(sleep, i)
        sequence = " ".join(
            f"{NAMES.get(c[0], c[0])}={c[4]}" for c in calls[first + 1 : last + 1]
        )
        out.append(
            (
                read_start - wake,
                end - read_start,
                write[2] - end,
                write[3] - write[2],
                sleep[2] - write[3],
                sleep[2] - wake,
                sequence,
            )
        )
    return out


def key_thread(pid):
    """The thread that reads the keys: the process's main thread (armjog's runtime, Python)."""
    return pid


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="target/release/armjog")
    parser.add_argument("--compare", action="append", default=[], help="another armjog binary")
    parser.add_argument("--cycles", type=int, default=60)
    parser.add_argument("--trace-seconds", type=float, default=0.0, help="0: the whole run")
    parser.add_argument(
        "--show", type=int, default=0, help="print each console's K most common bursts, call by call"
    )
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    bench = subprocess.Popen(
        [
            sys.executable,
            os.path.join(here, "pty_latency.py"),
            "--binary",
            args.binary,
            *[a for binary in args.compare for a in ("--compare", binary)],
            "--compare",
            "floor-exec",
            "--cycles",
            str(args.cycles),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    consoles = {}
    wanted = 2 + len(args.compare)
    deadline = time.monotonic() + 20
    while len(consoles) < wanted and time.monotonic() < deadline and bench.poll() is None:
        time.sleep(0.2)
        found = subprocess.run(["pgrep", "-a", "-P", str(bench.pid)], capture_output=True, text=True)
        for line in found.stdout.splitlines():
            pid, cmd = line.split(" ", 1)
            if "--talos" in cmd:
                consoles.setdefault(cmd.split()[0], int(pid))
            elif "--floor-child" in cmd:
                consoles.setdefault("floor-exec", int(pid))
    if len(consoles) < wanted:
        bench.kill()
        sys.exit(f"key_burst: found only {consoles} under the bench")
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "perf.data")
        tids = ",".join(str(key_thread(p)) for p in consoles.values())
        perf = subprocess.Popen(
            ["perf", "record", "-q", "-e", "raw_syscalls:sys_enter,raw_syscalls:sys_exit",
             "-t", tids, "-o", data],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        if args.trace_seconds > 0:
            time.sleep(args.trace_seconds)
            perf.send_signal(signal.SIGINT)
        output, _ = bench.communicate()
        if perf.poll() is None:
            perf.send_signal(signal.SIGINT)
        perf.wait()
        script = subprocess.run(["perf", "script", "-i", data], capture_output=True, text=True)
    by_thread = syscalls(script.stdout.splitlines())
    print(output.strip())
    names = ["wake->read", "read", "read->write", "write", "write->sleep", "burst"]
    print(f"{'console':28} {'keys':>5} " + " ".join(f"{n:>12}" for n in names) + "   (µs, median)")
    for name, pid in consoles.items():
        rows = bursts(by_thread.get(key_thread(pid), []))
        if not rows:
            print(f"{name:28} no key bursts traced")
            continue
        medians = [statistics.median(r[k] for r in rows) / 1000 for k in range(len(names))]
        print(f"{name[-28:]:28} {len(rows):5} " + " ".join(f"{m:12.1f}" for m in medians))
        counts = {}
        for r in rows:
            counts[r[-1]] = counts.get(r[-1], 0) + 1
        for sequence, n in sorted(counts.items(), key=lambda kv: -kv[1])[: args.show]:
            print(f"    {n:4} x  {sequence}")


if __name__ == "__main__":
    main()
