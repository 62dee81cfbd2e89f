"""Bad input raises curvenet.InputError with the command line's message, file and line."""

import pytest

import curvenet


def test_a_bad_number_names_the_file_and_line(cli, tmp_path):
    f = tmp_path / "bad.txt"
    f.write_text("CURVE 2\n0 0 0\n1 zero 0\n")
    with pytest.raises(curvenet.InputError) as e:
        curvenet.load(curves=[f])
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(f) and e.value.line == 3
    cli_err = cli("analyze", "--curves", f, check=False)
    assert cli_err.returncode == 2
    assert str(e.value) in cli_err.stderr


def test_a_missing_file_and_bad_parameters(grid, tmp_path):
    with pytest.raises(curvenet.InputError) as e:
        curvenet.load(curves=[tmp_path / "missing.obj"])
    assert e.value.file == str(tmp_path / "missing.obj")
    with pytest.raises(curvenet.InputError, match="scale"):
        curvenet.load(grid, scale=-1.0)
    with pytest.raises(curvenet.InputError, match="supports"):
        curvenet.load(grid, supports="glued")
    with pytest.raises(curvenet.InputError, match="expected an \\(n, 3\\) array"):
        curvenet.load([[0.0, 1.0], [2.0, 3.0]])
    net = curvenet.load(grid)
    with pytest.raises(curvenet.InputError, match="remove names curve 99"):
        net.analyze(remove=[99])
    with pytest.raises(curvenet.InputError, match="budget"):
        net.simplify(1.5)
    with pytest.raises(curvenet.InputError, match="keep names curve 50"):
        net.simplify(0.5, keep=[50])
    with pytest.raises(curvenet.InputError, match="unknown example"):
        curvenet.example("cathedral")
    with pytest.raises(curvenet.InputError, match="not a folder"):
        curvenet.open_run(tmp_path / "no-run")
    with pytest.raises(curvenet.InputError, match="result.json"):
        curvenet.open_run(tmp_path)


