"""The command line and Python are two front ends of one engine: for the same inputs and
options they write the same result.json (apart from the paths of the inputs and the run
folder) and analyse to the same numbers."""

import json

import numpy as np
import pytest

import curvenet


@pytest.fixture(scope="module")
def dome(cli, tmp_path_factory):
    """Ten random geodesics on the built-in dome (extent 4000) and the dome as an OBJ file."""
    d = tmp_path_factory.mktemp("dome")
    cli("trace", "--mesh", "dome", "--geodesics", "10", "--seed", "3",
        "--out", d / "curves.json", "--mesh-out", d / "dome.obj")
    return d


@pytest.fixture(scope="module")
def wave(cli, tmp_path_factory):
    """Another random network: nine geodesics on the built-in wave."""
    d = tmp_path_factory.mktemp("wave")
    cli("trace", "--mesh", "wave", "--geodesics", "9", "--seed", "5",
        "--out", d / "curves.json", "--mesh-out", d / "wave.obj")
    return d


def _comparable(result: dict) -> dict:
    """result.json without what names paths (the inputs' and the run folder's)."""
    r = json.loads(json.dumps(result))
    inp = r["setup"]["input"]
    inp.pop("curve_files", None)
    inp.pop("mesh", None)
    # Groups given as lists are named by their position, a groups file's by the file: their
    # curves are what must agree.
    for g in r["setup"].get("constraints", {}).get("groups", []):
        g.pop("name", None)
        g.pop("origin", None)
    return r


def _read_faces(obj):
    faces, vertices = [], []
    for line in open(obj):
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.array(vertices), np.array(faces)


# (name, the command line's options, load()'s keyword arguments, simplify()'s)
BASE = ["--budget", "0.4"]
CASES = [
    ("default edge length", [], {}, {}),
    ("edge length", ["--edge-length", "150"], {"edge_length": 150}, {}),
    ("budget length", ["--budget-length", "9000"], {}, {"budget": None, "budget_length": 9000}),
    ("keep", ["--keep", "0,3"], {}, {"keep": [0, 3]}),
    ("pinned", ["--supports", "pinned"], {"supports": "pinned"}, {}),
    ("connected", ["--connected"], {}, {"connected": True}),
    ("min curves", ["--min-curves", "3"], {}, {"min_curves": 3}),
    ("max gap", ["--max-gap", "1600"], {}, {"max_gap": 1600}),
    ("max deviation", ["--max-deviation", "50"], {}, {"max_deviation": 50}),
    ("symmetry", ["--symmetry", "auto"], {}, {"symmetry": "auto"}),
    ("groups", ["--groups", "{groups}"], {}, {"groups": "{groups}"}),
    ("group lists", ["--groups", "{groups}"], {}, {"groups": [[1, 2], [4, 7]]}),
    ("local search", ["--local-search"], {}, {"local_search": True}),
    ("alternatives", ["--alternatives", "2"], {}, {"alternatives": 2}),
    ("certificate", ["--certify", "--certificate-nodes", "5"], {},
     {"certify": True, "certificate_nodes": 5}),
    ("frequency", ["--objective", "frequency"], {"objective": "frequency"}, {}),
    ("physical", ["--units", "mm", "--material", "steel", "--radius", "20"],
     {"units": "mm", "material": "steel", "radius": 20}, {}),
    ("physical frequency", ["--units", "mm", "--material", "aluminium", "--objective",
                            "frequency", "--max-deviation", "5", "--local-search"],
     {"units": "mm", "material": "aluminium", "objective": "frequency"},
     {"max_deviation": 5, "local_search": True}),
    ("mesh int32", [], {"mesh": "int32"}, {}),
    ("mesh uint32", [], {"mesh": "uint32"}, {}),
    ("mesh int64", ["--connected"], {"mesh": "int64"}, {"connected": True}),
    ("built-in mesh", ["--mesh", "dome"], {"mesh": "dome"}, {}),
]


