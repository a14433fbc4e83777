#!/usr/bin/env python3
"""Where the semi-smooth contact Newton's iterations go, from a debug trace.

Reads the stderr of `SLITHER_DEBUG=1 slither run ...` (the lines `semi-smooth statuses it K:
...` with one character per contact, `.` free, `#` stick, `~` slide, and `semi-smooth
converged at it K`) and prints, over the converged solves:

- how the converged statuses differ from the last converged step's, by kind;
- per band of iterations per step: the steps, their share of all iterations, those
  differences, the status changes per iteration inside the step, and the contacts that change
  status more than once inside the step (back and forth);
- the largest jump of the converged statuses from one step to the next;
- with `--window K`, the same run in windows of K steps: iterations per step, the share of
  steps that take 10 or more, landings and lift-offs per step, how many contacts the step's
  first iterate has on another status than the converged one, and the median merit of the
  first iterate (`semi-smooth it 1: theta`).

Usage: lab/status_anatomy/status_trace.py TRACE [LABEL] [--window K]
"""
import re
import sys

STATUS = re.compile(r"semi-smooth statuses it (\d+): (\S*)")
DONE = re.compile(r"semi-smooth converged at it (\d+)")
THETA1 = re.compile(r"semi-smooth it 1: theta ([0-9.eE+-]+)")
KINDS = [("stick to slide", "#", "~"), ("slide to stick", "~", "#"),
         ("landings", ".", "#~"), ("lift-offs", "#~", ".")]
BANDS = [(1, 3), (4, 6), (7, 10), (11, 20), (21, 10**9)]


def changes(a, b):
    """Per kind, the contacts whose status goes from one of `src` to one of `dst`."""
    return [sum(1 for x, y in zip(a, b) if x != y and x in src and y in dst)
            for _, src, dst in KINDS]


def main():
    args = sys.argv[1:]
    window = None
    if "--window" in args:
        k = args.index("--window")
        window = int(args[k + 1])
        del args[k:k + 2]
    path = args[0]
    label = args[1] if len(args) > 1 else path
    # (iterations, converged-vs-last changes, changes per iteration, back-and-forth,
    # first iterate's statuses off the converged ones, first merit)
    steps = []
    attempt = []
    step_first, theta1 = None, None
    last_final = None
    failed = 0
    with open(path, errors="replace") as f:
        for line in f:
            m = THETA1.search(line)
            if m and theta1 is None:
                theta1 = float(m.group(1))
                continue
            m = STATUS.search(line)
            if m:
                if int(m.group(1)) == 1 and attempt:
                    failed += 1  # an attempt that never converged (retry or fallback)
                    attempt = []
                if step_first is None:
                    step_first = m.group(2)
                attempt.append(m.group(2))
                continue
            m = DONE.search(line)
            if m and attempt:
                its = int(m.group(1))
                final = attempt[-1]
                inner = [sum(1 for x, y in zip(a, b) if x != y) for a, b in zip(attempt, attempt[1:])]
                flips = [0] * len(final)
                for a, b in zip(attempt, attempt[1:]):
                    for i, (x, y) in enumerate(zip(a, b)):
                        if x != y:
                            flips[i] += 1
                back_and_forth = sum(1 for k in flips if k >= 2)
                diff = changes(last_final, final) if last_final and len(last_final) == len(final) else None
                off = sum(1 for x, y in zip(step_first or final, final) if x != y)
                steps.append((its, diff, sum(inner) / max(1, len(inner)), back_and_forth, off,
                              theta1))
                last_final = final
                attempt = []
                step_first, theta1 = None, None
    if not steps:
        sys.exit(f"{path}: no converged semi-smooth solve in the trace (run with SLITHER_DEBUG=1)")
    total = sum(s[0] for s in steps)
    print(f"## {label}")
    print()
    print(f"{len(steps)} converged solves, {total / len(steps):.2f} iterations each; "
          f"{failed} attempts that did not converge")
    with_diff = [s for s in steps if s[1] is not None]
    means = [sum(s[1][k] for s in with_diff) / max(1, len(with_diff)) for k in range(len(KINDS))]
    print("converged statuses against the last step's, per step: "
          + ", ".join(f"{name} {v:.2f}" for (name, _, _), v in zip(KINDS, means)))
    jump = max((sum(s[1][:2]) for s in with_diff), default=0)
    print(f"largest change of stick and slide statuses from one step to the next: {jump} contacts")
    print()
    print("| iterations per step | steps | share of iterations | "
          + " | ".join(name for name, _, _ in KINDS)
          + " | status changes per iteration | contacts back and forth |")
    print("|---" * (5 + len(KINDS)) + "|")
    for lo, hi in BANDS:
        band = [s for s in steps if lo <= s[0] <= hi]
        if not band:
            continue
        share = sum(s[0] for s in band) / total
        bd = [s for s in band if s[1] is not None]
        kinds = [sum(s[1][k] for s in bd) / max(1, len(bd)) for k in range(len(KINDS))]
        inner = sum(s[2] for s in band) / len(band)
        bf = sum(s[3] for s in band) / len(band)
        name = f"{lo} to {hi}" if hi < 10**9 else f"{lo} or more"
        print(f"| {name} | {len(band)} | {100 * share:.0f} % | "
              + " | ".join(f"{k:.2f}" for k in kinds)
              + f" | {inner:.2f} | {bf:.2f} |")
    print()
    if window:
        print(f"In windows of {window} steps:")
        print()
        print("| steps | iterations per step | steps of 10 or more | landings per step | "
              "lift-offs per step | first statuses off the converged | first merit (median) |")
        print("|---|---|---|---|---|---|---|")
        for lo in range(0, len(steps), window):
            w = steps[lo:lo + window]
            wd = [s for s in w if s[1] is not None]
            land = sum(s[1][2] for s in wd) / max(1, len(wd))
            lift = sum(s[1][3] for s in wd) / max(1, len(wd))
            thetas = sorted(s[5] for s in w if s[5] is not None)
            med = thetas[len(thetas) // 2] if thetas else float("nan")
            print(f"| {lo + 1} to {lo + len(w)} | {sum(s[0] for s in w) / len(w):.2f} | "
                  f"{100 * sum(1 for s in w if s[0] >= 10) / len(w):.0f} % | {land:.2f} | "
                  f"{lift:.2f} | {sum(s[4] for s in w) / len(w):.1f} | {med:.2e} |")
        print()


if __name__ == "__main__":
    main()
