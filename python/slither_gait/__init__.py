"""slither in Python: snake locomotion on discrete elastic rods, with numpy arrays.

The engine is slither's Rust library (``slither_gait._native``); this package gives the same
answers as the ``slither`` command line, through the same library calls::

    import slither_gait as sg
    p = sg.load_problem("problems/s_start.toml")
    r = sg.run(p.with_(**{"gait.speed": 0.3}))
    r.summary["v_s"], r.regime, r.x.shape      # summary.json as a dict; (frames, nodes, 3) in m
    r.save("out")                              # the files `slither run` writes

Problems are validated as problem files are (a bad key or value raises ``ValueError`` with
the CLI's message). ``run`` releases the GIL while it simulates, so runs in several Python
threads proceed in parallel, and Ctrl-C raises ``KeyboardInterrupt`` within a few steps.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Union

import numpy as np

from . import _native
from ._native import Problem, load_problem

__all__ = [
    "Problem",
    "load_problem",
    "run",
    "Result",
    "SimulationError",
    "load",
    "optimize",
    "Optimization",
    "phase",
    "PhaseDiagram",
    "topology",
    "ARRAYS",
]

PathLike = Union[str, "os.PathLike[str]"]

#: The arrays of a result (the contents of ``trajectory.npz``): name -> (shape, unit).
#: F frames, N real nodes (head first), W windows of the link density.
ARRAYS: Dict[str, tuple] = {
    "t": ("(F,)", "s (static runs: load fraction)"),
    "s": ("(N,)", "m, arc length of each node"),
    "x": ("(F, N, 3)", "m, node positions"),
    "v": ("(F, N, 3)", "m/s, node velocities"),
    "theta": ("(F, N-1)", "rad, edge twist angles"),
    "normal_force": ("(F, N)", "N, normal contact force on each node"),
    "slip_velocity": ("(F, N, 3)", "m/s, horizontal velocity of nodes in contact, 0 elsewhere"),
    "elevation": ("(F, N)", "m, z - a/2"),
    "slip_speed": ("(F, N)", "m/s, horizontal speed of nodes in contact, NaN in the air"),
    "lambda_": ("(F, W)", "turns/m, local link density"),
    "diameter": ("(1,)", "m, the rod's diameter a (for the movie renderer)"),
    "gait_period": ("(1,)", "s, the gait's pulse time (NaN without a gait)"),
    "gait_speed": ("(1,)", "m/s, the gait's v_m (NaN without a gait)"),
    "stuck_speed": ("(1,)", "m/s, the slip speed below which a contact counts as stuck"),
}


class SimulationError(RuntimeError):
    """A run stopped by a failed step. ``.result`` holds everything computed up to it."""

    def __init__(self, message: str, result: "Result"):
        super().__init__(message)
        self.result = result


class Result:
    """A run: ``summary`` (the dict of ``summary.json``), ``regime``, and the arrays of
    ``trajectory.npz`` as attributes (see :data:`ARRAYS`; ``lambda`` is ``lambda_``).
    """

    def __init__(self, summary: Dict[str, Any], arrays: Dict[str, np.ndarray],
                 native: Optional[Any] = None, source: Optional[Path] = None):
        self.summary = summary
        self._arrays = arrays
        self._native = native
        self._source = source

    def __getattr__(self, name: str) -> np.ndarray:
        key = "lambda" if name == "lambda_" else name
        arrays = self.__dict__.get("_arrays", {})
        if key in arrays:
            return arrays[key]
        raise AttributeError(name)

    @property
    def regime(self) -> Optional[str]:
        """The regime letter of the run (``summary["regime"]``; None for a failed run)."""
        return self.summary.get("regime")

    @property
    def arrays(self) -> Dict[str, np.ndarray]:
        """Every array by its name in ``trajectory.npz`` (``lambda``, not ``lambda_``)."""
        return dict(self._arrays)

    def save(self, out_dir: PathLike, plots: bool = True) -> Path:
        """Write the files ``slither run`` writes (summary.json, final.csv, trajectory.npz and,
        unless ``plots=False``, the figures, vtk/, the ground tracks and, unless the problem
        says ``[output] movie = false``, movie.gif) into ``out_dir``, through the same run
        pipeline as the CLI; returns its path. A loaded result copies the files it was loaded
        from."""
        out = Path(out_dir)
        if self._native is not None:
            self._native.save(str(out), plots)
        elif self._source is not None:
            out.mkdir(parents=True, exist_ok=True)
            for name in ["summary.json", "final.csv", "trajectory.npz"]:
                shutil.copy2(self._source / name, out / name)
            if plots:
                for f in self._source.glob("*.png"):
                    shutil.copy2(f, out / f.name)
                if (self._source / "vtk").is_dir():
                    shutil.copytree(self._source / "vtk", out / "vtk", dirs_exist_ok=True)
        return out

    def __repr__(self) -> str:
        s = self.summary
        return (f"Result({s.get('problem')!r}: {s.get('status')}, t = {s.get('t_final')} s, "
                f"v_s = {s.get('v_s')} m/s, regime {self.regime})")


def run(problem: Union[Problem, PathLike], accuracy: Optional[float] = None,
        progress: Union[bool, Callable[[float], Any]] = True, force: bool = False) -> Result:
    """Simulate ``problem`` as ``slither run`` does and return the :class:`Result`.

    ``problem`` is a :class:`Problem` or a problem file's path. ``accuracy`` is ``--accuracy``
    (the cheapest model whose estimated relative error of v_s/v_m is below it). ``progress``:
    True prints the fraction done on ``sys.stderr`` (after the first second), False prints
    nothing, a callable gets the fraction in [0, 1] now and then. ``force`` runs above the
    size limits, as ``--force``. The GIL is released while simulating; Ctrl-C raises
    ``KeyboardInterrupt``. A run stopped by a failed step raises :class:`SimulationError`
    carrying the partial result.
    """
    if not isinstance(problem, Problem):
        problem = load_problem(os.fspath(problem))
    show: Any = None
    if callable(progress):
        show = progress
    elif progress:
        show = True
    native = _native.run(problem, accuracy, show, force)
    result = Result(json.loads(native.summary_json()), dict(native.arrays()), native=native)
    err = native.error()
    if err is not None:
        raise SimulationError(err, result)
    return result


def load(out_dir: PathLike) -> Result:
    """Read a run's outputs (``summary.json`` and ``trajectory.npz`` written by ``slither run``
    or :meth:`Result.save`) back into a :class:`Result`."""
    d = Path(out_dir)
    with open(d / "summary.json", encoding="utf-8") as f:
        summary = json.load(f)
    with np.load(d / "trajectory.npz") as npz:
        arrays = {k: npz[k] for k in npz.files}
    return Result(summary, arrays, source=d)


def _read_csv(path: Path) -> Dict[str, Any]:
    """A CSV file as columns: numbers as float arrays, other columns as lists of strings."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
    cols: Dict[str, Any] = {}
    for i, name in enumerate(header):
        values = [r[i] for r in body]
        try:
            cols[name] = np.array([float(v) for v in values])
        except ValueError:
            cols[name] = values
    return cols


