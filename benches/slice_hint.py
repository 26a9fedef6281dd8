#!/usr/bin/env python3
"""A console run with the scheduler's slice hint: what the kernel's own latency knob would buy.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/pty_latency.py --table --repeat 2 --cycles 150 --compare benches/slice_hint.py
    SLICE_US=300 ARMJOG_BIN=/path/to/armjog python3 benches/pty_latency.py --compare benches/slice_hint.py

It sets its own EEVDF slice (`sched_attr.sched_runtime` with SCHED_OTHER, Linux 6.12 and
later, no privilege needed; default 100 us, the least the kernel takes) and execs the console
(`ARMJOG_BIN`, default target/release/armjog) with the arguments it was given. Every thread the
console starts inherits the hint. A thread with a shorter slice than the running one may
preempt it when it wakes, so on a busy core the console would no longer wait for a CPU hog's
turn. The console itself cannot ask for this: no maintained crate wraps `sched_setattr`, and
the crate forbids `unsafe`.

Measured on the 2-core VM (kernel 6.18; `--table --repeat 2 --cycles 150`, so two runs of each
phase, this beside HEAD and the floors; medians of the runs):
- Under `stress --cpu 2` the tails shrink: release->STOP p99 0.46 ms against 3.10 (the Python
  floor 4.33), and p99 0.39 / 0.53 against 1.39 / 4.80 run by run. The p50s do not move:
  release->STOP 0.155 against 0.159 ms, press->START 0.215 against 0.216 (the floor 0.191).
- At rest both p50s are slower: release->STOP 0.234 against 0.205 ms, press->START 0.308
  against 0.256 (release->STOP p99 1.16 against 0.44, press->START p99 0.69 against 0.79).
  Likely (not measured apart): the operator a write wakes no longer takes the console's CPU
  at once, and the painter, which inherits the hint, preempts as well.
So the hint is no way to the press's p50 under load (issue 21's last cell), and at rest it
costs both p50s. A hint on the runtime's thread alone was not measured; in the console it would
take an `unsafe` syscall.
"""

import ctypes
import os
import struct
import sys

SYS_SCHED_SETATTR = {"x86_64": 314, "aarch64": 274}
SCHED_OTHER = 0


def set_slice(nanoseconds):
    """Sets this thread's slice hint; exits with the reason when the kernel refuses it."""
    number = SYS_SCHED_SETATTR.get(os.uname().machine)
    if number is None:
        sys.exit(f"slice_hint: no sched_setattr number known for {os.uname().machine}")
    # struct sched_attr (48 bytes): size, policy, flags, nice, priority, runtime, deadline, period.
    attr = struct.pack("IIQiIQQQ", 48, SCHED_OTHER, 0, 0, 0, nanoseconds, 0, 0)
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.syscall(number, 0, ctypes.create_string_buffer(attr), 0) != 0:
        sys.exit(f"slice_hint: sched_setattr: {os.strerror(ctypes.get_errno())}")


def main():
    slice_us = os.environ.get("SLICE_US", "100")
    if not slice_us.isdigit() or not 100 <= int(slice_us) <= 100_000:
        sys.exit(f"slice_hint: SLICE_US={slice_us}: a whole number of us from 100 to 100000")
    set_slice(int(slice_us) * 1000)
    binary = os.environ.get("ARMJOG_BIN", "target/release/armjog")
    try:
        os.execv(binary, [binary] + sys.argv[1:])
    except OSError as e:
        sys.exit(f"slice_hint: cannot run {binary}: {e.strerror}")


if __name__ == "__main__":
    main()
