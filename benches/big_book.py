#!/usr/bin/env python3
"""Figures of the real console binary with a big positions book (issue 9, item 5).

Usage (from the repository root, after `cargo build --release`):

    python3 benches/big_book.py                        # a book just under the 16 MB limit
    python3 benches/big_book.py --megabytes 4 --runs 3
    python3 benches/big_book.py --binary /tmp/armjog-old   # the same figures for another build

It writes a valid book (compact JSON, names `pos-000000`..., each with a position and an
orientation) to a temporary directory, starts `armjog --positions FILE` on its built-in
simulated arm in a detached tmux session (120x40), and reads the screen with `tmux capture-pane`
(polled every 5 ms, so every time below is good to about 10 ms):

- first frame: start -> the positions panel's title is on the screen;
- book shown: start -> the first position's name is on the screen;
- quit while loading: a second start, `q` typed as soon as the first frame is up -> the process
  has ended (a console that parses the book on its event loop only sees the key after it);
- key: PageDown (select the next position) -> the selection mark is on the second name;
- save: `p`, a name, Enter (the simulated operator saves it, the console writes the book) ->
  "saved" is on the screen, and -> the file has been replaced (the write is atomic: a rename);
- rest CPU: the process's user+system time over 5 s, book loaded, no key held, after 2 s to
  settle (in % of one core); "rest CPU, last" the same with the last position selected (PageUp
  from the first wraps to it), where a list drawn from its start walks the whole book;
- peak RSS: VmHWM from /proc/PID/status, read before quitting;
- quit: `q` -> the process has ended.

The figures depend on the machine and its load: compare builds on the same machine, or run them
alternately with --runs.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

POLL = 0.005
TIMEOUT = 120.0


def write_book(path, limit_bytes):
    """A valid book of as many entries as fit under `limit_bytes`; returns the entry count."""
    parts = []
    size = len('{"format":1,"positions":{}}\n')
    count = 0
    while True:
        entry = {
            "anchor": False,
            "cartesian": [4566 + count % 1000, 10 + count % 77, 4338 - count % 500],
            "orientation": [90.0, 0.0, 90.0 + (count % 360) / 10.0],
        }
        part = json.dumps(f"pos-{count:06d}") + ":" + json.dumps(entry, separators=(",", ":"))
        extra = len(part) + (1 if parts else 0)
        if size + extra > limit_bytes:
            break
        parts.append(part)
        size += extra
        count += 1
    with open(path, "w") as f:
        f.write('{"format":1,"positions":{' + ",".join(parts) + "}}\n")
    return count


def tmux(*args):
    return subprocess.run(["tmux", *args], capture_output=True, text=True, check=False)


def screen(session):
    return tmux("capture-pane", "-p", "-t", session).stdout


def wait_for(what, deadline=TIMEOUT):
    start = time.monotonic()
    while time.monotonic() - start < deadline:
        if what():
            return True
        time.sleep(POLL)
    return False


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(") ")[1].split()[0] != "Z"
    except (FileNotFoundError, IndexError):
        return False


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().split(") ")[1].split()
    ticks = os.sysconf("SC_CLK_TCK")
    return (int(fields[11]) + int(fields[12])) / ticks


def peak_rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def start(session, binary, book, workdir):
    # Each start reads the book as written first (a run saves into it).
    shutil.copyfile(book + ".orig", book)
    env = f"ARMJOG_DATA_DIR={workdir} ARMJOG_LOG_DIR={workdir}"
    command = f"exec env {env} {binary} --positions {book}"
    started = time.monotonic()
    result = tmux("new-session", "-d", "-s", session, "-x", "120", "-y", "40", command)
    if result.returncode != 0:
        sys.exit(f"tmux: {result.stderr.strip()}")
    pid = int(tmux("display-message", "-p", "-t", session, "#{pane_pid}").stdout.strip())
    return started, pid


def quit_and_time(session, pid):
    typed = time.monotonic()
    tmux("send-keys", "-t", session, "q")
    ended = wait_for(lambda: not alive(pid), 30.0)
    took = time.monotonic() - typed
    tmux("kill-session", "-t", session)
    return took if ended else float("inf")


def one_run(binary, book, count, workdir, run):
    figures = {}
    session = f"armjog-big-book-{os.getpid()}-{run}"
    started, pid = start(session, binary, book, workdir)
    title = "Positions ("
    if not wait_for(lambda: title in screen(session)):
        tmux("kill-session", "-t", session)
        sys.exit("no frame within the timeout:\n" + screen(session))
    figures["first frame (s)"] = time.monotonic() - started
    if not wait_for(lambda: "pos-000000" in screen(session)):
        tmux("kill-session", "-t", session)
        sys.exit("the book was never shown:\n" + screen(session))
    figures["book shown (s)"] = time.monotonic() - started
    time.sleep(2.0)
    before = cpu_seconds(pid)
    time.sleep(5.0)
    figures["rest CPU (% core)"] = (cpu_seconds(pid) - before) / 5.0 * 100.0
    typed = time.monotonic()
    tmux("send-keys", "-t", session, "PageDown")
    if wait_for(lambda: "> pos-000001" in screen(session), 30.0):
        figures["key PageDown (s)"] = time.monotonic() - typed
    else:
        figures["key PageDown (s)"] = float("inf")
    tmux("send-keys", "-t", session, "PageUp", "PageUp")
    last = f"> pos-{count - 1:06d}"
    if not wait_for(lambda: last in screen(session), 30.0):
        sys.exit("the last position was never selected:\n" + screen(session))
    time.sleep(1.0)
    before = cpu_seconds(pid)
    time.sleep(5.0)
    figures["rest CPU, last (% core)"] = (cpu_seconds(pid) - before) / 5.0 * 100.0
    tmux("send-keys", "-t", session, "p")
    if not wait_for(lambda: "Save current pose" in screen(session), 30.0):
        sys.exit("no save form:\n" + screen(session))
    tmux("send-keys", "-t", session, "zzzz")
    inode = os.stat(book).st_ino
    typed = time.monotonic()
    tmux("send-keys", "-t", session, "Enter")
    if wait_for(lambda: "saved 'zzzz'" in screen(session), 30.0):
        figures["save shown (s)"] = time.monotonic() - typed
    else:
        figures["save shown (s)"] = float("inf")
    if wait_for(lambda: os.stat(book).st_ino != inode, 30.0):
        figures["save written (s)"] = time.monotonic() - typed
    else:
        figures["save written (s)"] = float("inf")
    figures["file after save (MB)"] = os.path.getsize(book) / (1024 * 1024)
    figures["peak RSS (MB)"] = peak_rss_mb(pid)
    figures["quit (s)"] = quit_and_time(session, pid)

    session += "-q"
    started, pid = start(session, binary, book, workdir)
    if not wait_for(lambda: title in screen(session)):
        tmux("kill-session", "-t", session)
        sys.exit("no frame within the timeout (second start)")
    figures["quit while loading (s)"] = quit_and_time(session, pid)
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default="target/release/armjog")
    parser.add_argument("--megabytes", type=float, default=16.0)
    parser.add_argument("--runs", type=int, default=1)
    args = parser.parse_args()
    if shutil.which("tmux") is None:
        sys.exit("tmux is needed")
    binary = os.path.abspath(args.binary)
    workdir = tempfile.mkdtemp(prefix="armjog-big-book-")
    try:
        book = os.path.join(workdir, "book.json")
        # Just under the limit: 4 KiB of margin below the megabytes asked for.
        count = write_book(book + ".orig", int(args.megabytes * 1024 * 1024) - 4096)
        print(f"book: {count} positions, {os.path.getsize(book + '.orig')} bytes ({binary})")
        runs = [one_run(binary, book, count, workdir, run) for run in range(args.runs)]
        for name in runs[0]:
            values = ", ".join(f"{r[name]:.3f}" for r in runs)
            print(f"{name:24} {values}")
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
