# Type stubs of the native module (crates/curvenet-py/src). Private: use the package's API.
from os import PathLike
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

CurveTuple = Tuple[npt.NDArray[np.float64], bool, Optional[str], str, int]
MeshTuple = Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]
_Path = Union[str, PathLike[str]]

def read_curves(path: _Path) -> Tuple[List[CurveTuple], List[str]]: ...
def curves_from_arrays(
    file: str,
    arrays: Sequence[npt.NDArray[np.float64]],
    closed: Sequence[Optional[bool]],
    labels: Sequence[Optional[str]],
    lines: Sequence[int],
) -> Tuple[List[CurveTuple], List[str]]: ...
def read_mesh(path: _Path) -> Tuple[MeshTuple, str, List[str]]: ...
def example_names() -> List[str]: ...
class Network:
    def __init__(
        self,
        sources: List[Union[str, CurveTuple]],
        mesh: Union[str, Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], str], None] = None,
        scale: float = 1.0,
        edge_length: Optional[float] = None,
        supports: Optional[str] = None,
        merge_joints: Optional[float] = None,
        radius: Optional[float] = None,
        young: Optional[str] = None,
        anchor_weight: Optional[float] = None,
        eigen_count: int = 4,
        objective: str = "lambda",
        units: Optional[str] = None,
        material: Optional[str] = None,
        density: Optional[str] = None,
        strength: Optional[str] = None,
        tube: Optional[str] = None,
        load: Optional[str] = None,
        gravity: Optional[str] = None,
        loads: Optional[_Path] = None,
        deflection_limit: Optional[str] = None,
        buckling_factor: Optional[str] = None,
        supports_file: Optional[_Path] = None,
        warnings: List[str] = ...,
        example: Optional[str] = None,
        data: Optional[_Path] = None,
    ) -> None: ...
    @property
    def example(self) -> Optional[Tuple[float, List[int], str]]: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def rods(self) -> List[npt.NDArray[np.uint32]]: ...
    @property
    def closed(self) -> List[bool]: ...
    @property
    def anchors(self) -> List[npt.NDArray[np.uint32]]: ...
    @property
    def rest_lengths(self) -> npt.NDArray[np.float64]: ...
    @property
    def joints(self) -> List[Tuple[int, List[int]]]: ...
    @property
    def edge_length(self) -> float: ...
    @property
    def supports(self) -> str: ...
    @property
    def curves(self) -> List[CurveTuple]: ...
    @property
    def mesh(self) -> Optional[MeshTuple]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def build_info(self) -> str: ...
    def analyze(self, remove: List[int] = ...) -> Dict[str, object]: ...
    def simplify(
        self,
        out: _Path,
        budget: Optional[float] = None,
        budget_length: Optional[float] = None,
        keep: Optional[List[int]] = None,
        groups_file: Optional[_Path] = None,
        groups: List[List[int]] = ...,
        symmetry: Optional[str] = None,
        connected: bool = False,
        min_curves: Optional[int] = None,
        max_gap: Optional[float] = None,
        max_deviation: Optional[float] = None,
        local_search: bool = False,
        alternatives: int = 0,
        certify: bool = False,
        certificate_nodes: Optional[int] = None,
        pictures: bool = True,
        resume: bool = False,
        force: bool = False,
        progress: Optional[Callable[[str], object]] = None,
        slide: bool = False,
        max_move: Optional[str] = None,
        fixed_ends: bool = False,
        pin: List[int] = ...,
    ) -> List[str]: ...

def slide(
    from_: _Path,
    out: _Path,
    max_move: Optional[str] = None,
    fixed_ends: bool = False,
    pin: List[int] = ...,
    pictures: bool = True,
    force: bool = False,
) -> List[str]: ...

class Run:
    def __init__(self, dir: _Path) -> None: ...
    @property
    def dir(self) -> str: ...
    @property
    def result_json(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def curve_count(self) -> int: ...
    def displacement(self, k: Optional[int] = None) -> npt.NDArray[np.float64]: ...
    def mode(self, k: Optional[int] = None) -> npt.NDArray[np.float64]: ...
    def polylines(
        self, curves: List[int], u: Optional[npt.NDArray[np.float64]] = None
    ) -> List[Tuple[npt.NDArray[np.float64], bool]]: ...
    def export(self, out: _Path, format: str = "all", k: Optional[int] = None) -> List[str]: ...
    def export_text(self, format: str, k: Optional[int] = None) -> Tuple[str, str]: ...
