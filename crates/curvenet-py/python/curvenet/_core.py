"""Loading, analysing and simplifying curve networks (the API of the command line)."""

from __future__ import annotations

import json
import numbers
import os
import reprlib
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._errors import InputError

__all__ = [
    "Analysis",
    "Answer",
    "Record",
    "Iteration",
    "Network",
    "Result",
    "example",
    "example_names",
    "load",
    "open_run",
]

PathLike = Union[str, "os.PathLike[str]"]
CurveSource = Union[PathLike, np.ndarray, Sequence[Sequence[float]]]


def _is_path(x: Any) -> bool:
    return isinstance(x, (str, os.PathLike))


# Arguments of the wrong type are bad input like any other: an ``InputError`` naming the
# keyword argument, never the bare ``TypeError`` of a conversion deeper down.

def _shown(value: Any) -> str:
    """``value`` as an error message shows it (bounded: a long list is cut short)."""
    return reprlib.repr(value)


def _real(option: str, value: Any) -> Optional[float]:
    """A number option (``None``: its default). ``True`` and text are refused: an option that
    takes a unit says so and goes through :func:`_text`."""
    if value is None:
        return None
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InputError(f"{option}: expected a number, got {_shown(value)}")
    return float(value)


def _name(option: str, value: Any) -> Optional[str]:
    """A word option such as ``supports="pinned"`` (``None``: its default)."""
    if value is None or isinstance(value, str):
        return value
    raise InputError(f"{option}: expected text, got {_shown(value)}")


def _path(option: str, value: Any) -> Optional[str]:
    """A file or folder option (``None``: its default)."""
    if value is None:
        return None
    if not _is_path(value):
        raise InputError(f"{option}: expected a file or folder path, got {_shown(value)}")
    return os.fspath(value)


def _flag(option: str, value: Any) -> bool:
    """A yes/no option: ``True`` or ``False`` (``"no"`` is refused, not taken as true)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{option}: expected True or False, got {_shown(value)}")
    return bool(value)


def _out_and_pictures(out: Any, pictures: Any, prefix: str) -> Tuple[str, bool]:
    """A run's folder and whether to draw its pictures, the last options checked: ``out``, or
    a new temporary folder named ``prefix…``; ``pictures`` by default only into a folder the
    caller named."""
    if pictures is not None:
        pictures = _flag("pictures", pictures)
    folder = _path("out", out)
    if folder is None:
        folder = tempfile.mkdtemp(prefix=prefix)
    return folder, (out is not None) if pictures is None else pictures


def _read_curve_sources(
    curves: Union[CurveSource, Iterable[CurveSource]],
    tolerance: Optional[float],
    layer: Optional[str],
) -> Tuple[list, Optional[tuple], Optional[str], List[str], List[str]]:
    """Curve sources for the native layer (paths of curve files, read there, and curve
    tuples), a mesh found in a .3dm (or None) and its name, the files, the warnings."""
    if _is_path(curves) or isinstance(curves, np.ndarray):
        curves = [curves]
    try:
        curves = list(curves)
    except TypeError:
        raise InputError("curves: expected curve files and/or (n, 3) arrays of points, got "
                         f"{_shown(curves)}") from None
    out: list = []
    warnings: List[str] = []
    files: List[str] = []
    mesh = None
    mesh_name = None
    arrays: List[np.ndarray] = []

    def flush_arrays() -> None:
        if arrays:
            got, w = _native.curves_from_arrays(
                "<arrays>",
                [np.ascontiguousarray(a, dtype=np.float64) for a in arrays],
                [None] * len(arrays),
                [None] * len(arrays),
                list(range(len(out) + 1, len(out) + len(arrays) + 1)),
            )
            out.extend(got)
            warnings.extend(w)
            arrays.clear()

    for src in curves:
        if _is_path(src):
            flush_arrays()
            path = os.fspath(src)
            files.append(path)
            if path.lower().endswith(".3dm"):
                from . import rhino

                got, m, w = rhino.read_3dm(path, tolerance=tolerance, layer=layer)
                out.extend(got)
                warnings.extend(w)
                if m is not None and mesh is None:
                    mesh, mesh_name = m, path
            else:
                # Read by the library itself, with the groups, materials and units the file
                # declares.
                out.append(path)
        else:
            try:
                a = np.asarray(src, dtype=np.float64)
            except (TypeError, ValueError):
                raise InputError(
                    f"curve {len(out) + len(arrays)}: expected a curve file or an (n, 3) "
                    f"array of points, got {_shown(src)}"
                ) from None
            if a.ndim != 2 or a.shape[1] != 3:
                raise InputError(
                    f"curve {len(out) + len(arrays)}: expected an (n, 3) array of points, "
                    f"got shape {a.shape}"
                )
            arrays.append(a)
    flush_arrays()
    return out, mesh, mesh_name, files, warnings


def _mesh_arrays(vertices: Any, faces: Any, name: str) -> tuple:
    """``(vertices, faces, name)`` for the native layer: float64 vertices and the faces of
    any integer dtype as int64 (negative or out-of-range indices are refused there)."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if f.dtype.kind not in "iu":
        raise InputError(f"{name}: faces must be integer vertex indices, got dtype {f.dtype}")
    if f.dtype.kind == "u" and f.size and int(f.max()) > np.iinfo(np.int64).max:
        raise InputError(f"{name}: a face names vertex {int(f.max())}, beyond any mesh")
    return v, np.ascontiguousarray(f, dtype=np.int64), name


