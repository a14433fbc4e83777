#!/usr/bin/env python3
"""Compare two phase.csv files of one grid (a study before and after a change of the model):
regime counts, the transition table, every cell whose label changed, the writhe and v_s/v_m
of the cells by regime, and for verified studies the uncertain cells. Prints Markdown (for tools/record.sh).

    python3 lab/self_contact_phase_verified/phase_compare.py BEFORE/phase.csv AFTER/phase.csv [NAME_BEFORE NAME_AFTER]
"""
import csv
import statistics
import sys
from collections import Counter


def rows(path):
    with open(path) as f:
        return {(float(r["weight"]), float(r["torque"])): r for r in csv.DictReader(f)}


def main():
    if len(sys.argv) not in (3, 5):
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    before, after = rows(sys.argv[1]), rows(sys.argv[2])
    nb, na = (sys.argv[3], sys.argv[4]) if len(sys.argv) == 5 else ("before", "after")
    if set(before) != set(after):
        print(f"the two files have different cells ({len(before)} and {len(after)})", file=sys.stderr)
        sys.exit(1)
    cells = sorted(before)
    regimes = sorted({r["regime"] for r in before.values()} | {r["regime"] for r in after.values()})
    cb = Counter(before[c]["regime"] for c in cells)
    ca = Counter(after[c]["regime"] for c in cells)
    print(f"{len(cells)} cells; regimes {nb}: " + ", ".join(f"{k} {cb[k]}" for k in regimes))
    print(f"{len(cells)} cells; regimes {na}: " + ", ".join(f"{k} {ca[k]}" for k in regimes))
    print()
    print(f"Transitions (rows {nb}, columns {na}):")
    print()
    print("| | " + " | ".join(regimes) + " |")
    print("|---" * (len(regimes) + 1) + "|")
    moves = Counter((before[c]["regime"], after[c]["regime"]) for c in cells)
    for r in regimes:
        print(f"| {r} | " + " | ".join(str(moves[(r, s)]) for s in regimes) + " |")
    changed = [c for c in cells if before[c]["regime"] != after[c]["regime"]]
    print()
    print(f"{len(changed)} cells changed label:")
    print()
    print(f"| W | G | W/G | {nb} | {na} | v_s/v_m {nb} | v_s/v_m {na} | writhe snapshot {nb} | {na} | max elevation / a {nb} | {na} |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    f = lambda r, k: float(r[k]) if r[k] not in ("", "nan", "NaN") else float("nan")
    for c in changed:
        b, a = before[c], after[c]
        print(f"| {c[0]:.1f} | {c[1]:.2f} | {c[0] / c[1]:.2f} | {b['regime']} | {a['regime']} | "
              f"{f(b, 'v_s_over_v_m'):.4f} | {f(a, 'v_s_over_v_m'):.4f} | {f(b, 'writhe_snapshot'):.3f} | "
              f"{f(a, 'writhe_snapshot'):.3f} | {f(b, 'max_elevation_over_a'):.2f} | {f(a, 'max_elevation_over_a'):.2f} |")
    print()
    print("By regime (median over the cells of that label): v_s/v_m, writhe snapshot, largest |writhe|, cell wall s")
    print()
    print("| regime | " + nb + ": cells, v_s/v_m, Wr snapshot, max Wr, wall s | " + na + ": cells, v_s/v_m, Wr snapshot, max Wr, wall s |")
    print("|---|---|---|")
    for r in regimes:
        out = []
        for data in (before, after):
            sel = [data[c] for c in cells if data[c]["regime"] == r]
            if not sel:
                out.append("0")
                continue
            med = lambda k: statistics.median(f(x, k) for x in sel)
            out.append(f"{len(sel)}, {med('v_s_over_v_m'):.4f}, {med('writhe_snapshot'):.3f}, "
                       f"{med('writhe_max'):.3f}, {med('wall_time_s'):.2f}")
        print(f"| {r} | {out[0]} | {out[1]} |")
    if "label_agreement" in before[cells[0]] and "label_agreement" in after[cells[0]]:
        # Verified studies: a cell is uncertain when its runs disagree (agreement below 1).
        unsure = lambda data: [c for c in cells if float(data[c]["label_agreement"]) < 1.0]
        ub, ua = unsure(before), unsure(after)
        print()
        print(f"uncertain cells (label agreement below 1): {nb} {len(ub)}, {na} {len(ua)}; "
              f"uncertain in both {len(set(ub) & set(ua))}, only {nb} {len(set(ub) - set(ua))}, "
              f"only {na} {len(set(ua) - set(ub))}")
        print()
        print(f"| W | G | {nb}: label, agreement | {na}: label, agreement |")
        print("|---|---|---|---|")
        for c in cells:
            if c in ub or c in ua:
                print(f"| {c[0]:.1f} | {c[1]:.2f} | {before[c]['regime']}, {float(before[c]['label_agreement']):.2f} | "
                      f"{after[c]['regime']}, {float(after[c]['label_agreement']):.2f} |")
    tb = sum(f(before[c], "wall_time_s") for c in cells)
    ta = sum(f(after[c], "wall_time_s") for c in cells)
    print()
    print(f"sum of cell wall times: {nb} {tb:.1f} s, {na} {ta:.1f} s")


if __name__ == "__main__":
    main()
