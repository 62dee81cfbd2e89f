"""Rhino .3dm files in and out, through rhino3dm."""

import numpy as np
import pytest

import curvenet
from curvenet import rhino

rhino3dm = pytest.importorskip("rhino3dm")


def sketch(path, curves, nurbs=True, mesh=True):
    """A .3dm with `curves` as polylines, plus one NURBS curve across them and a mesh."""
    doc = rhino3dm.File3dm()
    for c in curves:
        doc.Objects.AddCurve(rhino3dm.PolylineCurve([rhino3dm.Point3d(*map(float, p)) for p in c]))
    if nurbs:
        pts = [rhino3dm.Point3d(-1.0, -1.0, 0.2), rhino3dm.Point3d(-0.3, -0.2, 0.5),
               rhino3dm.Point3d(0.3, 0.2, 0.5), rhino3dm.Point3d(1.0, 1.0, 0.2)]
        doc.Objects.AddCurve(rhino3dm.NurbsCurve.Create(False, 3, pts))
    if mesh:
        m = rhino3dm.Mesh()
        for x, y in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            m.Vertices.Add(float(x), float(y), 0.0)
        m.Faces.AddFace(0, 1, 2, 3)
        doc.Objects.AddMesh(m)
    assert doc.Write(str(path), 8)
    return path


def test_3dm_curves_and_mesh_are_read(grid, tmp_path):
    f = sketch(tmp_path / "sketch.3dm", grid)
    net = curvenet.load(curves=[f], edge_length=0.1)
    assert net.curve_count == len(grid) + 1
    for got, want in zip(net.curves, grid):
        np.testing.assert_array_equal(got, want)
    # The NURBS curve is sampled within the tolerance of the true curve.
    doc = rhino3dm.File3dm.Read(str(f))
    curve = [o.Geometry for o in doc.Objects if isinstance(o.Geometry, rhino3dm.NurbsCurve)][0]
    pts = net.curves[-1]
    assert len(pts) > 8
    t0, t1 = curve.Domain.T0, curve.Domain.T1
    fine = np.array([[curve.PointAt(t).X, curve.PointAt(t).Y, curve.PointAt(t).Z]
                     for t in np.linspace(t0, t1, 2001)])
    # Distance of each fine point to the sampled polyline's chords.
    a, b = pts[:-1], pts[1:]
    ab = b - a
    t = np.clip(np.einsum("pk,sk->ps", fine, ab) - np.einsum("sk,sk->s", a, ab),
                0.0, None) / np.einsum("sk,sk->s", ab, ab)
    t = np.clip(t, 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    d = np.min(np.linalg.norm(fine[:, None, :] - closest, axis=2), axis=1)
    diag = np.linalg.norm(pts.max(0) - pts.min(0))
    assert d.max() <= 1.05e-3 * diag, d.max() / diag
    vertices, faces = net.mesh
    assert vertices.shape == (4, 3) and faces.shape == (2, 3)


def test_a_result_written_to_3dm_reads_back(grid, tmp_path):
    net = curvenet.load(grid, edge_length=0.1)
    r = net.simplify(0.6, out=tmp_path / "run", pictures=False)
    out = r.write_3dm(tmp_path / "result.3dm")
    doc = rhino3dm.File3dm.Read(str(out))
    by_layer = {}
    for o in doc.Objects:
        layer = doc.Layers[o.Attributes.LayerIndex].FullPath
        by_layer.setdefault(layer, []).append(int(o.Attributes.GetUserString("curvenet.curve")))
    assert by_layer["curvenet::kept"] == r.final_curves
    assert sorted(by_layer["curvenet::removed"]) == sorted(r.removed_curves)
    assert by_layer["curvenet::equilibrium"] == r.final_curves
    assert any(k.startswith("curvenet::worst-case mode") for k in by_layer)
    # The kept curves read back (by layer) are the result's designed shapes.
    kept = curvenet.load(curves=[out], layer="curvenet::kept", edge_length=0.1)
    for got, (want, closed) in zip(kept.curves, r.polylines(r.final_curves)):
        np.testing.assert_array_equal(got, want)
    eq = curvenet.load(curves=[out], layer="curvenet::equilibrium", edge_length=0.1)
    for got, (want, _) in zip(eq.curves, r.polylines(r.final_curves, "equilibrium")):
        np.testing.assert_array_equal(got, want)


def test_the_rhino_scripts_work_on_rhino_geometry(grid):
    curves = [rhino3dm.PolylineCurve([rhino3dm.Point3d(*map(float, p)) for p in c]) for c in grid]
    r = rhino.simplify_geometry(curves, None, budget=0.6, keep=[0], edge_length=0.1)
    assert 0 in r.final_curves and r.stop == "budget_met"
    layers = rhino.result_layers(r)
    assert [lay.path for lay in layers][:3] == ["curvenet::kept", "curvenet::removed",
                                                "curvenet::equilibrium"]
    assert [name for name, _, _ in layers[0].objects] == [f"curve {c}" for c in r.final_curves]


def test_a_bad_3dm_raises_input_error(tmp_path):
    f = tmp_path / "broken.3dm"
    f.write_bytes(b"not a rhino file")
    with pytest.raises(curvenet.InputError) as e:
        curvenet.load(curves=[f])
    assert e.value.file == str(f)
    empty = sketch(tmp_path / "empty.3dm", [], nurbs=False)
    with pytest.raises(curvenet.InputError, match="no curves"):
        curvenet.load(curves=[empty])
