"""The exceptions of nhc, with the words of the command line (docs/python.md, "Errors").

Error            every failure nhc reports
  SceneError     bad input: the scene (.file, .line, .column) or an argument; exit 2 on the command line
  MathError      a numerical or mathematical failure (.t when a run failed at a time); exit 3
  HostError      the environment: the compiler, the cache, the disk, memory; exit 4
"""
from typing import Any, Optional


class Error(Exception):
    """Any failure nhc reports."""


class SceneError(Error):
    """Bad input. `file`, `line`, `column` locate it (line and column 0 when unknown)."""

    def __init__(self, message: str, file: str = "", line: int = 0, column: int = 0) -> None:
        super().__init__(message)
        self.file, self.line, self.column = file, line, column


class MathError(Error):
    """A numerical or mathematical failure; `t` is the time a run stopped at, or None. Raised by
    Model.simulate, it also has `run`: the nhc.Run up to the failure; raised by Scene.optimize, the
    last point IPOPT reached."""

    run: Any  # set by Model.simulate and Scene.optimize only

    def __init__(self, message: str, t: Optional[float] = None) -> None:
        super().__init__(message)
        self.t = t


class HostError(Error):
    """The environment failed nhc: the compiler, the cache directory, the disk, memory."""
