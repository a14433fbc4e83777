#!/usr/bin/env python3
"""Two S-starts from two Python threads at once against one alone (slither_gait releases the
GIL while it simulates, so on 2 cores the pair should take about one run's wall time, not two).

    python3 lab/python_threads/python_threads.py [REPEATS]

Needs slither_gait installed (pip install ./python). Prints each timing and the medians.
"""
import os
import statistics
import sys
import threading
import time

import slither_gait as sg


def main(repeats):
    p = sg.load_problem("problems/s_start.toml")
    run = lambda: sg.run(p, progress=False)
    run()  # warm: page in the library, allocate
    singles, pairs = [], []
    for k in range(repeats):
        t0 = time.perf_counter()
        run()
        singles.append(time.perf_counter() - t0)
        threads = [threading.Thread(target=run) for _ in range(2)]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        pairs.append(time.perf_counter() - t0)
        print(f"repeat {k + 1}: one run {singles[-1]:.3f} s, two threads {pairs[-1]:.3f} s")
    one, two = statistics.median(singles), statistics.median(pairs)
    print(f"cores: {os.cpu_count()}; medians of {repeats}: one run {one:.3f} s, two runs in two "
          f"threads {two:.3f} s, ratio {two / one:.2f} (1.00: fully parallel, 2.00: serialised)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