def _read_mesh(mesh: Any) -> Tuple[Any, List[str]]:
    """The mesh for the native layer (a path, read there, or arrays) and warnings."""
    if mesh is None:
        return None, []
    if _is_path(mesh):
        path = os.fspath(mesh)
        if path.lower().endswith(".3dm"):
            from . import rhino

            _, m, w = rhino.read_3dm(path, curves=False)
            if m is None:
                raise InputError(f"{path}: no mesh in the file", path, None)
            return _mesh_arrays(m[0], m[1], path), w
        return path, []
    try:
        vertices, faces = mesh
    except (TypeError, ValueError):
        raise InputError("mesh: expected a file path, a built-in surface name or "
                         "(vertices, faces) arrays") from None
    return _mesh_arrays(vertices, faces, "<arrays>"), []


def _ids(option: str, ids: Optional[Iterable[Any]]) -> Optional[List[int]]:
    """Curve ids as the command line takes them: non-negative integers (``1.9`` is refused,
    not rounded)."""
    if ids is None:
        return None
    if isinstance(ids, (int, np.integer)):
        ids = [ids]
    out = []
    for c in ids:
        if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)):
            raise InputError(f"{option}: curve ids are whole numbers, got {c!r}")
        if c < 0:
            raise InputError(f"{option}: curve ids are 0 or more, got {c}")
        out.append(int(c))
    return out


def _whole(option: str, value: Any, least: int = 0) -> int:
    """A whole-number option as the command line takes it (``2.5`` and ``True`` are refused,
    not rounded), ``least`` or more."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{option}: expected a whole number, got {value!r}")
    if value < least:
        raise InputError(f"{option} is {value}: it must be {least} or more")
    return int(value)


def _text(x: Any) -> Optional[str]:
    """An option given as a number or as text with its unit (``210e9`` or ``"210GPa"``)."""
    return None if x is None else str(x)


_MODEL_DOC = """
    Model options, as on the command line (``--radius`` is ``radius=``, and so on):
    ``supports`` (``"clamped"``, the default, or ``"pinned"``), ``supports_file`` (a JSON
    file of supports per curve end, by point or by curve and end, overriding ``supports``
    there; a curve file's own ``"supports"`` per curve do the same), ``merge_joints`` (merge
    joints closer than this fraction of ``h``), ``radius`` (the rod radius, scene units;
    default 2), ``young`` (Young's modulus: a number in the paper's mode, default 1; with a
    unit such as ``"210GPa"`` in the physical mode), ``anchor_weight`` (default 500),
    ``eigen_count`` (eigenvalues reported, 1 to 100; default 4) and ``objective``
    (``"lambda"``, the paper's λ_eq, or ``"frequency"``, the first natural frequency's μ_min).

    The physical mode (``units`` ``"mm"``, ``"cm"`` or ``"m"``, and/or ``material``: steel,
    aluminium, gfrp, timber) reports frequencies in Hz, deflections in the scene's unit and
    stresses in MPa beside λ: ``density``, ``strength``, ``tube`` (``"60x4"``: outer diameter
    x wall), ``load`` (``"1kN/m"``) and ``gravity`` (m/s², a magnitude along -z or
    ``"gx,gy,gz"``) refine it. ``loads`` (a loads file: load cases and combinations, see
    docs/units.md) adds each case's nonlinear equilibrium, deflection, utilisation and critical
    load factor to the analysis (``physical["load_cases"]``), checked against
    ``deflection_limit`` (``"span/250"`` or a length such as ``"20mm"``) and
    ``buckling_factor`` (the smallest acceptable critical factor, default 1).
"""


def _with_model_doc(f: Callable) -> Callable:
    """Puts the model options' documentation where the docstring says ``{model}``."""
    f.__doc__ = (f.__doc__ or "").replace("{model}", _MODEL_DOC.strip("\n"))
    return f