@pytest.mark.parametrize("name,args,load_kw,run_kw", CASES, ids=[c[0] for c in CASES])
def test_a_run_gives_the_command_lines_result(cli, dome, tmp_path, name, args, load_kw, run_kw):
    groups = tmp_path / "groups.txt"
    groups.write_text("a: 1 2\nb: 4 7\n")
    fill = lambda v: str(groups) if v == "{groups}" else v  # noqa: E731
    args = [fill(a) for a in args]
    run_kw = {k: fill(v) for k, v in run_kw.items()}
    curves, obj = dome / "curves.json", dome / "dome.obj"
    mesh_args = [] if "--mesh" in args else ["--mesh", obj]
    budget = [] if "--budget-length" in args else BASE
    cli("simplify", "--curves", curves, *mesh_args, *budget, *args, "--out", tmp_path / "cli")

    load_kw = dict(load_kw)
    mesh = load_kw.pop("mesh", obj)
    if mesh in ("int32", "uint32", "int64"):
        v, f = _read_faces(obj)
        mesh = (v, f.astype(mesh))
    net = curvenet.load([curves], mesh=mesh, **load_kw)
    run_kw = {"budget": 0.4, **run_kw}
    got = net.simplify(out=tmp_path / "py", pictures=False, **run_kw)
    expected = curvenet.open_run(tmp_path / "cli")
    assert _comparable(got.result) == _comparable(expected.result)
    if expected.answer is None:
        assert got.answer is None
    else:
        assert got.answer.curves == expected.answer.curves
        assert got.answer.lambda_eq == expected.answer.lambda_eq


def test_a_second_random_network_and_a_paper_example(cli, wave, tmp_path):
    cli("simplify", "--curves", wave / "curves.json", "--mesh", wave / "wave.obj",
        "--budget", "0.35", "--local-search", "--out", tmp_path / "cli-wave")
    got = curvenet.load([wave / "curves.json"], mesh=wave / "wave.obj").simplify(
        0.35, local_search=True, out=tmp_path / "py-wave", pictures=False)
    assert _comparable(got.result) == _comparable(curvenet.open_run(tmp_path / "cli-wave").result)

    cli("example", "tower", "--out", tmp_path / "cli-tower")
    got = curvenet.example("tower").simplify(out=tmp_path / "py-tower", pictures=False)
    expected = curvenet.open_run(tmp_path / "cli-tower")
    assert _comparable(got.result) == _comparable(expected.result)
    # The example's own scale is recorded, so the command line resumes Python's folder.
    assert got.result["setup"]["input"]["scale"] == 10.0
    again = cli("example", "tower", "--out", tmp_path / "py-tower", "--resume")
    assert "already complete" in again.stderr