def _read_json(path: Path) -> Optional[Any]:
    if not path.exists():
        return None
    with open(path, encoding="utf-8") as f:
        return json.load(f)


class Optimization:
    """A gait study's outputs: ``optimum`` (optimum.json), ``history`` (history.csv as
    columns), ``accuracy`` (accuracy.json, when the study has ``[accuracy]``), ``counts`` (what
    this call simulated, reused and found) and ``out_dir``."""

    def __init__(self, out_dir: PathLike, counts: Optional[Dict[str, Any]] = None):
        self.out_dir = Path(out_dir)
        self.counts = counts or {}
        self.optimum = _read_json(self.out_dir / "optimum.json")
        self.history = _read_csv(self.out_dir / "history.csv")
        self.accuracy = _read_json(self.out_dir / "accuracy.json")

    def __repr__(self) -> str:
        return f"Optimization({str(self.out_dir)!r}, {self.counts})"


def optimize(study: PathLike, out: PathLike = "out_optimize", progress: bool = True) -> Optimization:
    """Run a gait study file as ``slither optimize --out out`` (rerunning with the same ``out``
    reuses history.csv) and return its outputs. Ctrl-C stops it between evaluations."""
    counts = _native.optimize(os.fspath(study), os.fspath(out), progress)
    return Optimization(out, counts)


class PhaseDiagram:
    """A phase sweep's outputs: ``cells`` (phase.csv as columns), ``info`` (phase.json),
    ``boundaries`` (boundaries.json), ``refine`` (refine.csv, with ``refine = true``),
    ``counts`` and ``out_dir``."""

    def __init__(self, out_dir: PathLike, counts: Optional[Dict[str, Any]] = None):
        self.out_dir = Path(out_dir)
        self.counts = counts or {}
        self.cells = _read_csv(self.out_dir / "phase.csv")
        self.info = _read_json(self.out_dir / "phase.json")
        self.boundaries = _read_json(self.out_dir / "boundaries.json")
        refine = self.out_dir / "refine.csv"
        self.refine = _read_csv(refine) if refine.exists() else None

    def __repr__(self) -> str:
        return f"PhaseDiagram({str(self.out_dir)!r}, {self.counts})"


def phase(study: PathLike, shard: Optional[str] = None, out: PathLike = "out_phase",
          progress: bool = True) -> PhaseDiagram:
    """Run a phase file as ``slither phase --out out [--shard I/N]`` and return its outputs.
    The sweep runs its cells in parallel and is not interrupted by Ctrl-C before it ends;
    rerunning with the same ``out`` reuses the finished cells."""
    counts = _native.phase(os.fspath(study), os.fspath(out), shard, progress)
    return PhaseDiagram(out, counts)


def topology(curve: Any, closed: bool = False) -> Dict[str, float]:
    """Twist ``tw``, writhe ``wr`` and link ``lk`` (turns) of a framed curve, as
    ``slither topology``: a CSV file (x,y,z,d1x,d1y,d1z) or a pair ``(x, d1)`` of (N, 3)
    arrays. ``closed=True`` adds the Gauss linking integral ``lk_gauss``."""
    if isinstance(curve, (str, os.PathLike)):
        curve = os.fspath(curve)
    else:
        x, d1 = curve
        curve = (np.asarray(x, dtype=float).tolist(), np.asarray(d1, dtype=float).tolist())
    return dict(_native.topology(curve, closed))