def _model_kwargs(supports, merge_joints, radius, young, anchor_weight, eigen_count, objective,
                  units, material, density, strength, tube, load, gravity, loads=None,
                  deflection_limit=None, buckling_factor=None,
                  supports_file=None) -> Dict[str, Any]:
    return dict(
        supports=_name("supports", supports),
        merge_joints=_real("merge_joints", merge_joints),
        radius=_real("radius", radius),
        young=_text(young),
        anchor_weight=_real("anchor_weight", anchor_weight),
        eigen_count=_whole("eigen_count", eigen_count),
        objective=_name("objective", objective),
        units=_name("units", units),
        material=_name("material", material),
        density=_text(density),
        strength=_text(strength),
        tube=_text(tube),
        load=_text(load),
        gravity=_text(gravity),
        loads=_path("loads", loads),
        deflection_limit=_text(deflection_limit),
        buckling_factor=_text(buckling_factor),
        supports_file=_path("supports_file", supports_file),
    )


@_with_model_doc
def load(
    curves: Union[CurveSource, Iterable[CurveSource]],
    mesh: Any = None,
    scale: float = 1.0,
    edge_length: Optional[float] = None,
    supports: Optional[str] = None,
    *,
    supports_file: Optional[PathLike] = None,
    merge_joints: Optional[float] = None,
    radius: Optional[float] = None,
    young: Union[float, str, None] = None,
    anchor_weight: Optional[float] = None,
    eigen_count: int = 4,
    objective: str = "lambda",
    units: Optional[str] = None,
    material: Optional[str] = None,
    density: Optional[str] = None,
    strength: Optional[str] = None,
    tube: Optional[str] = None,
    load: Optional[str] = None,
    gravity: Union[float, str, None] = None,
    loads: Optional[PathLike] = None,
    deflection_limit: Union[float, str, None] = None,
    buckling_factor: Optional[float] = None,
    tolerance: Optional[float] = None,
    layer: Optional[str] = None,
) -> "Network":
    """Builds the rod network of ``curves`` (``curvenet analyze``/``simplify``'s inputs).

    ``curves``: curve files (``.txt``, ``.obj``, ``.json``, ``.3dm``) and/or ``(n, 3)`` point
    arrays, in curve-id order; a JSON curve file's groups, units and per-curve materials are
    read as the command line reads them. ``mesh``: the surface (an OBJ file, a built-in
    surface name such as ``"dome"``, a ``.3dm`` holding a mesh, or ``(vertices, faces)``
    arrays, faces of any integer dtype); a ``.3dm`` among the curves gives its mesh when
    ``mesh`` is not given. ``scale`` multiplies everything; ``edge_length`` is the resampling
    length ``h`` after scaling (default, as on the command line: the median curve's length
    over 50, and no less than the total length over 100,000). ``tolerance`` is how far NURBS
    curves of a ``.3dm`` may be from their sampled polylines (default: 1e-3 × each curve's
    bounding-box diagonal); ``layer`` keeps only the ``.3dm`` objects on that layer (full
    path, e.g. ``"curvenet::kept"``) and its sub-layers.
    {model}
    Raises :class:`curvenet.InputError` with the command line's message (file and line, or
    the keyword argument).
    """
    # The options are checked before any file is read.
    model = _model_kwargs(supports, merge_joints, radius, young, anchor_weight, eigen_count,
                          objective, units, material, density, strength, tube, load, gravity,
                          loads, deflection_limit, buckling_factor, supports_file)
    scale = 1.0 if scale is None else _real("scale", scale)
    edge_length = _real("edge_length", edge_length)
    sources, found_mesh, found_name, files, warnings = _read_curve_sources(
        curves, _real("tolerance", tolerance), _name("layer", layer))
    m, w = _read_mesh(mesh)
    warnings.extend(w)
    if m is None and found_mesh is not None:
        m = _mesh_arrays(found_mesh[0], found_mesh[1], found_name)
    native = _native.Network(
        sources,
        mesh=m,
        scale=scale,
        edge_length=edge_length,
        warnings=warnings,
        **model,
    )
    return Network(native)


def example_names() -> List[str]:
    """The names of the paper's examples (``curvenet example NAME``)."""
    return list(_native.example_names())


@_with_model_doc
def example(
    name: str,
    supports: Optional[str] = None,
    *,
    supports_file: Optional[PathLike] = None,
    data: Optional[PathLike] = None,
    merge_joints: Optional[float] = None,
    radius: Optional[float] = None,
    young: Union[float, str, None] = None,
    anchor_weight: Optional[float] = None,
    eigen_count: int = 4,
    objective: str = "lambda",
    units: Optional[str] = None,
    material: Optional[str] = None,
    density: Optional[str] = None,
    strength: Optional[str] = None,
    tube: Optional[str] = None,
    load: Optional[str] = None,
    gravity: Union[float, str, None] = None,
    loads: Optional[PathLike] = None,
    deflection_limit: Union[float, str, None] = None,
    buckling_factor: Optional[float] = None,
) -> "Network":
    """The paper's example ``name`` (``roof``, ``tower``, ...; see :func:`example_names`) with
    its set-up (``curvenet example NAME``): the network, and as :meth:`Network.simplify`'s
    defaults its budget and keep list. ``data`` names a folder with the paper's ``meshes/``
    and ``curves/`` (default: the copies embedded in curvenet).
    {model}"""
    native = _native.Network(
        [],
        example=_name("name", name),
        data=_path("data", data),
        **_model_kwargs(supports, merge_joints, radius, young, anchor_weight, eigen_count,
                        objective, units, material, density, strength, tube, load, gravity,
                        loads, deflection_limit, buckling_factor, supports_file),
    )
    return Network(native)


