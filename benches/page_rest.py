#!/usr/bin/env python3
"""What this machine charges to touch memory again after a pause: the cost behind a press.

Usage: python3 benches/page_rest.py [--pages 4096] [--rest 0.05,0.2,0.5,1,2]

It maps `--pages` pages, touches each once, then for each rest sleeps that long and times one
read per page. On bare metal a page read again after a pause costs what a cache miss costs
(some 0.1 us). On a virtual machine whose host reclaims or unmaps a guest's idle memory, it
costs a fault on the host, tens of us each after a second. A console's key path touches a few
hundred pages (its code, the app's state, the allocator's, the runtime's), so there a key
after a pause costs milliseconds, and the more pages a program touches per key, the more:
this is why `benches/pty_latency.py`'s press->START depends on how long each console rested.
"""

import argparse
import mmap
import time

PAGE = mmap.PAGESIZE


def sweep(buf, pages):
    """ns per page for one read of every page."""
    started = time.perf_counter_ns()
    total = 0
    for i in range(0, pages * PAGE, PAGE):
        total += buf[i]
    return (time.perf_counter_ns() - started) / pages


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pages", type=int, default=4096)
    parser.add_argument("--rest", default="0.05,0.2,0.5,1,2", help="rests, s, comma-separated")
    args = parser.parse_args()
    buf = mmap.mmap(-1, args.pages * PAGE)
    for i in range(0, args.pages * PAGE, PAGE):
        buf[i] = 1
    sweep(buf, args.pages)
    warm = min(sweep(buf, args.pages) for _ in range(3))
    print(f"{args.pages} pages; read again at once: {warm / 1000:.2f} us per page")
    for rest in (float(r) for r in args.rest.split(",")):
        time.sleep(rest)
        cost = sweep(buf, args.pages)
        print(f"after {rest:g} s at rest: {cost / 1000:7.2f} us per page ({cost / warm:6.0f}x)")


if __name__ == "__main__":
    main()
