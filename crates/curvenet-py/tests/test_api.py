"""The API on small networks: loading, analysis, the greedy, run folders, exports."""

import numpy as np
import pytest

import curvenet


def test_curves_from_arrays_and_from_a_file_make_the_same_network(grid, tmp_path):
    a = curvenet.load(grid)
    f = tmp_path / "grid.txt"
    with open(f, "w") as out:
        for c in grid:
            out.write(f"CURVE {len(c)}\n")
            for p in c:
                out.write(" ".join(repr(float(x)) for x in p) + "\n")
    b = curvenet.load(curves=[f])
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.curve_count == 8 and len(a.joints) == 16
    assert a.edges.shape[1] == 2 and len(a.edge_curves) == len(a.edges)
    np.testing.assert_allclose(a.rest_lengths.sum(), a.total_length)


def test_analysis_and_removal(grid):
    net = curvenet.load(grid, edge_length=0.1)
    full = net.analyze()
    less = net.analyze(remove=[0])
    assert full.stable and full.lambda_eq > 0
    assert less.report["removed"] == [0]
    assert less.lambda_eq < full.lambda_eq
    np.testing.assert_allclose(full.equilibrium, net.positions + full.displacement)


def test_a_greedy_run_reads_back_and_exports(grid, tmp_path):
    net = curvenet.load(grid, edge_length=0.1)
    r = net.simplify(0.6, keep=[1], out=tmp_path / "run")
    assert r.complete and r.stop == "budget_met"
    assert 1 in r.final_curves
    assert r.lengths[-1] <= r.budget
    again = curvenet.open_run(tmp_path / "run")
    assert again.removed_curves == r.removed_curves
    np.testing.assert_array_equal(again.lambdas, r.lambdas)
    assert (tmp_path / "run" / "viewer.html").is_file()
    paths = r.export(tmp_path / "export", format="obj")
    assert [p.name for p in paths] == [f"curves_{len(r.iterations) - 1:04}.obj",
                                       f"curves_{len(r.iterations) - 1:04}_rest.obj"]
    assert r.mode().shape == r.positions.shape
    assert abs(np.linalg.norm(r.mode()) - 1.0) < 1e-9


def test_an_exception_in_progress_stops_the_run(grid):
    net = curvenet.load(grid, edge_length=0.1)

    def stop(it):
        if it.iteration == 1:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        net.simplify(0.4, progress=stop)


def test_a_run_folder_is_claimed_as_the_command_line_claims_it(grid, tmp_path):
    """`out` is locked while a run writes there, a fresh run removes an earlier run's files,
    and a folder that is no run's is refused without force=True (as `curvenet simplify`)."""
    import fcntl

    net = curvenet.load(grid, edge_length=0.1)
    run = tmp_path / "run"
    net.simplify(0.6, out=run, pictures=False)
    stale = run / "iterations" / "9999.obj"
    stale.write_text("# an earlier run's\n")
    net.simplify(0.6, out=run, pictures=False)
    assert not stale.exists()
    assert (run / "result.json").is_file()

    with open(run / ".curvenet.lock", "a") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(curvenet.InputError, match="another curvenet run is writing"):
            net.simplify(0.6, out=run, pictures=False)
        fcntl.flock(held, fcntl.LOCK_UN)

    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(curvenet.InputError, match="not a curvenet run's.*force=True"):
        net.simplify(0.6, out=foreign, pictures=False)
    net.simplify(0.6, out=foreign, pictures=False, force=True)
    assert (foreign / "notes.txt").read_text() == "mine"
    assert (foreign / "result.json").is_file()
