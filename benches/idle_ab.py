#!/usr/bin/env python3
"""The console at rest, several builds side by side: CPU, wake-ups, page faults and memory.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/idle_ab.py target/release/armjog /tmp/armjog-before
    ROUNDS=5 WINDOW=10 python3 benches/idle_ab.py A B C     # more rounds, any number of builds

On a shared machine the console's CPU at rest moves by half from one minute to the next, more
than most changes move it: `console_live -- idle` measures one build after another, so its
figures for two builds are not comparable. Here every build runs at the same time, each in its
own tmux (160x48) against its own `armjog sim` (this build's, strict: 5 reads a snapshot) with
telemetry at 30 Hz over Modbus and a Talos link beside it, and each round measures all of them
over the same window: the load is the same for all, so their ratio is the figure to read.

Per build it prints CPU (% of one core, from the scheduler's run time of all its threads) per
round and their mean, wake-ups per second (context switches of all its threads), minor page
faults per second, and resident memory at the end. SETTLE (default 35 s) passes first: the
history panel's 30 s fill before the console is at rest.
"""

import os
import re
import subprocess
import sys
import tempfile
import time

SIM = "target/release/armjog"


def threads(pid):
    return os.listdir(f"/proc/{pid}/task")


def run_ns(pid):
    return sum(int(open(f"/proc/{pid}/task/{t}/schedstat").read().split()[0]) for t in threads(pid))


def switches(pid):
    total = 0
    for t in threads(pid):
        for line in open(f"/proc/{pid}/task/{t}/status"):
            if line.startswith(("voluntary_ctxt_switches:", "nonvoluntary_ctxt_switches:")):
                total += int(line.split()[1])
    return total


def minor_faults(pid):
    return int(open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[7])


def rss_mb(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def start(binary, index, work):
    """`armjog sim` and the console on it in tmux; returns (sim, console pid, tmux socket)."""
    logs = os.path.join(work, str(index))
    os.makedirs(logs)
    sim = subprocess.Popen(
        [SIM, "sim", "--talos-listen", "127.0.0.1:0", "--modbus-listen", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "ARMJOG_LOG_DIR": logs},
    )
    addrs = []
    for _ in range(4):
        found = re.search(r"127\.0\.0\.1:\d+", sim.stdout.readline())
        if found:
            addrs.append(found.group(0))
    if len(addrs) != 2:
        sim.kill()
        sys.exit(f"could not read the simulator's addresses: {addrs}")
    socket = f"armjog-idle-ab-{os.getpid()}-{index}"
    command = (
        f"ARMJOG_DATA_DIR={logs} ARMJOG_LOG_DIR={logs} exec {binary} "
        f"--talos {addrs[0]} --modbus {addrs[1]} --telemetry-hz 30"
    )
    subprocess.run(
        ["tmux", "-L", socket, "new-session", "-d", "-s", "b", "-x", "160", "-y", "48", command],
        check=True,
    )
    shown = subprocess.run(
        ["tmux", "-L", socket, "display", "-p", "-t", "b", "#{pane_pid}"],
        capture_output=True,
        text=True,
        check=True,
    )
    return sim, int(shown.stdout.strip()), socket


def main():
    binaries = sys.argv[1:]
    if not binaries or any(b.startswith("-") for b in binaries):
        sys.exit(__doc__)
    for binary in [SIM, *binaries]:
        if not os.access(binary, os.X_OK):
            sys.exit(f"{binary} not found: run `cargo build --release` first")
    settle = float(os.environ.get("SETTLE", "35"))
    rounds = int(os.environ.get("ROUNDS", "3"))
    window = float(os.environ.get("WINDOW", "10"))
    work = tempfile.mkdtemp(prefix="armjog-idle-ab-")
    started = []
    try:
        for i, binary in enumerate(binaries):
            started.append((binary, *start(binary, i, work)))
        time.sleep(settle)
        cpu = {b: [] for b in binaries}
        wakes = {b: [] for b in binaries}
        faults = {b: [] for b in binaries}
        for _ in range(rounds):
            before = {pid: (run_ns(pid), switches(pid), minor_faults(pid)) for _, _, pid, _ in started}
            time.sleep(window)
            for binary, _, pid, _ in started:
                ns, sw, flt = before[pid]
                cpu[binary].append((run_ns(pid) - ns) / 1e9 / window * 100)
                wakes[binary].append((switches(pid) - sw) / window)
                faults[binary].append((minor_faults(pid) - flt) / window)
        mean = lambda v: sum(v) / len(v)
        base = mean(cpu[binaries[0]])
        print(f"at rest, {len(binaries)} consoles side by side, {rounds} rounds of {window:.0f} s after {settle:.0f} s:")
        for binary, _, pid, _ in started:
            print(
                f"  {binary:<36} CPU {mean(cpu[binary]):5.2f} % ({' '.join(f'{v:.2f}' for v in cpu[binary])})"
                f" = {mean(cpu[binary]) / base:4.2f}x the first,"
                f" wake-ups {mean(wakes[binary]):6.1f}/s, faults {mean(faults[binary]):5.1f}/s,"
                f" RSS {rss_mb(pid):5.1f} MB"
            )
    finally:
        for _, sim, _, socket in started:
            subprocess.run(["tmux", "-L", socket, "kill-server"], stderr=subprocess.DEVNULL)
            sim.kill()


if __name__ == "__main__":
    main()