def _xyz(a: np.ndarray) -> np.ndarray:
    return np.asarray(a).reshape(-1, 3)


class Analysis:
    """The analysis of a network at equilibrium (``curvenet analyze``)."""

    def __init__(self, raw: Dict[str, Any], positions: np.ndarray):
        self.report: Dict[str, Any] = json.loads(raw["report"])
        """Everything ``curvenet analyze --json`` prints."""
        self.eigenvalues: np.ndarray = raw["eigenvalues"]
        """The smallest eigenvalues at equilibrium, ascending."""
        self.mode: np.ndarray = raw["mode"]
        """The worst-case load: the unit eigenvector of ``lambda_eq``, ``(V, 3)``."""
        self.displacement: np.ndarray = raw["displacement"]
        """Displacements of the equilibrium from the drawn state, ``(V, 3)``."""
        self.equilibrium: np.ndarray = positions + self.displacement
        """Vertex positions at equilibrium, ``(V, 3)``."""

    @property
    def lambda_eq(self) -> float:
        """``λ_eq``: the smallest eigenvalue of the Hessian at equilibrium."""
        return float(self.report["lambda"])

    @property
    def zero_modes(self) -> int:
        """Eigenvalues within the zero threshold (mechanisms)."""
        return int(self.report["zero_modes"])

    @property
    def negative_modes(self) -> int:
        """Eigenvalues below it (unstable directions)."""
        return int(self.report["negative_modes"])

    @property
    def stable(self) -> bool:
        """True when the equilibrium is stable: no zero or negative mode."""
        return self.zero_modes == 0 and self.negative_modes == 0

    @property
    def warnings(self) -> List[str]:
        """Warnings of the reading, the build and the analysis."""
        return list(self.report.get("warnings", []))

    @property
    def physical(self) -> Optional["Record"]:
        """In the physical mode, the structure in a material's units (``analyze --json``'s
        ``physical``: ``stable``, ``frequencies_hz``, ``first_frequency_hz``,
        ``self_weight_max_deflection`` and ``load_max_deflection`` in ``units``, stresses in
        MPa, ``max_utilisation``, ``mass_kg``, ``load_cases`` with ``loads=``, ...); None in
        the paper's mode."""
        p = self.report.get("physical")
        return None if p is None else Record(p)

    def __repr__(self) -> str:
        state = "" if self.stable else (
            f", UNSTABLE: {self.zero_modes} zero and {self.negative_modes} negative mode(s)"
        )
        return f"<curvenet.Analysis lambda_eq={self.lambda_eq:.6e}{state}>"


class Record(dict):
    """A JSON object of a report (a dict) whose keys also read as attributes."""

    def __getattr__(self, name: str) -> Any:
        try:
            v = self[name]
        except KeyError:
            raise AttributeError(name) from None
        return Record(v) if isinstance(v, dict) else v


class Answer(Record):
    """The network to build (``result.json``'s ``answer``, or one of its ``alternatives``):
    ``curves``, ``length``, ``lambda_eq`` (the record's ``lambda``), ``source`` (``greedy``,
    ``local_search``, ...), ``iteration`` (for a network of the greedy's path)."""

    @property
    def lambda_eq(self) -> float:
        return float(self["lambda"])

    @property
    def curves(self) -> List[int]:
        return list(self["curves"])

    @property
    def source(self) -> str:
        return str(self["source"])

    def __repr__(self) -> str:
        return (f"<curvenet.Answer {len(self.curves)} curves from {self.source}, "
                f"lambda_eq={self.lambda_eq:.6e}>")


