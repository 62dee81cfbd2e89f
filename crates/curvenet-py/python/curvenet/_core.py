"""Loading, analysing and simplifying curve networks (the API of the command line)."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._errors import InputError

__all__ = [
    "Analysis",
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


def _read_curve_sources(
    curves: Union[CurveSource, Iterable[CurveSource]],
    tolerance: Optional[float],
    layer: Optional[str],
) -> Tuple[list, Optional[tuple], Optional[str], List[str], List[str]]:
    """Curve tuples, a mesh found in a .3dm (or None) and its name, the files, the warnings."""
    if _is_path(curves) or isinstance(curves, np.ndarray):
        curves = [curves]
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
                got, w = _native.read_curves(path)
                out.extend(got)
                warnings.extend(w)
        else:
            a = np.asarray(src, dtype=np.float64)
            if a.ndim != 2 or a.shape[1] != 3:
                raise InputError(
                    f"curve {len(out) + len(arrays)}: expected an (n, 3) array of points, "
                    f"got shape {a.shape}"
                )
            arrays.append(a)
    flush_arrays()
    return out, mesh, mesh_name, files, warnings


def _read_mesh(mesh: Any) -> Tuple[Optional[tuple], Optional[str], List[str]]:
    if mesh is None:
        return None, None, []
    if _is_path(mesh):
        path = os.fspath(mesh)
        if path.lower().endswith(".3dm"):
            from . import rhino

            _, m, w = rhino.read_3dm(path, curves=False)
            if m is None:
                raise InputError(f"{path}: no mesh in the file", path, None)
            return m, path, w
        m, description, w = _native.read_mesh(path)
        return m, description, w
    vertices, faces = mesh
    return (
        (np.ascontiguousarray(vertices, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int64)),
        "<arrays>",
        [],
    )


def load(
    curves: Union[CurveSource, Iterable[CurveSource]],
    mesh: Any = None,
    scale: float = 1.0,
    edge_length: Optional[float] = None,
    supports: str = "clamped",
    *,
    merge_joints: Optional[float] = None,
    radius: Optional[float] = None,
    young: Optional[float] = None,
    anchor_weight: Optional[float] = None,
    eigen_count: int = 4,
    tolerance: Optional[float] = None,
    layer: Optional[str] = None,
) -> "Network":
    """Builds the rod network of ``curves`` (``curvenet analyze``/``simplify``'s inputs).

    ``curves``: curve files (``.txt``, ``.obj``, ``.json``, ``.3dm``) and/or ``(n, 3)`` point
    arrays, in curve-id order. ``mesh``: the surface (an OBJ file, a built-in surface name, a
    ``.3dm`` holding a mesh, or ``(vertices, faces)`` arrays); a ``.3dm`` among the curves
    gives its mesh when ``mesh`` is not given. ``scale`` multiplies everything;
    ``edge_length`` is the resampling length ``h`` after scaling (default: the median input
    segment). ``tolerance`` is how far NURBS curves of a ``.3dm`` may be from their sampled
    polylines (default: 1e-3 × each curve's bounding-box diagonal); ``layer`` keeps only the
    ``.3dm`` objects on that layer (full path, e.g. ``"curvenet::kept"``) and its sub-layers.

    Raises :class:`curvenet.InputError` with the command line's message (file and line).
    """
    tuples, found_mesh, found_name, files, warnings = _read_curve_sources(curves, tolerance, layer)
    m, mesh_name, w = _read_mesh(mesh)
    warnings.extend(w)
    if m is None and found_mesh is not None:
        m, mesh_name = found_mesh, found_name
    native = _native.Network(
        tuples,
        mesh=m,
        mesh_name=mesh_name,
        scale=scale,
        edge_length=edge_length,
        supports=supports,
        merge_joints=merge_joints,
        radius=radius,
        young=young,
        anchor_weight=anchor_weight,
        eigen_count=eigen_count,
        warnings=warnings,
        curve_files=files,
    )
    return Network(native)


def example_names() -> List[str]:
    """The names of the paper's examples (``curvenet example NAME``)."""
    return list(_native.example_names())


def example(
    name: str,
    supports: Optional[str] = None,
    *,
    data: Optional[PathLike] = None,
    merge_joints: Optional[float] = None,
    radius: Optional[float] = None,
    young: Optional[float] = None,
    anchor_weight: Optional[float] = None,
    eigen_count: int = 4,
) -> "Network":
    """The paper's example ``name`` (``roof``, ``tower``, ...; see :func:`example_names`) with
    its set-up: the network, and as :meth:`Network.simplify`'s defaults its budget and keep
    list. ``data`` names a folder with the paper's ``meshes/`` and ``curves/``."""
    ex = _native.example(name, supports or "clamped", None if data is None else os.fspath(data))
    vertices, faces = ex["mesh"]
    native = _native.Network(
        ex["curves"],
        mesh=(vertices, np.asarray(faces, dtype=np.int64)),
        mesh_name=ex["mesh_file"],
        scale=1.0,
        edge_length=ex["edge_length"],
        supports=ex["supports"],
        merge_joints=merge_joints,
        radius=radius,
        young=young,
        anchor_weight=anchor_weight,
        eigen_count=eigen_count,
        warnings=list(ex["warnings"]),
        example=ex["name"],
        curve_files=list(ex["curve_files"]),
    )
    net = Network(native, budget=ex["budget"], keep=list(ex["keep"]))
    net.paper = json.loads(ex["paper"])
    # The run records the example's scale (as `curvenet example` does).
    net._description_scale = ex["scale"]
    return net


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

    def __repr__(self) -> str:
        state = "" if self.stable else (
            f", UNSTABLE: {self.zero_modes} zero and {self.negative_modes} negative mode(s)"
        )
        return f"<curvenet.Analysis lambda_eq={self.lambda_eq:.6e}{state}>"


class Network:
    """A rod network built from curves (see :func:`load`, :func:`example`)."""

    def __init__(self, native: "_native.Network", budget: Optional[float] = None,
                 keep: Optional[List[int]] = None):
        self._native = native
        self.default_budget = budget
        """The example's budget fraction (None for :func:`load`)."""
        self.default_keep = keep or []
        """The example's keep list."""
        self.paper: Optional[Dict[str, Any]] = None
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
        ``λ_eq``, the smallest eigenvalues, the worst-case mode (``curvenet analyze``)."""
        raw = self._native.analyze(sorted(set(int(c) for c in remove)))
        return Analysis(raw, self.positions)

    def simplify(
        self,
        budget: Optional[float] = None,
        *,
        budget_length: Optional[float] = None,
        keep: Optional[Iterable[int]] = None,
        local_search: bool = False,
        out: Optional[PathLike] = None,
        resume: bool = False,
        force: bool = False,
        pictures: Optional[bool] = None,
        progress: Optional[Callable[["Iteration"], Any]] = None,
    ) -> "Result":
        """Runs the greedy (``curvenet simplify``) down to ``budget`` (a fraction of the total
        rest length) or ``budget_length`` (a length), never removing ``keep``.

        The run is written to the folder ``out`` exactly as the command line writes it
        (default: a new temporary folder), so :func:`open_run` reads it again and
        ``resume=True`` continues an interrupted run. As on the command line, another run
        writing in ``out`` meanwhile is refused, a fresh run into an earlier run's folder
        removes that run's files first, and a non-empty folder that is not a curvenet run's is
        refused unless ``force=True``. ``pictures`` writes the pictures and the
        viewer page (default: when ``out`` is given). ``progress(iteration)`` is called after
        each iteration; an exception it raises stops the run, as does Ctrl-C
        (``KeyboardInterrupt``), within a fraction of a second, keeping what was recorded.
        ``local_search=True`` also runs the local search from the greedy's final network and
        from the best single curves.
        """
        if budget is None and budget_length is None:
            budget = self.default_budget
        if keep is None:
            keep = self.default_keep
        if out is None:
            out = tempfile.mkdtemp(prefix="curvenet-run-")
            if pictures is None:
                pictures = False
        if pictures is None:
            pictures = True
        cb = None
        if progress is not None:
            def cb(text: str) -> None:
                progress(Iteration(json.loads(text)))
        warnings = self._native.simplify(
            os.fspath(out),
            budget=budget,
            budget_length=budget_length,
            keep=[int(c) for c in keep],
            local_search=local_search,
            pictures=pictures,
            resume=resume,
            force=force,
            progress=cb,
        )
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
        """The curves of the last recorded network."""
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
    def answer(self) -> Optional[Dict[str, Any]]:
        """The network to build when the run chose one (``result.json``'s ``answer``);
        otherwise the final network's record."""
        return self.result.get("answer") or self.result.get("final")

    @property
    def alternatives(self) -> List[Dict[str, Any]]:
        return list(self.result.get("alternatives", []))

    @property
    def local_search(self) -> Optional[Dict[str, Any]]:
        return self.result.get("local_search")

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
        return len(self.iterations) - 1 if iteration is None else int(iteration)

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
        curves = [int(c) for c in curves]
        if state == "rest":
            return self._native.polylines(curves, None)
        if state == "equilibrium":
            return self._native.polylines(curves, self.displacement(iteration))
        raise InputError(f"unknown state '{state}' (expected rest or equilibrium)")

    def export(self, out: Optional[PathLike] = None, format: str = "all",
               iteration: Optional[int] = None) -> List[Path]:
        """Writes an iteration's network (default: the last) as ``curvenet export`` does:
        ``format`` is ``obj``, ``json``, ``csv``, ``network`` or ``all``; ``out`` a folder
        (default: ``export/`` in the run folder). Returns the paths written."""
        folder = self.folder / "export" if out is None else Path(out)
        return [Path(p) for p in self._native.export(os.fspath(folder), format, self._k(iteration))]

    def write_3dm(self, path: PathLike, iteration: Optional[int] = None,
                  mode_scale: Optional[float] = None) -> Path:
        """Writes a Rhino file: kept and removed curves (designed shapes), the kept curves at
        equilibrium and displaced along the worst-case mode, and the surface, on layers
        under ``curvenet`` (see :mod:`curvenet.rhino`)."""
        from . import rhino

        return rhino.write_3dm(self, path, iteration=iteration, mode_scale=mode_scale)

    def __repr__(self) -> str:
        last = self.iterations[-1]
        state = "" if last.stable else ", UNSTABLE"
        return (f"<curvenet.Result {len(self.removed_curves)} removed, "
                f"{len(last['curves'])} curves left, lambda_eq={last['lambda']:.6e}{state}, "
                f"stop={self.stop}, folder={str(self.folder)!r}>")


def open_run(folder: PathLike) -> Result:
    """Reads a run folder written by ``curvenet simplify``/``example`` or
    :meth:`Network.simplify`."""
    return Result(_native.Run(os.fspath(folder)))
