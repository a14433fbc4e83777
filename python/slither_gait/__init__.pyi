"""Type stubs of slither_gait (see the module docstring of slither_gait/__init__.py)."""
import os
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Union

import numpy as np
from numpy.typing import NDArray

from ._native import Problem as Problem, load_problem as load_problem

PathLike = Union[str, os.PathLike[str]]
ARRAYS: Dict[str, tuple]

class SimulationError(RuntimeError):
    result: "Result"
    def __init__(self, message: str, result: "Result") -> None: ...

class Result:
    summary: Dict[str, Any]
    t: NDArray[np.float64]
    s: NDArray[np.float64]
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    theta: NDArray[np.float64]
    normal_force: NDArray[np.float64]
    slip_velocity: NDArray[np.float64]
    elevation: NDArray[np.float64]
    slip_speed: NDArray[np.float64]
    lambda_: NDArray[np.float64]
    @property
    def regime(self) -> Optional[str]: ...
    @property
    def arrays(self) -> Dict[str, NDArray[np.float64]]: ...
    def save(self, out_dir: PathLike, plots: bool = True) -> Path: ...

def run(problem: Union[Problem, PathLike], accuracy: Optional[float] = None,
        progress: Union[bool, Callable[[float], Any]] = True, force: bool = False) -> Result: ...
def load(out_dir: PathLike) -> Result: ...

class Optimization:
    out_dir: Path
    counts: Dict[str, Any]
    optimum: Optional[Dict[str, Any]]
    history: Dict[str, Any]
    accuracy: Optional[Dict[str, Any]]
    def __init__(self, out_dir: PathLike, counts: Optional[Dict[str, Any]] = None) -> None: ...

def optimize(study: PathLike, out: PathLike = "out_optimize", progress: bool = True) -> Optimization: ...

class PhaseDiagram:
    out_dir: Path
    counts: Dict[str, Any]
    cells: Dict[str, Any]
    info: Optional[Dict[str, Any]]
    boundaries: Optional[Any]
    refine: Optional[Dict[str, Any]]
    def __init__(self, out_dir: PathLike, counts: Optional[Dict[str, Any]] = None) -> None: ...

def phase(study: PathLike, shard: Optional[str] = None, out: PathLike = "out_phase",
          progress: bool = True) -> PhaseDiagram: ...
def topology(curve: Any, closed: bool = False) -> Dict[str, float]: ...
