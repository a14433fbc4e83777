"""Type stubs of the native extension (PyO3). Use the wrappers in ``slither_gait``."""
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

CHECK_EVERY_S: float

class Problem:
    """A validated problem (the contents of a problem file)."""

    @staticmethod
    def from_dict(data: Dict[str, Any], name: str = "<dict>") -> "Problem":
        """A problem from nested dicts shaped like the file's tables; raises ValueError with
        the CLI's message for a bad key or value."""
    @staticmethod
    def from_toml(text: str, name: str = "<string>") -> "Problem":
        """A problem from TOML text."""
    def to_toml(self) -> str:
        """The TOML text (the file's own text when loaded from a file)."""
    def to_dict(self) -> Dict[str, Any]:
        """The tables and keys written in the text, as nested dicts."""
    @property
    def path(self) -> str:
        """The file (or name) it came from."""
    def with_(self, overrides: Optional[Dict[str, Any]] = None, **kwargs: Any) -> "Problem":
        """A validated copy with keys changed: dotted keys (``{"gait.speed": 0.3}``) or
        tables as dicts (``gait={"speed": 0.3}``)."""

def load_problem(path: str) -> Problem:
    """Read and validate a problem file; ValueError (bad content) or OSError (unreadable)."""

class NativeRun:
    def summary_json(self) -> str: ...
    def error(self) -> Optional[str]: ...
    def arrays(self) -> Dict[str, Any]: ...
    def save(self, out_dir: str, plots: bool = True) -> None: ...

def run(problem: Problem, accuracy: Optional[float] = None,
        progress: Union[None, bool, Callable[[float], Any]] = None,
        force: bool = False) -> NativeRun: ...
def optimize(study: str, out: str, progress: bool = True) -> Dict[str, Any]: ...
def phase(file: str, out: str, shard: Optional[str] = None,
          progress: bool = True) -> Dict[str, Any]: ...
def topology(curve: Union[str, Tuple[List[List[float]], List[List[float]]]],
             closed: bool = False) -> Dict[str, float]: ...
