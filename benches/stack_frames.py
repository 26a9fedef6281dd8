#!/usr/bin/env python3
"""The largest stack frames in a build, by function (x86-64, needs objdump).

Usage (from the repository root, after `cargo build --release`):

    python3 benches/stack_frames.py                           # target/release/armjog, top 30
    python3 benches/stack_frames.py BINARY --top 50
    python3 benches/stack_frames.py --match event_loop --match raw::poll

Every page of a function's stack frame is touched each time it is called: a frame over a page
is probed page by page (rustc's stack probes), and after a pause each page touched again costs
a key a fault on this VM (`benches/page_rest.py`). The polls on the key path (the console's
loop, the driver's loop, the Talos link task, and tokio's `raw::poll` of each) should stay a
page or two; a large one usually has a rarely run branch inlined into it: set-up, an exit, a
future built and spawned (see `docs/architecture.md`, the key-to-wire path).

A frame's size is read from the function's prologue: the `sub $N,%rsp` instructions, and for a
probed frame the loop's bound (`sub $N,%r11`). Functions named alike (monomorphised generics)
are listed each with its address.
"""

import argparse
import re
import subprocess
import sys

HEADER = re.compile(r"^([0-9a-f]+) <(.*)>:$")
SUB = re.compile(r"\bsub\s+\$0x([0-9a-f]+),%(rsp|r11)")
# The prologue: frames are set up within the first instructions.
PROLOGUE = 45
PROBE_STEP = 0x1000


def frames(binary):
    """[(bytes, address, name)] for every function whose prologue reserves stack."""
    listing = subprocess.run(
        ["objdump", "-d", "--no-show-raw-insn", "-C", binary],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    found = []
    name = address = None
    subs, probed, seen = [], 0, 0

    def close():
        if name is None or not (subs or probed):
            return
        size = sum(subs) + probed
        if probed:
            # The probe loop's own step is counted by its bound.
            size -= PROBE_STEP
        if 0 < size < 1 << 32:
            found.append((size, address, name))

    for line in listing.splitlines():
        header = HEADER.match(line)
        if header:
            close()
            address, name = header.group(1).lstrip("0"), header.group(2)
            subs, probed, seen = [], 0, 0
            continue
        if name is None:
            continue
        seen += 1
        if seen > PROLOGUE:
            continue
        sub = SUB.search(line)
        if sub:
            value = int(sub.group(1), 16)
            if sub.group(2) == "r11":
                probed = value
            else:
                subs.append(value)
    close()
    return sorted(found, reverse=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary", nargs="?", default="target/release/armjog")
    parser.add_argument("--top", type=int, default=30)
    parser.add_argument(
        "--match", action="append", default=[], help="only functions whose name contains this"
    )
    args = parser.parse_args()
    listed = frames(args.binary)
    if args.match:
        listed = [f for f in listed if any(m in f[2] for m in args.match)]
    if not listed:
        sys.exit("no function matched")
    for size, address, name in listed[: args.top]:
        print(f"{size:8d}  {address:>8}  {name[:140]}")


if __name__ == "__main__":
    main()