class Network:
    """A rod network built from curves (see :func:`load`, :func:`example`)."""

    def __init__(self, native: "_native.Network"):
        self._native = native
        ex = native.example
        self.default_budget: Optional[float] = None if ex is None else ex[0]
        """The example's budget fraction (None for :func:`load`)."""
        self.default_keep: List[int] = [] if ex is None else list(ex[1])
        """The example's keep list."""
        self.paper: Optional[Dict[str, Any]] = None if ex is None else json.loads(ex[2])
        """For an example, the paper's Table 1 figures."""

    @property
    def positions(self) -> np.ndarray:
        """Vertex positions of the drawn (rest) state, ``(V, 3)``."""
        return self._native.positions

    @property
    def rods(self) -> List[np.ndarray]:
        """Per curve id, its vertex indices in order."""
        return self._native.rods

    @property
    def curve_count(self) -> int:
        return len(self._native.closed)

    @property
    def vertex_count(self) -> int:
        return int(self._native.positions.shape[0])

    @property
    def closed(self) -> List[bool]:
        """Per curve id, whether the curve is closed."""
        return self._native.closed

    @property
    def anchors(self) -> List[np.ndarray]:
        """Per curve id, its supported vertices."""
        return self._native.anchors

    @property
    def edges(self) -> np.ndarray:
        """Every rod edge as a vertex pair, ``(E, 2)`` (for plotting, e.g. with polyscope)."""
        return self._edges()[0]

    @property
    def edge_curves(self) -> np.ndarray:
        """The curve id of each of :attr:`edges`, ``(E,)``."""
        return self._edges()[1]

    def _edges(self) -> Tuple[np.ndarray, np.ndarray]:
        pairs, ids = [], []
        for c, (rod, closed) in enumerate(zip(self.rods, self.closed)):
            rod = np.asarray(rod, dtype=np.int64)
            e = np.stack([rod[:-1], rod[1:]], axis=1)
            if closed:
                e = np.vstack([e, [[rod[-1], rod[0]]]])
            pairs.append(e)
            ids.append(np.full(len(e), c, dtype=np.int64))
        return np.vstack(pairs), np.concatenate(ids)

    @property
    def joints(self) -> List[Tuple[int, List[int]]]:
        """Shared vertices: ``(vertex, [curve ids])``."""
        return self._native.joints

    @property
    def rest_lengths(self) -> np.ndarray:
        """Per curve id, its rest length (the material to cut)."""
        return self._native.rest_lengths

    @property
    def total_length(self) -> float:
        return float(np.sum(self.rest_lengths))

    @property
    def edge_length(self) -> float:
        """The resampling length ``h``."""
        return self._native.edge_length

    @property
    def supports(self) -> str:
        return self._native.supports

    @property
    def curves(self) -> List[np.ndarray]:
        """The input curves (scaled) as ``(n, 3)`` point arrays, in id order."""
        return [c[0] for c in self._native.curves]

    @property
    def mesh(self) -> Optional[Tuple[np.ndarray, np.ndarray]]:
        """The surface as ``(vertices, faces)``, or None."""
        return self._native.mesh

    @property
    def warnings(self) -> List[str]:
        """Warnings of the reading and the build."""
        return self._native.warnings

    @property
    def build_info(self) -> Dict[str, Any]:
        """Construction details (crossings, joints, isolated curves, ...)."""
        return json.loads(self._native.build_info)

    def analyze(self, remove: Iterable[int] = ()) -> Analysis:
        """Relaxes the network (without the curves ``remove``) and analyses its equilibrium:
        ``λ_eq``, the smallest eigenvalues, the worst-case mode and, in the physical mode,
        :attr:`Analysis.physical` (``curvenet analyze``). Ctrl-C stops it."""
        raw = self._native.analyze(_ids("remove", remove) or [])
        return Analysis(raw, self.positions)

    def simplify(
        self,
        budget: Optional[float] = None,
        *,
        budget_length: Optional[float] = None,
        keep: Optional[Iterable[int]] = None,
        groups: Union[PathLike, Sequence[Sequence[int]], None] = None,
        symmetry: Optional[str] = None,
        connected: bool = False,
        min_curves: Optional[int] = None,
        max_gap: Optional[float] = None,
        max_deviation: Optional[float] = None,
        local_search: bool = False,
        alternatives: int = 0,
        certify: bool = False,
        certificate_nodes: Optional[int] = None,
        out: Optional[PathLike] = None,
        resume: bool = False,
        force: bool = False,
        pictures: Optional[bool] = None,
        progress: Optional[Callable[["Iteration"], Any]] = None,
        slide: bool = False,
        max_move: Union[float, str, None] = None,
        fixed_ends: bool = False,
        pin: Optional[Iterable[int]] = None,
        slide_rounds: int = 0,
    ) -> "Result":
        """Simplifies the network to a budget (``curvenet simplify``): the greedy down to
        ``budget`` (a fraction of the total rest length) or ``budget_length`` (a length),
        never removing ``keep`` (an example's own budget and keep list by default), then
        the steps asked for, and the answer: the most stable network found that is stable,
        within the budget and meets every design constraint (``Result.answer``, None when
        there is none).

        Design constraints, as on the command line: ``groups`` (a groups file, or lists of
        curve ids kept or removed together), ``symmetry`` (``"rotate:N"``, ``"mirror"``,
        ``"auto"`` or ``"none"``), ``connected``, ``min_curves``, ``max_gap`` (needs the
        surface) and ``max_deviation``. After the greedy: ``local_search``, ``alternatives``
        (up to K further distinct networks; runs the local search), ``certify`` (an upper
        bound on λ_fix within the budget; ``certificate_nodes`` of branch and bound).
        ``slide=True`` then slides the answer's curves on the surface into the run folder's
        ``slide/`` (:func:`slide`: ``max_move``, ``fixed_ends``, ``pin``, ``slide_rounds``),
        read back as :attr:`Result.slide`.

        The run is written to the folder ``out`` exactly as the command line writes it
        (default: a new temporary folder), so :func:`open_run` reads it again and
        ``resume=True`` continues an interrupted run. As on the command line, another run
        writing in ``out`` meanwhile is refused, a fresh run into an earlier run's folder
        removes that run's files first, and a non-empty folder that is not a curvenet run's is
        refused unless ``force=True``. ``pictures`` writes the pictures and the viewer page
        (default: when ``out`` is given). ``progress(iteration)`` is called after each
        iteration; an exception it raises stops the run, as does Ctrl-C
        (``KeyboardInterrupt``), within a second, keeping what was recorded. The call
        releases the GIL: runs in several threads go on side by side.
        """
        # Every option is checked before anything is written (the temporary folder too).
        groups_file = None
        group_lists: List[List[int]] = []
        if groups is not None:
            if _is_path(groups):
                groups_file = os.fspath(groups)
            else:
                try:
                    groups = list(groups)
                except TypeError:
                    raise InputError("groups: expected a groups file or lists of curve ids, "
                                     f"got {_shown(groups)}") from None
                group_lists = [_ids(f"groups[{k}]", g) or [] for k, g in enumerate(groups)]
        if progress is not None and not callable(progress):
            raise InputError(f"progress: expected a function of one iteration, got "
                             f"{_shown(progress)}")
        options = dict(
            budget=_real("budget", budget),
            budget_length=_real("budget_length", budget_length),
            keep=_ids("keep", keep),
            groups_file=groups_file,
            groups=group_lists,
            symmetry=_name("symmetry", symmetry),
            connected=_flag("connected", connected),
            min_curves=None if min_curves is None else _whole("min_curves", min_curves),
            max_gap=_real("max_gap", max_gap),
            max_deviation=_real("max_deviation", max_deviation),
            local_search=_flag("local_search", local_search),
            alternatives=_whole("alternatives", alternatives),
            certify=_flag("certify", certify),
            certificate_nodes=(None if certificate_nodes is None
                               else _whole("certificate_nodes", certificate_nodes)),
            resume=_flag("resume", resume),
            force=_flag("force", force),
            slide=_flag("slide", slide),
            max_move=None if max_move is None else str(max_move),
            fixed_ends=_flag("fixed_ends", fixed_ends),
            pin=_ids("pin", pin) or [],
            slide_rounds=_whole("slide_rounds", slide_rounds),
        )
        out, pictures = _out_and_pictures(out, pictures, "curvenet-run-")
        cb = None
        if progress is not None:
            def cb(text: str) -> None:
                progress(Iteration(json.loads(text)))
        warnings = self._native.simplify(out, pictures=pictures, progress=cb, **options)
        result = open_run(out)
        result.warnings = list(warnings) + result.warnings
        return result

    def __repr__(self) -> str:
        return (f"<curvenet.Network {self.curve_count} curves, {self.vertex_count} vertices, "
                f"{len(self.joints)} joints, h={self.edge_length:g}>")


