#!/usr/bin/env python3
"""Pages of memory one key press touches, by mapping: the cost of a press after a pause.

Usage (from the repository root, as root or the console's owner; Linux only):

    cargo build --release && python3 benches/key_pages.py [BINARY|floor|floor-rs] [--rounds 10]

It starts the console as `benches/pty_latency.py` does (a pty answering crossterm's queries, an
ack-dialect Talos operator on loopback). Each round it waits 1 s, clears the process's
referenced bits (`/proc/PID/clear_refs`), presses the Right arrow, and once the START frame
has arrived reads `Referenced` from `/proc/PID/smaps` per mapping, then releases. What it
counts includes what the console does right after the START (drawing the frame, the audit
record), so it bounds the key path from above. On a machine that charges a fault for a page
touched again after a pause (`benches/page_rest.py`), the press costs about this many faults.
The counts vary by a few pages from round to round, far less than timings do: compare two
builds by their medians.
"""

import argparse
import os
import re
import select
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pty_latency as pl  # noqa: E402

MAPPING = re.compile(r"^[0-9a-f]+-[0-9a-f]+ (\S+) \S+ \S+ \S+\s*(.*)$")


def referenced_pages(pid):
    """{mapping: pages} with any page referenced since the last clear_refs."""
    pages = {}
    name = None
    with open(f"/proc/{pid}/smaps") as smaps:
        for line in smaps:
            mapping = MAPPING.match(line)
            if mapping:
                perms, path = mapping.groups()
                name = f"{os.path.basename(path) or '[anon]'} {perms}"
            elif line.startswith("Referenced:"):
                kb = int(line.split()[1])
                if kb:
                    pages[name] = pages.get(name, 0) + kb * 1024 // os.sysconf("SC_PAGE_SIZE")
    return pages


def pump(console, until=None, seconds=2.0):
    """Serves the pty and the operator for `seconds`, or until a frame `until` arrives."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        readable, _, _ = select.select(console.fds(), [], [], 0.01)
        for fd in readable:
            if fd == console.master:
                console.drain_pty()
                continue
            if until in console.on_readable(fd, pl.now_ns()):
                return True
    return until is None


def median(values):
    values = sorted(values)
    return values[len(values) // 2] if values else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary", nargs="?", default="target/release/armjog")
    parser.add_argument("--rounds", type=int, default=10)
    args = parser.parse_args()
    console = pl.Console(args.binary, "120x40", tempfile.mkdtemp(prefix="armjog-pages-"))
    pump(console, seconds=2.0)
    rounds = []
    for _ in range(args.rounds):
        pump(console, seconds=1.0)
        with open(f"/proc/{console.pid}/clear_refs", "w") as clear:
            clear.write("1")
        os.write(console.master, pl.PRESS_RIGHT)
        if not pump(console, until=pl.POLAR_START):
            sys.exit(f"{args.binary}: no START within 2 s")
        rounds.append(referenced_pages(console.pid))
        os.write(console.master, pl.RELEASE_RIGHT)
        if not pump(console, until=pl.POLAR_STOP):
            sys.exit(f"{args.binary}: no STOP within 2 s")
    console.quit()
    totals = [sum(r.values()) for r in rounds]
    print(f"{args.binary}: pages referenced by a press, until its START arrived: "
          f"median {median(totals)}, min {min(totals)}, max {max(totals)} ({args.rounds} rounds)")
    for name in sorted({n for r in rounds for n in r}, key=lambda n: -median([r.get(n, 0) for r in rounds])):
        pages = median([r.get(name, 0) for r in rounds])
        if pages:
            print(f"  {pages:5}  {name}")


if __name__ == "__main__":
    main()
