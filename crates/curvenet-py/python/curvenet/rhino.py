"""Rhino files and Rhino geometry: reading sketches, writing results.

Everything here works on geometry from the ``rhino3dm`` package and, duck-typed, on
RhinoCommon geometry inside Rhino 8 (both have ``PointAt``, ``Domain``, ``IsClosed``,
``TryGetPolyline`` on curves and ``Vertices``/``Faces`` on meshes): the script in
``examples/rhino/`` is a thin shell over :func:`simplify_geometry` and :func:`result_layers`.

Curves: polylines (and lines) keep their points; any other curve (NURBS, arcs, ...) is sampled
so that no chord is farther than ``tolerance`` from the curve (by bisection, checked at each
chord's midpoint and quarter points). Meshes: quads are split into two triangles.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from . import _native
from ._errors import InputError

__all__ = [
    "Layer",
    "LAYER_ROOT",
    "mesh_arrays",
    "read_3dm",
    "result_layers",
    "sample_curve",
    "simplify_geometry",
    "write_3dm",
]

#: The parent layer of everything :func:`write_3dm` writes.
LAYER_ROOT = "curvenet"

#: Default chordal tolerance, relative to each curve's bounding-box diagonal.
RELATIVE_TOLERANCE = 1e-3

#: The most points a sampled curve gets.
MAX_POINTS = 20_000


def _xyz(p: Any) -> Tuple[float, float, float]:
    return (float(p.X), float(p.Y), float(p.Z))


def _polyline_points(curve: Any) -> Optional[List[Tuple[float, float, float]]]:
    """The points of a curve that is a polyline (rhino3dm returns the polyline or None,
    RhinoCommon a ``(success, polyline)`` pair), else None."""
    try:
        got = curve.TryGetPolyline()
    except Exception:  # noqa: BLE001 - a curve type without the method
        return None
    if isinstance(got, tuple):
        ok, poly = got[0], got[1] if len(got) > 1 else None
        if not ok:
            return None
        got = poly
    if got is None:
        return None
    return [_xyz(got[i]) for i in range(got.Count)]


def _domain(curve: Any) -> Tuple[float, float]:
    d = curve.Domain
    return float(d.T0), float(d.T1)


def _diagonal(points: np.ndarray) -> float:
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def sample_curve(curve: Any, tolerance: Optional[float] = None) -> Tuple[np.ndarray, bool]:
    """``(points (n, 3), closed)`` of a Rhino curve: a polyline's points, or samples of any
    other curve with every chord within ``tolerance`` of the curve (default:
    ``RELATIVE_TOLERANCE`` × the curve's bounding-box diagonal). A closed curve's points do
    not repeat the first."""
    closed = bool(curve.IsClosed)
    pts = _polyline_points(curve)
    if pts is not None:
        a = np.array(pts, dtype=np.float64)
    else:
        t0, t1 = _domain(curve)
        spans = 1
        try:
            spans = max(1, int(curve.SpanCount))
        except Exception:  # noqa: BLE001
            pass
        n0 = max(8, 4 * spans)
        ts = list(np.linspace(t0, t1, n0 + 1))
        at = {t: np.array(_xyz(curve.PointAt(t))) for t in ts}
        coarse = np.array([at[t] for t in ts])
        tol = tolerance if tolerance is not None else RELATIVE_TOLERANCE * _diagonal(coarse)
        if not (tol > 0 and math.isfinite(tol)):
            tol = 0.0
        out = [ts[0]]
        stack = [(ts[i], ts[i + 1], 0) for i in range(len(ts) - 2, -1, -1)]
        while stack:
            a_t, b_t, depth = stack.pop()
            pa = at.setdefault(a_t, np.array(_xyz(curve.PointAt(a_t))))
            pb = at.setdefault(b_t, np.array(_xyz(curve.PointAt(b_t))))
            worst = 0.0
            for f in (0.25, 0.5, 0.75):
                t = a_t + f * (b_t - a_t)
                p = at.setdefault(t, np.array(_xyz(curve.PointAt(t))))
                worst = max(worst, float(np.linalg.norm(p - (pa + f * (pb - pa)))))
            if tol > 0 and worst > tol and depth < 30 and len(at) < MAX_POINTS:
                m = 0.5 * (a_t + b_t)
                stack.append((m, b_t, depth + 1))
                stack.append((a_t, m, depth + 1))
            else:
                out.append(b_t)
        a = np.array([at[t] for t in out])
    if closed and len(a) > 1 and np.array_equal(a[0], a[-1]):
        a = a[:-1]
    return a, closed


def mesh_arrays(mesh: Any) -> Tuple[np.ndarray, np.ndarray]:
    """``(vertices (V, 3), faces (F, 3))`` of a Rhino mesh; quads become two triangles."""
    vs = mesh.Vertices
    vertices = np.array([_xyz(vs[i]) for i in range(len(vs))], dtype=np.float64)
    faces: List[Tuple[int, int, int]] = []
    fs = mesh.Faces
    for i in range(len(fs) if hasattr(fs, "__len__") else fs.Count):
        f = fs[i]
        if isinstance(f, tuple):
            a, b, c, d = f
        else:  # RhinoCommon MeshFace
            a, b, c, d = f.A, f.B, f.C, f.D
        faces.append((a, b, c))
        if d != c:
            faces.append((a, c, d))
    return vertices, np.array(faces, dtype=np.int64).reshape(-1, 3)


def _layer_path(doc: Any, index: int) -> str:
    try:
        return doc.Layers[index].FullPath or ""
    except Exception:  # noqa: BLE001
        return ""


def read_3dm(path: str, tolerance: Optional[float] = None, layer: Optional[str] = None,
             curves: bool = True) -> Tuple[list, Optional[tuple], List[str]]:
    """Reads a ``.3dm``: its curves as the package's curve tuples (each curve's ``line`` is
    the object's 1-based position in the file), its first mesh (or None) and warnings.
    ``layer`` keeps only objects on that layer (full path) or below it."""
    import rhino3dm

    if not os.path.isfile(path):
        raise InputError(f"{path}: cannot read the file: no such file", path, None)
    doc = rhino3dm.File3dm.Read(path)
    if doc is None:
        raise InputError(f"{path}: not a Rhino .3dm file (rhino3dm could not read it)", path, None)
    arrays, closed, labels, lines = [], [], [], []
    mesh = None
    warnings: List[str] = []
    skipped = 0
    for k, obj in enumerate(doc.Objects):
        g = obj.Geometry
        attrs = obj.Attributes
        if layer is not None:
            full = _layer_path(doc, attrs.LayerIndex)
            if full != layer and not full.startswith(layer + "::"):
                continue
        if isinstance(g, rhino3dm.Curve):
            if not curves:
                continue
            pts, c = sample_curve(g, tolerance)
            arrays.append(pts)
            closed.append(c)
            labels.append(attrs.Name or None)
            lines.append(k + 1)
        elif isinstance(g, rhino3dm.Mesh):
            if mesh is None:
                mesh = mesh_arrays(g)
            else:
                warnings.append(f"{path}:{k + 1}: warning: a second mesh; only the first is used")
        else:
            skipped += 1
    if skipped:
        warnings.append(
            f"{path}: warning: {skipped} object(s) that are neither curves nor meshes ignored"
        )
    if curves and not arrays:
        where = f" on layer '{layer}'" if layer is not None else ""
        raise InputError(f"{path}: no curves{where}", path, None)
    tuples: list = []
    if arrays:
        tuples, w = _native.curves_from_arrays(path, arrays, closed, labels, lines)
        warnings.extend(w)
    return tuples, mesh, warnings


def simplify_geometry(curves: Sequence[Any], mesh: Any = None, *, budget: float,
                      keep: Iterable[int] = (), tolerance: Optional[float] = None,
                      progress: Any = None, **load_options: Any):
    """The Rhino script's work: simplifies Rhino ``curves`` (on ``mesh``, a Rhino mesh or
    None) to ``budget`` (a fraction of their total length), keeping the curves ``keep``
    (indices into ``curves``). Returns the :class:`curvenet.Result`."""
    from ._core import load

    samples = [sample_curve(c, tolerance) for c in curves]
    tuples, warnings = _native.curves_from_arrays(
        "<rhino selection>",
        [s[0] for s in samples],
        [s[1] for s in samples],
        [None] * len(samples),
        list(range(1, len(samples) + 1)),
    )
    arrays = [t[0] for t in tuples]
    m = mesh_arrays(mesh) if mesh is not None else None
    net = load(arrays, mesh=m, **load_options)
    result = net.simplify(budget, keep=list(keep), progress=progress)
    result.warnings = warnings + result.warnings
    return result


@dataclass
class Layer:
    """One layer of a result: its full path, colour, and objects ``(name, points, closed)``."""

    path: str
    color: Tuple[int, int, int]
    objects: List[Tuple[str, np.ndarray, bool]] = field(default_factory=list)


def result_layers(result: Any, iteration: Optional[int] = None,
                  mode_scale: Optional[float] = None) -> List[Layer]:
    """The layers :func:`write_3dm` writes (and the Rhino script adds): under ``curvenet``,
    ``kept`` and ``removed`` (designed shapes), ``equilibrium`` (the kept curves at
    equilibrium), ``worst-case mode`` (the kept curves displaced along the worst-case mode,
    the largest displacement ``mode_scale``, default 5% of the network's bounding-box
    diagonal). Object names are ``curve ID``."""
    k = result._k(iteration)
    # The native read first: it refuses an iteration past the end with the run's own message.
    mode = result.mode(k)
    kept = list(result.iterations[k]["curves"])
    kept_set = set(kept)
    removed = [c for c in range(result.curve_count) if c not in kept_set]
    pos = result.positions
    if mode_scale is None:
        mode_scale = 0.05 * _diagonal(pos)
    peak = float(np.max(np.linalg.norm(mode, axis=1))) if len(mode) else 0.0
    u_mode = result.displacement(k) + (mode * (mode_scale / peak) if peak > 0 else 0.0)

    def objects(curves: List[int], polylines: List[Tuple[np.ndarray, bool]]):
        return [(f"curve {c}", p, closed) for c, (p, closed) in zip(curves, polylines)]

    lam = result.iterations[k]["lambda"]
    return [
        Layer(f"{LAYER_ROOT}::kept", (30, 30, 30),
              objects(kept, result.polylines(kept, "rest"))),
        Layer(f"{LAYER_ROOT}::removed", (190, 190, 190),
              objects(removed, result.polylines(removed, "rest"))),
        Layer(f"{LAYER_ROOT}::equilibrium", (40, 110, 200),
              objects(kept, result.polylines(kept, "equilibrium", k))),
        Layer(f"{LAYER_ROOT}::worst-case mode (lambda {lam:.4e})", (210, 60, 40),
              objects(kept, result._native.polylines(kept, u_mode))),
    ]


def write_3dm(result: Any, path: os.PathLike, iteration: Optional[int] = None,
              mode_scale: Optional[float] = None) -> Path:
    """Writes :func:`result_layers` (and the surface, on ``curvenet::surface``) to a Rhino 8
    ``.3dm``. Each curve carries the user string ``curvenet.curve`` = its id."""
    import rhino3dm

    doc = rhino3dm.File3dm()
    root = rhino3dm.Layer()
    root.Name = LAYER_ROOT
    root_index = doc.Layers.Add(root)
    root_id = doc.Layers[root_index].Id

    def add_layer(full: str, color: Tuple[int, int, int]) -> int:
        layer = rhino3dm.Layer()
        layer.Name = full.split("::", 1)[1]
        layer.ParentLayerId = root_id
        layer.Color = (*color, 255)
        return doc.Layers.Add(layer)

    for lay in result_layers(result, iteration, mode_scale):
        index = add_layer(lay.path, lay.color)
        for name, pts, closed in lay.objects:
            ps = [rhino3dm.Point3d(*map(float, p)) for p in pts]
            if closed:
                ps.append(ps[0])
            attrs = rhino3dm.ObjectAttributes()
            attrs.LayerIndex = index
            attrs.Name = name
            attrs.SetUserString("curvenet.curve", name.split()[-1])
            doc.Objects.AddCurve(rhino3dm.PolylineCurve(ps), attrs)
    mesh_file = result.folder / "mesh.obj"
    if mesh_file.is_file():
        (vertices, faces), _, _ = _native.read_mesh(os.fspath(mesh_file))
        m = rhino3dm.Mesh()
        for v in vertices:
            m.Vertices.Add(float(v[0]), float(v[1]), float(v[2]))
        for f in faces:
            m.Faces.AddFace(int(f[0]), int(f[1]), int(f[2]))
        attrs = rhino3dm.ObjectAttributes()
        attrs.LayerIndex = add_layer(f"{LAYER_ROOT}::surface", (120, 160, 120))
        attrs.Name = "surface"
        doc.Objects.AddMesh(m, attrs)
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    if not doc.Write(os.fspath(tmp), 8):
        raise InputError(f"{path}: could not write the file", os.fspath(path), None)
    os.replace(tmp, path)
    return path
