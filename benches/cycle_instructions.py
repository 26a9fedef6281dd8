#!/usr/bin/env python3
"""Instructions one jog cycle costs the console, by thread: a figure that does not move with the
machine's load (needs valgrind).

Usage (from the repository root, after `cargo build --release`):

    python3 benches/cycle_instructions.py                       # target/release/armjog
    python3 benches/cycle_instructions.py /tmp/armjog-old target/release/armjog   # side by side

Timings on a shared 2-core machine move from one run to the next by more than most changes move
them; instruction counts do not. For each binary this runs `benches/pty_latency.py` twice, with
the console under `valgrind --tool=callgrind --separate-threads=yes`: SHORT cycles, then LONG
cycles (a cycle: press, hold 60-140 ms while the console jogs and draws, release). The start and
the exit cost the same in both runs, so (LONG run - SHORT run) / (LONG - SHORT) is what one cycle
costs. It prints that for the thread that reads the keys and runs the app, the driver and the
links (`main`), for the painter (`draw`: the thread that did the most besides main), and for the
whole process.

The counts are instructions, not time: a key's burst on a cold core costs cache and page misses
too, which this does not see (see `key_pages.py`, `key_burst.py`).
"""

import os
import re
import subprocess
import sys
import tempfile

SHORT = int(os.environ.get("SHORT", "10"))
LONG = int(os.environ.get("LONG", "40"))
HERE = os.path.dirname(os.path.abspath(__file__))


def totals(prefix):
    """Instructions per thread file of one callgrind run: {thread number: Ir}."""
    out = {}
    folder, base = os.path.split(prefix)
    for name in os.listdir(folder):
        found = re.fullmatch(re.escape(base) + r"-(\d+)", name)
        if not found:
            continue
        for line in open(os.path.join(folder, name)):
            if line.startswith("totals:"):
                out[int(found.group(1))] = int(line.split()[1])
    return out


def run(binary, cycles, work):
    prefix = os.path.join(work, f"cg.{cycles}.out")
    wrapper = os.path.join(work, "console.sh")
    with open(wrapper, "w") as f:
        f.write(
            "#!/bin/sh\n"
            f"exec valgrind --tool=callgrind --separate-threads=yes "
            f"--callgrind-out-file={prefix} {os.path.abspath(binary)} \"$@\"\n"
        )
    os.chmod(wrapper, 0o755)
    done = subprocess.run(
        [sys.executable, os.path.join(HERE, "pty_latency.py"), "--binary", wrapper,
         "--cycles", str(cycles)],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        sys.exit(f"{binary}: pty_latency.py failed:\n{done.stdout}{done.stderr}")
    counts = totals(prefix)
    if 1 not in counts:
        sys.exit(f"{binary}: no callgrind output at {prefix}-01")
    return counts


def main():
    binaries = sys.argv[1:] or ["target/release/armjog"]
    if any(b.startswith("-") for b in binaries):
        sys.exit(__doc__)
    for binary in binaries:
        if not os.access(binary, os.X_OK):
            sys.exit(f"{binary} not found: run `cargo build --release` first")
    print(f"instructions per jog cycle ({LONG} - {SHORT} cycles under callgrind):")
    first = None
    for binary in binaries:
        work = tempfile.mkdtemp(prefix="armjog-cycle-ir-")
        short, long = run(binary, SHORT, work), run(binary, LONG, work)
        per = {t: (long.get(t, 0) - short.get(t, 0)) / (LONG - SHORT) for t in long}
        main_ir = per[1]
        others = {t: v for t, v in per.items() if t != 1}
        draw = max(others.values(), default=0.0)
        whole = sum(per.values())
        first = first or main_ir
        print(
            f"  {binary:<36} main {main_ir:10.0f} ({main_ir / first:4.2f}x the first)"
            f"   draw {draw:10.0f}   whole process {whole:10.0f}"
        )


if __name__ == "__main__":
    main()
