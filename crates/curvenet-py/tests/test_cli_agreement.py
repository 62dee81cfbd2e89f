"""Python gives the command line's answers: the same λ, the same greedy."""

import json

import numpy as np

import curvenet


def test_lambda_of_the_roof_is_the_command_lines(cli):
    out = cli("example", "roof", "--analyze-only", "--json")
    expected = json.loads(out.stdout)
    a = curvenet.example("roof").analyze()
    assert abs(a.lambda_eq - expected["lambda"]) <= 1e-12 * abs(expected["lambda"])
    np.testing.assert_allclose(a.eigenvalues, expected["eigenvalues"], rtol=1e-12, atol=0)
    assert a.zero_modes == expected["zero_modes"] and a.negative_modes == expected["negative_modes"]
    assert a.stable
    assert a.mode.shape == a.equilibrium.shape == (expected["vertices"], 3)


def test_the_towers_greedy_makes_the_command_lines_removals(cli, tmp_path):
    cli_out = tmp_path / "cli"
    cli("example", "tower", "--out", cli_out)
    expected = curvenet.open_run(cli_out)
    seen = []
    got = curvenet.example("tower").simplify(out=tmp_path / "py", pictures=False,
                                             progress=seen.append)
    assert got.removed_curves == expected.removed_curves
    assert got.final_curves == expected.final_curves
    np.testing.assert_array_equal(got.lambdas, expected.lambdas)
    assert got.stop == expected.stop == "budget_met"
    # Progress saw every iteration, in order.
    assert [it.iteration for it in seen] == list(range(len(got.iterations)))
    assert seen[-1].lambda_eq == got.lambdas[-1]