class Iteration(dict):
    """One iteration of the greedy: the network after ``iteration`` removals. A dict (the
    record of ``result.json``) whose keys also read as attributes: ``curves``, ``length``,
    ``lambda_eq`` (the record's ``lambda``), ``removed`` (the curve removed next, None on the
    last), ``score``, ``eigenvalues``, ``zero_modes``, ``negative_modes``."""

    def __getattr__(self, name: str) -> Any:
        if name == "lambda_eq":
            name = "lambda"
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    @property
    def stable(self) -> bool:
        return self.get("zero_modes", 0) == 0 and self.get("negative_modes", 0) == 0


class Result:
    """A greedy run, read from its folder (:meth:`Network.simplify`, :func:`open_run`)."""

    def __init__(self, native: "_native.Run"):
        self._native = native
        self.result: Dict[str, Any] = json.loads(native.result_json)
        """``result.json`` as a dict (set-up, budget, stop, iterations, final network, and
        whatever else the run recorded: local search, certificate, ...)."""
        self.warnings: List[str] = list(native.warnings)
        self.iterations: List[Iteration] = [Iteration(it) for it in self.result["iterations"]]
        for k, it in enumerate(self.iterations):
            it["iteration"] = k

    @property
    def folder(self) -> Path:
        return Path(self._native.dir)

    @property
    def complete(self) -> bool:
        return bool(self.result["complete"])

    @property
    def stop(self) -> Optional[str]:
        """Why the greedy stopped (``budget_met``, ``budget_unmet``, ...)."""
        return self.result.get("stop")

    @property
    def budget(self) -> float:
        """The budget as a length."""
        return float(self.result["budget"])

    @property
    def final_curves(self) -> List[int]:
        """The curves of the greedy's last recorded network (the path's end; the network to
        build is :attr:`answer`)."""
        return list(self.iterations[-1]["curves"])

    @property
    def removed_curves(self) -> List[int]:
        """The curves removed, in order."""
        return [it["removed"] for it in self.iterations if it.get("removed") is not None]

    @property
    def lambdas(self) -> np.ndarray:
        """``λ_eq`` along the greedy, one per iteration."""
        return np.array([it["lambda"] for it in self.iterations])

    @property
    def lengths(self) -> np.ndarray:
        """Total rest length along the greedy."""
        return np.array([it["length"] for it in self.iterations])

    @property
    def answer(self) -> Optional[Answer]:
        """The network to build (``result.json``'s ``answer``): the most stable network the
        run found that is stable, within the budget and meets every constraint; None when
        the run has none (:attr:`no_answer` says why) or is unfinished."""
        a = self.result.get("answer")
        return None if a is None else Answer(a)

    @property
    def no_answer(self) -> Optional[Record]:
        """Why a finished run has no answer, and its smallest stable network; else None."""
        n = self.result.get("no_answer")
        return None if n is None else Record(n)

    @property
    def alternatives(self) -> List[Answer]:
        """The alternatives recorded (``alternatives=K``), best first."""
        return [Answer(a) for a in self.result.get("alternatives", [])]

    @property
    def local_search(self) -> Optional[Dict[str, Any]]:
        return self.result.get("local_search")

    @property
    def slide(self) -> Optional["Slide"]:
        """How the answer slid on the surface: this run's own ``slide`` record when it is a
        slid run, else that of the slid run in its ``slide/`` folder (``slide=True``); None
        when neither. Its :attr:`Slide.run` is the slid run, whose answer (source
        ``slide``) holds the moved curves."""
        if "slide" in self.result:
            return Slide(self.result["slide"], self)
        inner = self.folder / "slide" / "result.json"
        if inner.is_file():
            run = open_run(self.folder / "slide")
            return Slide(run.result["slide"], run)
        return None

    @property
    def certificate(self) -> Optional[Dict[str, Any]]:
        return self.result.get("certificate")

    @property
    def positions(self) -> np.ndarray:
        """Vertex positions of the drawn state, ``(V, 3)``."""
        return self._native.positions

    @property
    def curve_count(self) -> int:
        return self._native.curve_count

    def _k(self, iteration: Optional[int]) -> int:
        """An iteration by its number; None the last, and from the end when negative (-1 the
        last), as Python's indices. The native calls refuse one past the end."""
        n = len(self.iterations)
        if iteration is None:
            return n - 1
        k = _whole("iteration", iteration, least=-n)
        return k + n if k < 0 else k

    def displacement(self, iteration: Optional[int] = None) -> np.ndarray:
        """Equilibrium displacements of an iteration (default: the last), ``(V, 3)``."""
        return self._native.displacement(self._k(iteration))

    def equilibrium(self, iteration: Optional[int] = None) -> np.ndarray:
        """Vertex positions at an iteration's equilibrium, ``(V, 3)``."""
        return self.positions + self.displacement(iteration)

    def mode(self, iteration: Optional[int] = None) -> np.ndarray:
        """The worst-case mode of an iteration (unit norm), ``(V, 3)``."""
        return self._native.mode(self._k(iteration))

    def polylines(self, curves: Iterable[int], state: str = "rest",
                  iteration: Optional[int] = None) -> List[Tuple[np.ndarray, bool]]:
        """``(points, closed)`` of ``curves``: at rest (``state="rest"``) or at the
        iteration's equilibrium (``"equilibrium"``)."""
        curves = _ids("curves", curves) or []
        state = _name("state", state)
        if state == "rest":
            return self._native.polylines(curves, None)
        if state == "equilibrium":
            return self._native.polylines(curves, self.displacement(iteration))
        raise InputError(f"unknown state '{state}' (expected rest or equilibrium)")

    def export(self, out: Optional[PathLike] = None, format: str = "all",
               iteration: Optional[int] = None) -> List[Path]:
        """Writes an iteration's network (default: the last) as ``curvenet export`` does:
        ``format`` is ``obj``, ``json``, ``csv``, ``network``, ``structural`` (a physical
        run's neutral structural JSON), ``opensees`` (its OpenSeesPy script) or ``all``; ``out`` a folder
        (default: ``export/`` in the run folder). Returns the paths written."""
        folder = self.folder / "export" if out is None else Path(_path("out", out))
        return [Path(p) for p in self._native.export(os.fspath(folder), _name("format", format),
                                                      self._k(iteration))]

    def write_3dm(self, path: PathLike, iteration: Optional[int] = None,
                  mode_scale: Optional[float] = None) -> Path:
        """Writes a Rhino file: kept and removed curves (designed shapes), the kept curves at
        equilibrium and displaced along the worst-case mode, and the surface, on layers
        under ``curvenet`` (see :mod:`curvenet.rhino`)."""
        from . import rhino

        return rhino.write_3dm(self, _path("path", path), iteration=iteration,
                               mode_scale=_real("mode_scale", mode_scale))

    def __repr__(self) -> str:
        last = self.iterations[-1]
        state = "" if last.stable else ", UNSTABLE"
        return (f"<curvenet.Result {len(self.removed_curves)} removed, "
                f"{len(last['curves'])} curves left, lambda_eq={last['lambda']:.6e}{state}, "
                f"stop={self.stop}, folder={str(self.folder)!r}>")


