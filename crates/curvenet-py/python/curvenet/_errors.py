"""The exceptions curvenet raises."""

from __future__ import annotations

from typing import Optional

__all__ = ["CurvenetError", "InputError"]


class CurvenetError(RuntimeError):
    """A computation failed (an eigen solve that did not converge, a run folder that could
    not be written, ...). The message is the command line's."""


class InputError(ValueError):
    """Bad input: a malformed file, a bad parameter, a run folder that does not read.

    The message is the command line's (``file:line: message`` for a file); ``file`` and
    ``line`` name the place when there is one (``line`` is ``None`` for a whole-file problem;
    for a ``.3dm`` file it is the object's 1-based position in the file).
    """

    def __init__(self, message: str, file: Optional[str] = None, line: Optional[int] = None):
        super().__init__(message)
        self.file = file
        self.line = line


CurvenetError.__module__ = "curvenet"
InputError.__module__ = "curvenet"
