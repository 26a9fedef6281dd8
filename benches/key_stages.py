#!/usr/bin/env python3
"""Where a key's time goes on its way to the wire, stage by stage, at rest and under load.

Usage (from the repository root):

    cargo build --release --features key-stages --target-dir target/key-stages
    python3 benches/key_stages.py [--binary target/key-stages/release/armjog] [--cycles 150]
    python3 benches/key_stages.py --stress        # the same under `stress --cpu 2` as well

It runs `benches/pty_latency.py`'s cycles (press, hold, release; an ack-dialect Talos operator
on loopback) against a console built with the `key-stages` feature, which marks each stage of
the key path in memory (`src/key_stages.rs`) and writes the marks out when it quits. For every
key it takes the first time each stage was passed after the runtime woke for it, and prints,
for presses and releases apart, the median and p90 of each step and of the time since the wake.

The steps are on one thread and measured inside the process, so they do not carry the harness's
own noise; the first (`Woken` to `Read`) and the write (`Encoded` to `Written`) include the
kernel's work. What comes after `Written` runs before the thread sleeps again: on a busy core the
operator that receives the frame may be waiting for it (the kernel wakes a loopback receiver on
the sender's core).
"""

import argparse
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))

# src/key_stages.rs's `Stage`, in its order.
STAGES = [
    "Woken", "Read", "Input", "Decided", "Handed", "DriverTook", "Routed", "LinkTook",
    "Encoded", "Written", "Resumed", "Parked",
]
WOKEN, READ, INPUT, ENCODED, WRITTEN, PARKED = 0, 1, 2, 8, 9, 11


def keys_of(marks):
    """Per key, {stage: ns since the wake it was read after}, in the order the keys came."""
    keys = []
    for i, (stage, _) in enumerate(marks):
        # A read the event loop took next, or one whose release had the stop set written
        # ahead first (`console/input/release_stop.rs`: Encoded and Written come before Input).
        if stage != READ or i + 1 >= len(marks) or marks[i + 1][0] not in (INPUT, ENCODED):
            continue
        start = i
        while start > 0 and marks[start][0] != WOKEN:
            start -= 1
        if marks[start][0] != WOKEN:
            continue
        woke = marks[start][1]
        seen = {}
        for stage_j, at in marks[start:]:
            seen.setdefault(stage_j, at - woke)
            if stage_j == PARKED and WRITTEN in seen:
                break
        if WRITTEN in seen and PARKED in seen:
            keys.append(seen)
    return keys


def percentile(values, p):
    values = sorted(values)
    return values[min(len(values) - 1, int(p * (len(values) - 1) + 0.5))]


def print_steps(title, keys):
    """Each stage's step from the stage before it in time (by the median since the wake: a
    stop set written ahead makes Encoded and Written come before Input), and since the wake."""
    print(f"  {title}: {len(keys)} keys (us)")
    if not keys:
        return
    print(f"    {'stage':<12} {'step p50':>9} {'step p90':>9} {'since wake p50':>15}")
    present = [i for i in range(len(STAGES)) if any(i in k for k in keys)]
    order = sorted(present, key=lambda i: percentile([k[i] for k in keys if i in k], 0.5))
    for before, index in zip(order, order[1:]):
        with_both = [k for k in keys if index in k and before in k]
        since = [k[index] for k in keys if index in k]
        if not with_both:
            continue
        steps = [k[index] - k[before] for k in with_both]
        print(
            f"    {STAGES[index]:<12} {percentile(steps, 0.5) / 1000:9.1f}"
            f" {percentile(steps, 0.9) / 1000:9.1f} {percentile(since, 0.5) / 1000:15.1f}"
        )


def run(binary, cycles, size, rest, load):
    marks_file = tempfile.NamedTemporaryFile(prefix="armjog-key-stages-", delete=False).name
    env = dict(os.environ, ARMJOG_KEY_STAGES=marks_file)
    stress = None
    if load:
        stress = subprocess.Popen(
            ["stress", "--cpu", "2"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        time.sleep(1.0)
    try:
        done = subprocess.run(
            [sys.executable, os.path.join(HERE, "pty_latency.py"), "--binary", binary,
             "--cycles", str(cycles), "--size", size, "--rest", str(rest)],
            env=env, capture_output=True, text=True,
        )
    finally:
        if stress:
            os.killpg(stress.pid, signal.SIGTERM)
            stress.wait()
    if done.returncode != 0:
        sys.exit(f"pty_latency.py failed:\n{done.stdout}{done.stderr}")
    with open(marks_file) as f:
        marks = [tuple(int(x) for x in line.split()) for line in f if line.strip()]
    os.unlink(marks_file)
    if not marks:
        sys.exit(f"{binary} wrote no marks: build it with --features key-stages")
    return keys_of(marks), done.stdout.strip().splitlines()[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default="target/key-stages/release/armjog")
    parser.add_argument("--cycles", type=int, default=150)
    parser.add_argument("--stress", action="store_true", help="also under stress --cpu 2")
    parser.add_argument(
        "--rest",
        type=float,
        default=0.0,
        help="s more the console rests before each press: a press after a pause finds the "
        "caches cold, and this shows which steps pay for it",
    )
    parser.add_argument(
        "--size", default="120x40", help="terminal COLSxROWS; a large one makes frames costly"
    )
    args = parser.parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"{args.binary} not found: see the usage at the top of this file")
    if args.stress and not shutil.which("stress"):
        sys.exit("stress not found: apt-get install stress")
    phases = [("at rest", False)] + ([("under stress --cpu 2", True)] if args.stress else [])
    for name, load in phases:
        keys, summary = run(args.binary, args.cycles, args.size, args.rest, load)
        print(f"{name}: {summary}")
        # A cycle is a press then its release.
        print_steps("press", keys[0::2])
        print_steps("release", keys[1::2])


if __name__ == "__main__":
    main()
