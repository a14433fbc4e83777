"""Tests of slither_gait against the slither CLI (run by tests/python.rs, or directly:
SLITHER_BIN=target/release/slither python -m pytest python/tests from the repository root)."""
import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import slither_gait as sg

ROOT = Path(os.environ.get("SLITHER_ROOT", Path(__file__).resolve().parents[2]))
BIN = os.environ.get("SLITHER_BIN", str(ROOT / "target" / "release" / "slither"))
S_START = "problems/s_start.toml"


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def cli(*args, check=True):
    r = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True,
                       env={**os.environ, "RAYON_NUM_THREADS": "1"})
    if check and r.returncode != 0:
        raise AssertionError(f"slither {' '.join(map(str, args))}: {r.stderr}")
    return r


def comparable(summary):
    """summary.json without what may differ between two identical runs: wall times, the
    solver's timers (stats.*_s) and the problem's path."""
    s = json.loads(json.dumps(summary))
    s.pop("problem")
    s.pop("wall_time_s")
    for k in [k for k in s["stats"] if k.endswith("_s")]:
        s["stats"].pop(k)
    return s


def same_bits(a, b):
    """Dicts, lists and floats equal to the bit (NaN equal to NaN, -0.0 not equal to 0.0)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same_bits(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(same_bits, a, b))
    if isinstance(a, float) and isinstance(b, float):
        return np.float64(a).tobytes() == np.float64(b).tobytes()
    return type(a) is type(b) and a == b


def no_wall(d):
    """A JSON value without the keys that hold wall times."""
    if isinstance(d, dict):
        return {k: no_wall(v) for k, v in d.items() if "wall" not in k}
    if isinstance(d, list):
        return [no_wall(v) for v in d]
    return d


def same_columns(a, b):
    """CSV columns equal to the bit, but for wall times."""
    keys = [k for k in a if "wall" not in k]
    assert keys == [k for k in b if "wall" not in k]
    for k in keys:
        x, y = a[k], b[k]
        if isinstance(x, list):
            assert x == y, k
        else:
            assert x.tobytes() == y.tobytes(), k
    return True


def by_cell(cols):
    """phase.csv columns with the rows in (weight, torque) order."""
    order = np.lexsort((cols["torque"], cols["weight"]))
    return {k: ([v[i] for i in order] if isinstance(v, list) else v[order]) for k, v in cols.items()}


def short(duration=0.2):
    return sg.load_problem(S_START).with_(**{"time.duration": duration})


def test_summary_and_files_match_the_cli_to_the_bit(tmp_path):
    cli("run", S_START, "--out", tmp_path / "cli", "--quiet", "--no-plots")
    r = sg.run(sg.load_problem(S_START), progress=False)
    with open(tmp_path / "cli" / "summary.json") as f:
        expected = json.load(f)
    assert r.summary["status"] == "completed"
    assert same_bits(comparable(r.summary), comparable(expected))
    # A mutation the comparison must see: one ulp in one observable.
    changed = comparable(r.summary)
    changed["v_s"] = float(np.nextafter(changed["v_s"], 1.0))
    assert not same_bits(changed, comparable(expected))
    # The files save() writes are the CLI's: final.csv byte for byte, every array to the bit.
    r.save(tmp_path / "py", plots=False)
    assert (tmp_path / "py" / "final.csv").read_bytes() == (tmp_path / "cli" / "final.csv").read_bytes()
    with np.load(tmp_path / "cli" / "trajectory.npz") as a, np.load(tmp_path / "py" / "trajectory.npz") as b:
        assert sorted(a.files) == sorted(b.files)
        for k in a.files:
            assert a[k].shape == b[k].shape and a[k].tobytes() == b[k].tobytes(), k
            assert r.arrays[k].tobytes() == a[k].tobytes(), k
    # load() reads the files back to the same result.
    back = sg.load(tmp_path / "py")
    assert same_bits(back.summary, json.loads(json.dumps(r.summary)))
    for k in r.arrays:
        assert back.arrays[k].tobytes() == r.arrays[k].tobytes(), k
    assert back.regime == r.regime == expected["regime"]


def test_save_writes_what_slither_run_writes_byte_for_byte(tmp_path):
    # One run pipeline: save() writes the CLI's files, figures, tracks and movie included,
    # each byte for byte; summary.json differs only in its timers and the problem's name.
    cli("run", S_START, "--set", "time.duration=0.2", "--out", tmp_path / "cli", "--quiet")
    r = sg.run(short(0.2), progress=False)
    r.save(tmp_path / "py")
    def listing(d):
        return sorted(str(p.relative_to(d)) for p in d.rglob("*") if p.is_file())
    a, b = listing(tmp_path / "cli"), listing(tmp_path / "py")
    assert a == b
    assert {"tracks.png", "movie.gif", "snapshots.png", "trajectory.npz"} <= set(a)
    for name in a:
        if name != "summary.json":
            assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name
    with open(tmp_path / "cli" / "summary.json") as f:
        expected = json.load(f)
    assert same_bits(comparable(r.summary), comparable(expected))


def test_save_that_cannot_replace_keeps_the_previous_results(tmp_path):
    # save() goes through the CLI's staged commit: a directory where a result file must go
    # (which even root cannot replace) leaves the previous files and names the new ones' folder.
    r = sg.run(sg.load_problem(S_START).with_(**{"time.duration": 0.05}), progress=False)
    out = tmp_path / "py"
    r.save(out, plots=False)
    before = (out / "summary.json").read_bytes()
    (out / "movie_top_contact.gif").write_bytes(b"old movie")
    (out / "notes.txt").write_text("mine")
    (out / "final.csv").rename(out / "kept.csv")
    (out / "final.csv" / "inside").mkdir(parents=True)
    with pytest.raises(OSError) as e:
        r.save(out, plots=False)
    assert "final.csv" in str(e.value) and "unsaved_run_" in str(e.value)
    assert (out / "summary.json").read_bytes() == before
    assert (out / "movie_top_contact.gif").exists()
    kept = [d for d in out.iterdir() if d.name.startswith("unsaved_run_")]
    assert len(kept) == 1 and (kept[0] / "summary.json").exists()
    # Once the obstacle is gone a save replaces everything of slither's, the movie too.
    (out / "final.csv" / "inside").rmdir()
    (out / "final.csv").rmdir()
    r.save(out, plots=False)
    assert (out / "final.csv").is_file() and not (out / "movie_top_contact.gif").exists()
    assert (out / "notes.txt").read_text() == "mine"


BAD = [
    ("rod", "elements = 100", "elements = 0"),
    ("rod", "length = 1.0", "length = -1.0"),
    ("gait", "speed = 0.28", "speed = 0.28\nv_m = 0.3"),
    ("time", "dt = 3.6e-3", "dt = 0.0"),
]


@pytest.mark.parametrize("table,old,new", BAD)
def test_bad_input_raises_value_error_with_the_cli_message(tmp_path, table, old, new):
    text = (ROOT / S_START).read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    r = cli("run", bad, "--out", tmp_path / "out", "--quiet", "--no-plots", check=False)
    assert r.returncode == 2
    message = r.stderr.strip()
    assert message.startswith("error: ")
    with pytest.raises(ValueError) as e:
        sg.load_problem(str(bad))
    assert str(e.value).strip() == message[len("error: "):]
    with pytest.raises(ValueError) as e:
        sg.Problem.from_toml(bad.read_text(), name=str(bad))
    assert str(e.value).strip() == message[len("error: "):]


def test_bad_override_names_the_key_and_range():
    p = sg.load_problem(S_START)
    with pytest.raises(ValueError, match=r"`rod\.elements` = 0 is not allowed: must be"):
        p.with_(**{"rod.elements": 0})
    with pytest.raises(ValueError, match="unknown field `v_m`"):
        p.with_(gait={"v_m": 0.3})
    with pytest.raises(ValueError, match=r"`time\.dt`"):
        sg.Problem.from_dict({**p.to_dict(), "time": {"dt": -1.0, "duration": 1.0}})
    with pytest.raises(TypeError):
        p.with_(**{"gait.speed": object()})


def test_overrides():
    p = sg.load_problem(S_START)
    q = p.with_(**{"gait.speed": 0.3, "time.duration": 0.1})
    assert q.to_dict()["gait"]["speed"] == 0.3 and q.to_dict()["time"]["duration"] == 0.1
    assert p.to_dict()["gait"]["speed"] == 0.28  # the original is unchanged
    assert q.to_dict() == p.with_(gait={"speed": 0.3}, time={"duration": 0.1}).to_dict()
    assert q.to_dict() == p.with_({"gait": {"speed": 0.3}, "time.duration": 0.1}).to_dict()
    # Untouched keys keep their values; a dict round trip is the same problem.
    assert q.to_dict()["gait"]["centers"] == p.to_dict()["gait"]["centers"]
    assert sg.Problem.from_dict(q.to_dict()).to_dict() == q.to_dict()
    r = sg.run(q, progress=False)
    assert r.summary["t_final"] == pytest.approx(0.1, rel=1e-12)
    # The override reaches the model: the dimensionless pulse speed is measured against 0.3.
    assert r.summary["v_s_over_v_m"] == pytest.approx(r.summary["v_s"] / 0.3, rel=1e-12)


def test_arrays_have_the_documented_shapes_and_units():
    p = short(0.36)
    r = sg.run(p, progress=False)
    n, a, length = 101, 0.02, 1.0
    f = len(r.t)
    assert f == 11  # frames every 0.036 s from 0 to 0.36 s
    assert r.t[0] == 0.0 and r.t[-1] == pytest.approx(0.36, rel=1e-12)
    shapes = {"s": (n,), "x": (f, n, 3), "v": (f, n, 3), "theta": (f, n - 1),
              "normal_force": (f, n), "slip_velocity": (f, n, 3), "elevation": (f, n),
              "slip_speed": (f, n)}
    for name, shape in shapes.items():
        assert getattr(r, name).shape == shape, name
        assert getattr(r, name).dtype == np.float64
    assert r.lambda_.shape[0] == f and r.lambda_.ndim == 2
    assert set(sg.ARRAYS) == set(shapes) | {"t", "lambda_", "diameter", "gait_period",
                                            "gait_speed", "stuck_speed"}
    assert r.diameter.shape == (1,) and r.diameter[0] == a
    # Metres: arc length from the head to the tail is L; the initial rod lies straight on
    # the ground at z = a/2, and the elevation is z - a/2.
    assert r.s[0] == 0.0 and r.s[-1] == pytest.approx(length, rel=1e-12)
    seg = np.linalg.norm(np.diff(r.x[0], axis=0), axis=1).sum()
    assert seg == pytest.approx(length, rel=1e-9)
    assert np.allclose(r.x[0, :, 2], a / 2)
    assert np.allclose(r.elevation, r.x[:, :, 2] - a / 2, atol=1e-15)
    # Newtons: the ground carries about the weight rho g pi a^2/4 L = 3.08 N (the muscles
    # press the middle down and lift the bends: 2.97 N at 0.36 s; a force per length would be
    # 100x larger).
    weight = 1000.0 * 9.81 * np.pi * a**2 / 4 * length
    assert 0.8 < r.normal_force[-1].sum() / weight < 1.25
    # Summed node by node in order, as the run sums it (numpy's pairwise sum may differ in the
    # last bit).
    assert sum(r.normal_force[-1].tolist()) == r.summary["normal_force_final"]
    # m/s: the displacement over a frame interval divided by the interval is the frames' mean
    # velocity to within a factor 2 (a velocity per step or in mm/s would be off by 18x or
    # 1000x).
    dt = np.diff(r.t)[:, None, None]
    moved = np.linalg.norm((r.x[1:] - r.x[:-1]) / dt)
    mean_v = np.linalg.norm(0.5 * (r.v[1:] + r.v[:-1]))
    assert 0.5 < moved / mean_v < 2.0


def test_keyboard_interrupt_stops_a_long_run_within_steps():
    # Python's own Ctrl-C handler, also when this process was started with SIGINT ignored
    # (a background job of a non-interactive shell inherits SIG_IGN, and Python then
    # installs no handler, so SIGINT would do nothing at all).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _interrupt_a_long_run()
    finally:
        signal.signal(signal.SIGINT, previous)


def _interrupt_a_long_run():
    p = sg.load_problem(S_START).with_(**{"time.duration": 200.0})
    steps = []
    timer = threading.Timer(0.5, lambda: (steps.append(time.perf_counter()),
                                          os.kill(os.getpid(), signal.SIGINT)))
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        sg.run(p, progress=False, force=True)
    t1 = time.perf_counter()
    timer.join()
    latency = t1 - steps[0]
    print(f"KeyboardInterrupt {latency * 1e3:.0f} ms after SIGINT "
          f"(checks every {sg._native.CHECK_EVERY_S * 1e3:.0f} ms)")
    assert t1 - t0 < 30.0  # the run (100000 steps) was cut short
    assert latency < 1.0
    # The module is still usable after the interrupt.
    assert sg.run(short(0.02), progress=False).summary["status"] == "completed"


def test_two_threads_simulate_at_the_same_time():
    p = short(1.0)
    seen = {0: [], 1: []}
    results = {}

    def work(i):
        results[i] = sg.run(p, progress=lambda frac: seen[i].append(time.perf_counter()))

    threads = [threading.Thread(target=work, args=(i,)) for i in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    # The first and last progress calls bracket each simulation (first and last step).
    (s0, e0), (s1, e1) = (seen[0][0], seen[0][-1]), (seen[1][0], seen[1][-1])
    print(f"thread 0 simulated {s0:.3f} .. {e0:.3f} s, thread 1 {s1:.3f} .. {e1:.3f} s")
    assert max(s0, s1) < min(e0, e1), "the two simulations did not overlap"
    assert same_bits(comparable(results[0].summary)["v_s"], comparable(results[1].summary)["v_s"])


def test_topology_matches_the_cli(tmp_path):
    k = np.arange(40)
    phi = 2 * np.pi * k / 40
    x = np.stack([np.cos(phi), np.sin(phi), 0.2 * np.sin(3 * phi)], axis=1)
    tangent = np.roll(x, -1, axis=0) - x
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    up = np.array([0.0, 0.0, 1.0])
    d1 = up - (tangent @ up)[:, None] * tangent  # z up, made normal to each edge
    d1 /= np.linalg.norm(d1, axis=1)[:, None]
    csv = tmp_path / "curve.csv"
    with open(csv, "w") as f:
        f.write("x,y,z,d1x,d1y,d1z\n")
        for p, d in zip(x, d1):
            f.write(",".join(repr(float(v)) for v in [*p, *d]) + "\n")
    for closed in (False, True):
        out = cli("topology", csv, *(["--closed"] if closed else []))
        expected = json.loads(out.stdout)
        assert same_bits(sg.topology(csv, closed=closed), expected)
        assert same_bits(sg.topology((x, d1), closed=closed), expected)
    with pytest.raises(ValueError, match="<arrays>"):
        sg.topology((x[:1], d1[:1]))


def test_optimize_and_phase_hold_what_their_files_hold(tmp_path):
    base = tmp_path / "base.toml"
    base.write_text(short(0.1).to_toml())
    study = tmp_path / "study.toml"
    study.write_text(
        '[study]\nbase = "base.toml"\nmax_evaluations = 3\n\n'
        "[optimize]\nspeed = [0.25, 0.3]\n")
    o = sg.optimize(study, out=tmp_path / "opt", progress=False)
    cli("optimize", study, "--out", tmp_path / "opt_cli", "--quiet")
    with open(tmp_path / "opt_cli" / "optimum.json") as f:
        cli_optimum = json.load(f)
    assert o.counts["simulations"] == 3 and len(o.history["v_s"]) == 3
    assert same_bits(no_wall(o.optimum), no_wall(cli_optimum))
    assert same_columns(o.history, sg._read_csv(tmp_path / "opt_cli" / "history.csv"))
    ph = tmp_path / "phase.toml"
    ph.write_text('[phase]\nbase = "base.toml"\nweight = [300.0]\ntorque = [10.0, 15.0]\n')
    d = sg.phase(ph, out=tmp_path / "ph", progress=False)
    cli("phase", ph, "--out", tmp_path / "ph_cli", "--quiet")
    cli_cells = sg._read_csv(tmp_path / "ph_cli" / "phase.csv")
    assert d.counts["cells"] == 2 and len(d.cells["regime"]) == 2
    # Cells are appended as they finish (in parallel): compare them in grid order.
    assert same_columns(by_cell(d.cells), by_cell(cli_cells))
    with pytest.raises(ValueError, match="shard"):
        sg.phase(ph, shard="3/2", out=tmp_path / "ph2")
