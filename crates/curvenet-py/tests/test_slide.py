"""Sliding from Python: `simplify(slide=True)` and `curvenet.slide` record the slid run, read
back as `Result.slide`; bad values are `InputError`s naming the keyword."""

import numpy as np
import pytest

import curvenet


def bump(n=24):
    """A shallow bump over [-1, 1]², as the grid's curves lie on (their heights)."""
    s = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(s, s)
    z = 0.4 * (1.0 - 0.5 * (x ** 2 + y ** 2))
    vertices = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    at = lambda i, j: j * (n + 1) + i
    faces = [f for j in range(n) for i in range(n)
             for f in ([at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                       [at(i, j), at(i + 1, j + 1), at(i, j + 1)])]
    return vertices, np.array(faces)


def test_a_slid_run_reads_back(grid, tmp_path):
    net = curvenet.load(grid, mesh=bump(), edge_length=0.1)
    r = net.simplify(0.7, out=tmp_path / "run", pictures=False, slide=True, max_move="5%")
    s = r.slide
    assert s is not None and s.lambda_after >= s.lambda_before
    assert s.largest_move <= s.max_move
    assert s.answer is None or s.answer.source == "slide"
    again = curvenet.slide(r, tmp_path / "again", max_move=s.max_move)
    assert again.slide.lambda_after == pytest.approx(s.lambda_after, rel=1e-9)
    assert again.answer.source == "slide"


def test_bad_slides_are_input_errors(grid, tmp_path):
    net = curvenet.load(grid, edge_length=0.1)
    r = net.simplify(0.7, out=tmp_path / "run", pictures=False)
    with pytest.raises(curvenet.InputError, match="mesh"):
        curvenet.slide(r, tmp_path / "slid")
    with_mesh = curvenet.load(grid, mesh=bump(), edge_length=0.1)
    r = with_mesh.simplify(0.7, out=tmp_path / "run2", pictures=False)
    with pytest.raises(curvenet.InputError, match="max_move"):
        curvenet.slide(r, tmp_path / "slid", max_move=-1)
    with pytest.raises(curvenet.InputError, match="pin"):
        curvenet.slide(r, tmp_path / "slid", pin=[99])