def test_a_bad_array_curve_names_its_position():
    import numpy as np

    good = np.array([[0.0, 0, 0], [1, 0, 0]])
    bad = np.array([[0.0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(curvenet.InputError) as e:
        curvenet.load([good, bad])
    assert e.value.file == "<arrays>" and e.value.line == 2
    assert "curve 1" in str(e.value)


def test_counts_and_indices_are_whole_numbers_and_negative_iterations_count_from_the_end(
        grid, tmp_path):
    net = curvenet.load(grid)
    for bad in (-1, 2.5, True):
        with pytest.raises(curvenet.InputError, match="alternatives"):
            net.simplify(0.5, out=tmp_path / "a", alternatives=bad)
        with pytest.raises(curvenet.InputError, match="slide_rounds"):
            net.simplify(0.5, out=tmp_path / "a", slide_rounds=bad)
        with pytest.raises(curvenet.InputError, match="eigen_count"):
            curvenet.load(grid, eigen_count=bad)
    with pytest.raises(curvenet.InputError, match="min_curves"):
        net.simplify(0.5, out=tmp_path / "a", min_curves=-2)
    run = net.simplify(0.5, out=tmp_path / "run", pictures=False)
    last = len(run.iterations) - 1
    assert (run.displacement(-1) == run.displacement(last)).all()
    assert (run.mode(-len(run.iterations)) == run.mode(0)).all()
    for bad, what in ((last + 1, "no iteration"), (-last - 2, "iteration is"),
                      (1.5, "whole number")):
        with pytest.raises(curvenet.InputError, match=what):
            run.displacement(bad)
    with pytest.raises(curvenet.InputError, match="curve ids are 0 or more"):
        run.polylines([-1])
    pytest.importorskip("rhino3dm")
    with pytest.raises(curvenet.InputError, match="no iteration"):
        run.write_3dm(tmp_path / "past.3dm", iteration=last + 1)
    run.write_3dm(tmp_path / "last.3dm", iteration=-1)
    assert (tmp_path / "last.3dm").stat().st_size > 0


# Each keyword argument given a value of the wrong type, and the name the error must carry.
WRONG_TYPES = [
    ("load", dict(scale="2"), "scale"),
    ("load", dict(edge_length=[0.1]), "edge_length"),
    ("load", dict(radius="2"), "radius"),
    ("load", dict(merge_joints=True), "merge_joints"),
    ("load", dict(anchor_weight="heavy"), "anchor_weight"),
    ("load", dict(supports=1), "supports"),
    ("load", dict(objective=0), "objective"),
    ("load", dict(units=1000), "units"),
    ("load", dict(material=1), "material"),
    ("load", dict(loads=3), "loads"),
    ("load", dict(supports_file=3), "supports_file"),
    ("load", dict(tolerance="fine"), "tolerance"),
    ("load", dict(layer=2), "layer"),
    ("simplify", dict(budget="half"), "budget"),
    ("simplify", dict(budget=True), "budget"),
    ("simplify", dict(budget_length="12m"), "budget_length"),
    ("simplify", dict(max_gap="wide"), "max_gap"),
    ("simplify", dict(max_deviation=[1]), "max_deviation"),
    ("simplify", dict(symmetry=4), "symmetry"),
    ("simplify", dict(connected="no"), "connected"),
    ("simplify", dict(local_search=1), "local_search"),
    ("simplify", dict(certify="yes"), "certify"),
    ("simplify", dict(pictures="no"), "pictures"),
    ("simplify", dict(resume=0), "resume"),
    ("simplify", dict(force="yes"), "force"),
    ("simplify", dict(slide="yes"), "slide"),
    ("simplify", dict(fixed_ends=1), "fixed_ends"),
    ("simplify", dict(out=5), "out"),
    ("simplify", dict(groups=5), "groups"),
    ("simplify", dict(progress="print"), "progress"),
]


@pytest.mark.parametrize("call,kwargs,option", WRONG_TYPES,
                         ids=[f"{c}-{o}-{list(k.values())[0]!r}" for c, k, o in WRONG_TYPES])
def test_an_argument_of_the_wrong_type_is_an_input_error_naming_it(grid, tmp_path, call, kwargs,
                                                                    option):
    with pytest.raises(curvenet.InputError, match=f"^{option}: expected"):
        if call == "load":
            curvenet.load(grid, **kwargs)
        else:
            curvenet.load(grid).simplify(**{"budget": 0.5, "out": tmp_path / "run", **kwargs})
    # Nothing was written.
    assert not (tmp_path / "run").exists()


def test_the_other_calls_name_a_wrong_argument_too(grid, tmp_path):
    with pytest.raises(curvenet.InputError, match="^curves: expected"):
        curvenet.load(123)
    with pytest.raises(curvenet.InputError, match="^curve 1: expected a curve file"):
        curvenet.load([grid[0], {"x": 1}])
    with pytest.raises(curvenet.InputError, match="^name: expected text"):
        curvenet.example(3)
    with pytest.raises(curvenet.InputError, match="^data: expected a file or folder path"):
        curvenet.example("roof", data=1)
    with pytest.raises(curvenet.InputError, match="^folder: expected a file or folder path"):
        curvenet.open_run(5)
    with pytest.raises(curvenet.InputError, match="^run: expected a file or folder path"):
        curvenet.slide(5)
    run = curvenet.load(grid).simplify(0.5, out=tmp_path / "run", pictures=False)
    with pytest.raises(curvenet.InputError, match="^out: expected"):
        curvenet.slide(run, out=7)
    with pytest.raises(curvenet.InputError, match="^force: expected True or False"):
        curvenet.slide(run, force="yes")
    with pytest.raises(curvenet.InputError, match="^state: expected text"):
        run.polylines([0], state=1)
    with pytest.raises(curvenet.InputError, match="^format: expected text"):
        run.export(tmp_path / "e", format=1)
    with pytest.raises(curvenet.InputError, match="^out: expected"):
        run.export(out=1)
    with pytest.raises(curvenet.InputError, match="^path: expected"):
        run.write_3dm(1)
    with pytest.raises(curvenet.InputError, match="^mode_scale: expected a number"):
        run.write_3dm(tmp_path / "r.3dm", mode_scale="big")


def test_a_wrong_argument_leaves_no_temporary_folder(grid, tmp_path, monkeypatch):
    import tempfile

    temp = tmp_path / "temp"
    temp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    net = curvenet.load(grid)
    with pytest.raises(curvenet.InputError, match="^budget: expected a number"):
        net.simplify("half")
    with pytest.raises(curvenet.InputError, match="^pictures: expected True or False"):
        net.simplify(0.5, pictures="yes")
    run = net.simplify(0.5, out=tmp_path / "run", pictures=False)
    with pytest.raises(curvenet.InputError, match="^fixed_ends: expected True or False"):
        curvenet.slide(run, fixed_ends="no")
    with pytest.raises(curvenet.InputError, match="^pictures: expected True or False"):
        curvenet.slide(run, pictures=1)
    assert list(temp.iterdir()) == []