@pytest.mark.parametrize("options,kw", [
    ([], {}),
    (["--remove", "2,5"], {"remove": [2, 5]}),
    (["--objective", "frequency"], {"objective": "frequency"}),
    (["--units", "mm", "--material", "steel", "--radius", "20"],
     {"units": "mm", "material": "steel", "radius": 20}),
    (["--units", "mm", "--material", "steel", "--radius", "20", "--loads", "LOADS",
      "--deflection-limit", "span/300"],
     {"units": "mm", "material": "steel", "radius": 20, "loads": "LOADS",
      "deflection_limit": "span/300"}),
    (["--units", "mm", "--material", "steel", "--radius", "20", "--supports-file", "SUPPORTS"],
     {"units": "mm", "material": "steel", "radius": 20, "supports_file": "SUPPORTS"}),
], ids=["plain", "remove", "frequency", "physical", "load cases", "supports per end"])
def test_analyze_agrees_number_for_number(cli, dome, tmp_path, options, kw):
    loads = tmp_path / "loads.json"
    loads.write_text(json.dumps({
        "cases": [{"name": "G", "self_weight": True},
                  {"name": "S", "line": {"intensity": "2kN/m", "direction": [0, 0, -1],
                                         "per": "projected"}}],
        "combinations": [{"name": "ULS", "factors": {"G": 1.35, "S": 1.5}}]}))
    supports = tmp_path / "supports.json"
    supports.write_text(json.dumps({
        "format": "curvenet-supports", "version": 1,
        "supports": [{"curve": 0, "end": "start", "support": "free"},
                     {"curve": 1, "end": "end", "support": {"fixed": "z"}}]}))
    files = {"LOADS": loads, "SUPPORTS": supports}
    options = [str(files[o]) if o in files else o for o in options]
    kw = {k: (files[v] if isinstance(v, str) and v in files else v) for k, v in kw.items()}
    out = cli("analyze", "--curves", dome / "curves.json", "--mesh", dome / "dome.obj",
              *options, "--json")
    expected = json.loads(out.stdout)
    kw = dict(kw)
    remove = kw.pop("remove", [])
    got = curvenet.load([dome / "curves.json"], mesh=dome / "dome.obj", **kw).analyze(remove)
    expected.pop("warnings")
    report = dict(got.report)
    report.pop("warnings")
    assert report == expected
    if "units" in kw:
        assert got.physical is not None
        assert got.physical.first_frequency_hz == expected["physical"]["first_frequency_hz"]
        if "loads" in kw:
            assert [c["name"] for c in expected["physical"]["load_cases"]] == ["G", "S", "ULS"]
    else:
        assert got.physical is None


def _comparable_slide(result: dict) -> dict:
    """A slid run's result.json without what names paths (its `slide` record's `from`)."""
    r = _comparable(result)
    r["slide"].pop("from", None)
    return r


def test_a_slide_gives_the_command_lines_numbers(cli, dome, tmp_path):
    """The same slide (and a round of local search and slide after it) from the command line
    and from Python: the same records, number for number."""
    curves, obj = dome / "curves.json", dome / "dome.obj"
    cli("simplify", "--curves", curves, "--mesh", obj, *BASE, "--slide", "--max-move", "4%",
        "--slide-rounds", "1", "--out", tmp_path / "cli")
    net = curvenet.load([curves], mesh=obj)
    got = net.simplify(0.4, out=tmp_path / "py", pictures=False, slide=True, max_move="4%",
                       slide_rounds=1)
    expected = curvenet.open_run(tmp_path / "cli")
    assert got.slide is not None and expected.slide is not None
    assert _comparable_slide(got.slide.run.result) == _comparable_slide(expected.slide.run.result)
    assert len(got.slide.rounds) == 1
    for side in (tmp_path / "cli", tmp_path / "py"):
        assert (side / "slide" / "rounds" / "1" / "slid" / "result.json").is_file()
    a = curvenet.open_run(tmp_path / "cli" / "slide" / "rounds" / "1" / "slid")
    b = curvenet.open_run(tmp_path / "py" / "slide" / "rounds" / "1" / "slid")
    assert _comparable_slide(a.result) == _comparable_slide(b.result)
    # The answer is the best slide of every round, on both sides the same one.
    s = got.slide
    start, slid = s.rounds[0].start, s.rounds[0].slid
    assert s.answer_round == expected.slide.answer_round
    assert s.answer_round == (1 if slid > start + 1e-6 * abs(start) else 0)
    assert s.lambda_after == (slid if s.answer_round == 1 else start)
    assert s.answer.lambda_eq == expected.slide.answer.lambda_eq
    if s.answer_round == 1:
        for side in (tmp_path / "cli", tmp_path / "py"):
            assert (side / "slide" / "rounds" / "0" / "slid" / "result.json").is_file()
    # `curvenet slide` and `curvenet.slide` on the runs they made: the same slid numbers.
    cli("slide", tmp_path / "cli", "--out", tmp_path / "cli-again", "--pin", "0")
    again = curvenet.slide(got, tmp_path / "py-again", pin=[0])
    expected = curvenet.open_run(tmp_path / "cli-again")
    assert _comparable_slide(again.result) == _comparable_slide(expected.result)
    assert again.slide.lambda_after == expected.slide.lambda_after
