"""curvenet: stability-aware simplification of curve networks, from Python.

>>> import curvenet
>>> net = curvenet.example("roof")
>>> net.analyze().lambda_eq            # λ_eq of the whole network
>>> result = net.simplify()            # the greedy, to the example's budget
>>> result.answer.curves, result.lambdas

See ``docs/python.md`` in the repository for a walk-through.
"""

from ._core import (
    Analysis,
    Answer,
    Record,
    Iteration,
    Network,
    Result,
    Slide,
    example,
    example_names,
    load,
    open_run,
    slide,
)
from ._errors import CurvenetError, InputError
from ._native import __version__

__all__ = [
    "Analysis",
    "Answer",
    "Record",
    "CurvenetError",
    "InputError",
    "Iteration",
    "Network",
    "Result",
    "Slide",
    "__version__",
    "example",
    "example_names",
    "load",
    "open_run",
    "slide",
]
