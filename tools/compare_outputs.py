#!/usr/bin/env python3
"""Compare what two slither binaries write, field by field, timers excepted.

For a refactoring that must leave results bit for bit unchanged: runs the old and the new
binary on every bundled scene (problems/*.toml with a [rod] table) and compares every
summary.json field except the timers (wall_time_s, wall_time_total_s and the *_s timers of
the solver statistics), plus final.csv and the arrays of trajectory.npz byte for byte; runs the bundled
phase study (problems/phase_s_start.toml) and compares phase.csv, refine.csv and
boundaries.json without their wall-time columns; optionally a shortened optimize study.

    tools/compare_outputs.py --old /tmp/slither_old --new target/release/slither \
        --work /tmp/cmp [--only s_start,slide] [--skip-phase] [--optimize] \
        [--retired stats.active_set_,stats.switches.]

`--retired` names summary.json fields (prefixes of their dotted paths) that a change removed
on purpose: found only in the old output they are counted and listed once per scene, not as
differences; any other field found in one output only still is one.

Exit status 0 when every compared field is identical (floats compared exactly, NaN equal to
NaN), 1 otherwise. Single-threaded (RAYON_NUM_THREADS=1) so the runs are deterministic and
fit beside other builds.
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# Timer keys: wall-clock seconds, different on every run.
TIMERS = {
    "wall_time_s",
    "wall_time_total_s",
    "assembly_s",
    "factor_s",
    "solve_s",
    "line_search_s",
    "conic_s",
    "wall_s",
    "elapsed_s",
}


def is_timer(key):
    return key in TIMERS or key.endswith("wall_time_s") or key.endswith("_time_s")


def flatten(v, prefix=""):
    """Flatten JSON into {path: leaf}, dropping timer keys."""
    out = {}
    if isinstance(v, dict):
        for k, x in v.items():
            if is_timer(k):
                continue
            out.update(flatten(x, f"{prefix}.{k}" if prefix else k))
    elif isinstance(v, list):
        for i, x in enumerate(v):
            out.update(flatten(x, f"{prefix}[{i}]"))
    else:
        out[prefix] = v
    return out


def same(a, b):
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return type(a) is type(b) and a == b


RETIRED = ()


def compare_json(old, new, label):
    """Differences between two JSON files (list of strings), and the number of compared fields."""
    a = flatten(json.loads(Path(old).read_text()))
    b = flatten(json.loads(Path(new).read_text()))
    diffs = []
    for k in sorted(set(a) | set(b)):
        if k in a and k not in b and k.startswith(RETIRED):
            del a[k]
            continue
        if k not in a or k not in b:
            diffs.append(f"{label}: {k} only in {'new' if k not in a else 'old'}")
        elif not same(a[k], b[k]):
            diffs.append(f"{label}: {k}: old {a[k]!r} new {b[k]!r}")
    return diffs, len(a)


def compare_csv(old, new, label):
    """Differences between two CSV files, timer columns dropped; and the number of cells compared."""
    ra = list(csv.reader(Path(old).read_text().splitlines()))
    rb = list(csv.reader(Path(new).read_text().splitlines()))
    if not ra or not rb:
        return ([] if ra == rb else [f"{label}: one file empty"]), 0
    if ra[0] != rb[0]:
        return [f"{label}: headers differ: {ra[0]} vs {rb[0]}"], 0
    keep = [i for i, h in enumerate(ra[0]) if not is_timer(h)]
    diffs = []
    if len(ra) != len(rb):
        diffs.append(f"{label}: {len(ra) - 1} rows old, {len(rb) - 1} new")
    # Rows may come in completion order (parallel sweeps): compare as sorted multisets.
    ka = sorted(tuple(r[i] for i in keep) for r in ra[1:])
    kb = sorted(tuple(r[i] for i in keep) for r in rb[1:])
    for x, y in zip(ka, kb):
        if x != y:
            diffs.append(f"{label}: row differs:\n  old {x}\n  new {y}")
    return diffs, len(keep) * (len(ra) - 1)


def compare_bytes(old, new, label):
    a, b = Path(old), Path(new)
    if a.exists() != b.exists():
        return [f"{label}: exists only in {'old' if a.exists() else 'new'}"]
    if a.exists() and a.read_bytes() != b.read_bytes():
        return [f"{label}: bytes differ"]
    return []


def compare_npz(old, new, label):
    """The arrays of two .npz archives byte for byte (the zip entries' timestamps differ)."""
    import zipfile

    a, b = Path(old), Path(new)
    if a.exists() != b.exists():
        return [f"{label}: exists only in {'old' if a.exists() else 'new'}"]
    if not a.exists():
        return []
    za, zb = zipfile.ZipFile(a), zipfile.ZipFile(b)
    if za.namelist() != zb.namelist():
        return [f"{label}: members differ: {za.namelist()} vs {zb.namelist()}"]
    return [f"{label}: {n} differs" for n in za.namelist() if za.read(n) != zb.read(n)]


def run(binary, args, env):
    p = subprocess.run([binary] + args, capture_output=True, text=True, env=env, cwd=ROOT)
    return p.returncode, p.stderr


def scenes():
    for f in sorted((ROOT / "problems").glob("*.toml")):
        if re.search(r"^\[rod\]", f.read_text(), re.M):
            yield f


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--only", help="comma-separated scene names (file stems)")
    ap.add_argument("--skip-scenes", action="store_true")
    ap.add_argument("--skip-phase", action="store_true")
    ap.add_argument("--optimize", action="store_true", help="also a 6-evaluation optimize study")
    ap.add_argument("--short", action="store_true", help="also `run --accuracy 0.05` and the gait work-precision chart on the S-start cut to 0.3 s")
    ap.add_argument("--retired", help="comma-separated prefixes of summary.json fields removed on purpose (only in the old output)")
    args = ap.parse_args()
    global RETIRED
    RETIRED = tuple(args.retired.split(",")) if args.retired else ()
    if RETIRED:
        print(f"retired fields (only in the old summary.json, not compared): {', '.join(RETIRED)}")
    work = Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    env.pop("SLITHER_DEBUG", None)
    bins = {"old": str(Path(args.old).resolve()), "new": str(Path(args.new).resolve())}
    only = set(args.only.split(",")) if args.only else None
    failures = 0
    if not args.skip_scenes:
        for scene in scenes():
            name = scene.stem
            if only and name not in only:
                continue
            codes = {}
            for tag, b in bins.items():
                codes[tag], _ = run(b, ["run", str(scene), "--out", str(work / tag / name), "--quiet", "--no-plots"], env)
            diffs = []
            if codes["old"] != codes["new"]:
                diffs.append(f"exit codes old {codes['old']} new {codes['new']}")
            d, n = compare_json(work / "old" / name / "summary.json", work / "new" / name / "summary.json", "summary.json")
            diffs += d
            diffs += compare_bytes(work / "old" / name / "final.csv", work / "new" / name / "final.csv", "final.csv")
            diffs += compare_npz(work / "old" / name / "trajectory.npz", work / "new" / name / "trajectory.npz", "trajectory.npz")
            status = "IDENTICAL" if not diffs else "DIFFERENT"
            print(f"{name}: exit {codes['new']}, {n} summary.json fields, final.csv, trajectory.npz: {status}")
            for x in diffs[:20]:
                print("   ", x)
            failures += bool(diffs)
    if not args.skip_phase:
        study = ROOT / "problems" / "phase_s_start.toml"
        codes = {}
        for tag, b in bins.items():
            codes[tag], _ = run(b, ["phase", str(study), "--out", str(work / tag / "phase"), "--quiet"], env)
        diffs = [] if codes["old"] == codes["new"] else [f"exit codes old {codes['old']} new {codes['new']}"]
        n = 0
        for f in ["phase.csv", "refine.csv"]:
            a, b = work / "old" / "phase" / f, work / "new" / "phase" / f
            if a.exists() or b.exists():
                if not (a.exists() and b.exists()):
                    diffs.append(f"{f} exists only in one")
                    continue
                d, k = compare_csv(a, b, f)
                diffs += d
                n += k
        for f in sorted(p.name for p in (work / "old" / "phase").glob("*.json")):
            d, k = compare_json(work / "old" / "phase" / f, work / "new" / "phase" / f, f)
            diffs += d
            n += k
        print(f"phase_s_start: exit {codes['new']}, {n} cells/fields of phase.csv, refine.csv and json: {'IDENTICAL' if not diffs else 'DIFFERENT'}")
        for x in diffs[:20]:
            print("   ", x)
        failures += bool(diffs)
    if args.optimize:
        text = (ROOT / "problems" / "optimize_s_start.toml").read_text()
        text = re.sub(r"^max_evaluations\s*=.*$", "max_evaluations = 6", text, flags=re.M)
        text = text.replace('base = "s_start.toml"', f'base = "{ROOT / "problems" / "s_start.toml"}"')
        study = work / "optimize_short.toml"
        study.write_text(text)
        codes = {}
        for tag, b in bins.items():
            codes[tag], _ = run(b, ["optimize", str(study), "--out", str(work / tag / "optimize"), "--quiet"], env)
        diffs = [] if codes["old"] == codes["new"] else [f"exit codes old {codes['old']} new {codes['new']}"]
        d, n = compare_csv(work / "old" / "optimize" / "history.csv", work / "new" / "optimize" / "history.csv", "history.csv")
        diffs += d
        if (work / "old" / "optimize" / "optimum.json").exists():
            d, k = compare_json(work / "old" / "optimize" / "optimum.json", work / "new" / "optimize" / "optimum.json", "optimum.json")
            diffs += d
            n += k
        print(f"optimize (6 evaluations): exit {codes['new']}, {n} cells/fields of history.csv and optimum.json: {'IDENTICAL' if not diffs else 'DIFFERENT'}")
        for x in diffs[:20]:
            print("   ", x)
        failures += bool(diffs)
    if args.short:
        text = (ROOT / "problems" / "s_start.toml").read_text()
        text = re.sub(r"^duration\s*=.*$", "duration = 0.3", text, flags=re.M)
        short = work / "s_start_short.toml"
        short.write_text(text)
        jobs = [
            ("run --accuracy 0.05", ["run", str(short), "--quiet", "--no-plots", "--accuracy", "0.05", "--out"], "accuracy"),
            ("chart work-precision", ["chart", "work-precision", str(short), "--out"], "gait_chart"),
        ]
        for label, cmd, name in jobs:
            codes = {}
            for tag, b in bins.items():
                codes[tag], _ = run(b, cmd + [str(work / tag / name)], env)
            diffs = [] if codes["old"] == codes["new"] else [f"exit codes old {codes['old']} new {codes['new']}"]
            n = 0
            for f in sorted(p.name for p in (work / "old" / name).iterdir()):
                a, b = work / "old" / name / f, work / "new" / name / f
                if f.endswith(".json"):
                    d, k = compare_json(a, b, f)
                elif f.endswith(".csv"):
                    d, k = compare_csv(a, b, f)
                elif f.endswith(".npz"):
                    d, k = compare_npz(a, b, f), 0
                else:
                    continue
                diffs += d
                n += k
            print(f"{label} (S-start, 0.3 s): exit {codes['new']}, {n} fields of its JSON/CSV files: {'IDENTICAL' if not diffs else 'DIFFERENT'}")
            for x in diffs[:20]:
                print("   ", x)
            failures += bool(diffs)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
