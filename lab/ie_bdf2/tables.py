#!/usr/bin/env python3
"""Markdown tables from runs/table.tsv (last line per run wins)."""
import csv, sys
rows = list(csv.reader(open("runs/table.tsv"), delimiter="\t"))[1:]
seen = {}
for r in rows: seen[(r[0], r[1], r[2], r[3])] = r
def table(labels, cols=("v_s/v_m",)):
    print("| scene | integrator | elements | dt (s) | v_s/v_m | centroid x, y (m) | head x, y (m) | max elev./a | Newton it/step | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for k, r in seen.items():
        if k[0] in labels:
            print("| %s | %s | %s | %s | %s | %s, %s | %s, %s | %s | %s | %s |" % (r[0], "IE" if r[1] == "implicit" else "BDF2", r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[11], r[14]))
    print()
table(sys.argv[1].split(","))