class Slide(Record):
    """A slid run's record (``result.json``'s ``slide``): ``lambda_before``,
    ``lambda_after``, ``max_move``, ``largest_move``, ``joints_added``, ``joints_removed``,
    ``length_before``, ``length_after``, ``budget``, ``curves`` (each curve's id in the run
    it came from, ``largest_move`` and move ``coefficients``), ``evaluations``, ``steps``,
    ``rounds`` (with ``slide_rounds``: each round's ``start``, ``local_search`` and ``slid``
    objectives, its ``curves`` and ``folder``), ``answer_round`` (with ``slide_rounds``: the
    slide whose network is the answer, the best of every slide; 0 the first) and ``deviation``
    (the slid network's largest deviation, when a largest deviation is in force)."""

    def __init__(self, record: Dict[str, Any], run: "Result"):
        super().__init__(record)
        self.run = run
        """The slid run."""

    @property
    def gain(self) -> Optional[float]:
        """``lambda_after / lambda_before`` (None unless the start was stable)."""
        b = self["lambda_before"]
        return self["lambda_after"] / b if b > 0 else None

    @property
    def answer(self) -> Optional[Answer]:
        """The slid network (None when it is not stable within the budget)."""
        return self.run.answer

    @property
    def rounds(self) -> List[Record]:
        """The rounds after the slide (``slide_rounds``), each a :class:`Record` with
        ``round``, ``start``, ``local_search``, ``slid``, ``curves`` and ``folder``; empty
        without."""
        return [Record(r) for r in self.get("rounds", [])]

    @property
    def answer_round(self) -> Optional[int]:
        """With ``slide_rounds``: the slide whose network is the answer, the best of every
        slide by the objective (a later one only for a gain of more than 1e-6 relative): 0 the
        first slide, ``K`` round ``K``'s (the record is then that slide's own, and the first
        slide's run is kept in ``rounds/0/slid``); None without rounds."""
        return self.get("answer_round")


