"""Beyond one machine: a study of many designs on a Dask cluster (here a local cluster of two
worker processes), each task one run, the results gathered into a table; and the package's
calls side by side in threads of one process."""

import threading

import pytest

import curvenet

distributed = pytest.importorskip("distributed")


def one_design(curves: str, mesh: str, budget: float, material: str, connected: bool) -> dict:
    """One run of the sweep (what a worker does): a row of the table."""
    net = curvenet.load([curves], mesh=mesh, units="mm", material=material, radius=20)
    result = net.simplify(budget, connected=connected, pictures=False)
    a = result.answer
    return {
        "budget": budget,
        "material": material,
        "connected": connected,
        "curves": None if a is None else len(a.curves),
        "lambda_eq": None if a is None else a.lambda_eq,
        "length": None if a is None else a["length"],
    }


@pytest.fixture(scope="module")
def sketch(cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep")
    cli("trace", "--mesh", "dome", "--geodesics", "8", "--seed", "2",
        "--out", d / "curves.json", "--mesh-out", d / "dome.obj")
    return str(d / "curves.json"), str(d / "dome.obj")


def test_a_sweep_on_a_local_dask_cluster_gives_the_runs_of_one_process(sketch):
    curves, mesh = sketch
    grid = [(b, m, c) for b in (0.3, 0.5) for m in ("steel", "timber") for c in (False, True)]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        futures = [client.submit(one_design, curves, mesh, b, m, c, pure=False)
                   for b, m, c in grid]
        table = client.gather(futures)
    assert len(table) == len(grid)
    # The same runs in this process give the same rows: a run does not depend on where it runs.
    for (b, m, c), row in zip(grid, table):
        assert row == one_design(curves, mesh, b, m, c)


def test_calls_release_the_gil_and_run_side_by_side(sketch):
    curves, mesh = sketch
    net = curvenet.load([curves], mesh=mesh)
    alone = [net.simplify(b, pictures=False).answer.lambda_eq for b in (0.3, 0.5)]
    got = {}

    def run(b):
        got[b] = net.simplify(b, pictures=False).answer.lambda_eq

    threads = [threading.Thread(target=run, args=(b,)) for b in (0.3, 0.5)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [got[0.3], got[0.5]] == alone
