"""Shared fixtures: the repository, the command line to compare with, small sketches."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]


def cli_path() -> Path:
    """The `curvenet` binary the Python results are compared with: $CURVENET_CLI, or the
    workspace's release build (built by `cargo build --release -p curvenet-cli`)."""
    env = os.environ.get("CURVENET_CLI")
    p = Path(env) if env else REPO / "target" / "release" / "curvenet"
    if not p.is_file():
        pytest.fail(f"{p}: no curvenet binary; build it (cargo build --release -p curvenet-cli) "
                    "or set CURVENET_CLI")
    return p


@pytest.fixture(scope="session")
def cli():
    exe = cli_path()

    def run(*args, check=True):
        return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                              check=check, cwd=REPO)

    return run


def grid_curves(n: int = 4, points: int = 9) -> list:
    """`n` curves along x and `n` along y over a shallow dome, crossing at shared points."""
    s = np.linspace(-1.0, 1.0, points)
    offsets = np.linspace(-0.75, 0.75, n)
    out = []
    for o in offsets:
        for axis in (0, 1):
            xy = np.zeros((points, 2))
            xy[:, axis] = s
            xy[:, 1 - axis] = o
            z = 0.4 * (1.0 - 0.5 * (xy[:, 0] ** 2 + xy[:, 1] ** 2))
            out.append(np.column_stack([xy, z]))
    return out


@pytest.fixture
def grid():
    return grid_curves()