def slide(
    run: Union["Result", PathLike],
    out: Optional[PathLike] = None,
    *,
    max_move: Union[float, str, None] = None,
    fixed_ends: bool = False,
    pin: Optional[Iterable[int]] = None,
    pictures: Optional[bool] = None,
    force: bool = False,
    slide_rounds: int = 0,
) -> Result:
    """Slides the answer of a run (a :class:`Result` or its folder) on its surface to raise
    the objective (``curvenet slide``), into the run folder ``out`` (default: a new temporary
    folder), and returns the slid run (its :attr:`Result.slide` says how the curves moved).
    ``max_move``: how far a point may move, a length or ``"5%"`` of the surface's
    bounding-box diagonal (the default); ``fixed_ends`` keeps every end where it is (else
    ends on the surface's boundary slide along it); ``pin``: curves that do not move;
    ``slide_rounds``: then that many rounds, each a local search over the run's curves with
    the slid ones in place, then a slide of its network (``Slide.rounds`` lists each round's
    objectives; the last round's run is in ``out/rounds/K/slid``). Ctrl-C stops the search
    within a second, the best network so far recorded."""
    folder = run.folder if isinstance(run, Result) else Path(_path("run", run))
    # Every option is checked before anything is written (the temporary folder too).
    options = dict(
        max_move=None if max_move is None else str(max_move),
        fixed_ends=_flag("fixed_ends", fixed_ends),
        pin=_ids("pin", pin) or [],
        force=_flag("force", force),
        slide_rounds=_whole("slide_rounds", slide_rounds),
    )
    out, pictures = _out_and_pictures(out, pictures, "curvenet-slide-")
    warnings = _native.slide(os.fspath(folder), out, pictures=pictures, **options)
    result = open_run(out)
    result.warnings = list(warnings) + result.warnings
    return result


def open_run(folder: PathLike) -> Result:
    """Reads a run folder written by ``curvenet simplify``/``example`` or
    :meth:`Network.simplify`."""
    return Result(_native.Run(_path("folder", folder)))
