# Type stub of the compiled module, for editors and type checkers. The model
# keywords are the command line's options (tristereo.model_options() lists
# them with their defaults and ranges); a keyword left out takes the default
# of the chosen mode. python/tests/test_stub.py checks this file against the
# module's table, so a keyword added there and forgotten here fails the tests.
import os
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
INVALID_DISP_Q4: int

_Path = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]
_Size = Union[int, Tuple[int, int], str]
_Order = Optional[Literal["bgr", "rgb", "gray"]]
_Gap = Literal["inv_sq", "inv", "const"]

class Output:
    """What one frame produced: the caller's own arrays, unchanged by later frames
    (unless passed back as process(..., out=...), which refills them)."""
    disparity: npt.NDArray[np.float32]
    disp_q4: npt.NDArray[np.int16]
    vertices: npt.NDArray[np.int32]
    triangles: npt.NDArray[np.int32]
    vertex_disp_q4: npt.NDArray[np.int16]
    state: npt.NDArray[np.uint8]
    confidence: npt.NDArray[np.uint8]
    vertex_state: npt.NDArray[np.uint8]
    vertex_confidence: npt.NDArray[np.uint8]
    timings_ms: Dict[str, float]
    forced_splits: int
    criterion_splits: int
    samples: int
    uniqueness_rejected: int
    lr_rejected: int
    prior_redecided: int
    prior_recovered: int
    prior_lost: int
    filled: int
    min_confidence_rejected: int
    digest: str

class Pipeline:
    """Configure once (all memory allocated, workers started), then process() per frame."""
    def __init__(
        self,
        max_width: int,
        max_height: int,
        ndisp: int,
        *,
        mode: Literal["default", "paper"] = ...,
        dmin: int = ...,
        psnr: float = ...,
        max_area: int = ...,
        min_area: int = ...,
        window: _Size = ...,
        weights: Literal["box", "adaptive"] = ...,
        gamma_color: int = ...,
        gamma_proximity: int = ...,
        truncation: int = ...,
        lambda_q4: int = ...,
        gap: _Gap = ...,
        cost: Literal["ad", "census", "ad_census"] = ...,
        census: _Size = ...,
        ad_weight: int = ...,
        optimizer: Literal["paths", "dp"] = ...,
        paths: Literal[4, 8] = ...,
        p1: int = ...,
        p2: int = ...,
        p2_edge: int = ...,
        path_gap: _Gap = ...,
        lr_max_diff: int = ...,
        lr_source: Literal["costs", "mirror"] = ...,
        uniqueness: int = ...,
        fill: Literal["background", "none"] = ...,
        min_confidence: int = ...,
        support_prior: int = ...,
        support_trunc: int = ...,
        support_conf: int = ...,
        support_uniqueness: int = ...,
        plane_seg_fine: int = ...,
        plane_seg_coarse: int = ...,
        plane_min: int = ...,
        plane_tol: int = ...,
        edge_spread: int = ...,
        subpixel: bool = ...,
        subpixel_fit: Literal["parabola", "equiangular"] = ...,
        dense: bool = ...,
        threads: int = ...,
        kernels: Literal["auto", "scalar", "sse2", "avx2", "neon"] = ...,
        cpus: Union[Sequence[int], str] = ...,
        pin: bool = ...,
    ) -> None: ...
    def process(
        self,
        left: npt.NDArray[np.uint8],
        right: npt.NDArray[np.uint8],
        order: _Order = None,
        out: Optional[Output] = None,
    ) -> Output: ...
    @property
    def kernels(self) -> str: ...
    @property
    def threads(self) -> int: ...
    @property
    def params(self) -> Dict[str, Any]: ...
    @property
    def working_memory_bytes(self) -> int: ...

class VerifyReport:
    bit_exact: bool
    reference_digest: str
    @property
    def cases(self) -> List[Dict[str, Any]]: ...

def verify(
    left: npt.NDArray[np.uint8],
    right: npt.NDArray[np.uint8],
    ndisp: int,
    thread_counts: Sequence[int] = ...,
    order: _Order = None,
    *,
    mode: Literal["default", "paper"] = ...,
    dmin: int = ...,
    psnr: float = ...,
    max_area: int = ...,
    min_area: int = ...,
    window: _Size = ...,
    weights: Literal["box", "adaptive"] = ...,
    gamma_color: int = ...,
    gamma_proximity: int = ...,
    truncation: int = ...,
    lambda_q4: int = ...,
    gap: _Gap = ...,
    cost: Literal["ad", "census", "ad_census"] = ...,
    census: _Size = ...,
    ad_weight: int = ...,
    optimizer: Literal["paths", "dp"] = ...,
    paths: Literal[4, 8] = ...,
    p1: int = ...,
    p2: int = ...,
    p2_edge: int = ...,
    path_gap: _Gap = ...,
    lr_max_diff: int = ...,
    lr_source: Literal["costs", "mirror"] = ...,
    uniqueness: int = ...,
    fill: Literal["background", "none"] = ...,
    min_confidence: int = ...,
    support_prior: int = ...,
    support_trunc: int = ...,
    support_conf: int = ...,
    support_uniqueness: int = ...,
    plane_seg_fine: int = ...,
    plane_seg_coarse: int = ...,
    plane_min: int = ...,
    plane_tol: int = ...,
    edge_spread: int = ...,
    subpixel: bool = ...,
    subpixel_fit: Literal["parabola", "equiangular"] = ...,
    dense: bool = ...,
) -> VerifyReport: ...

_Camera = Union["Calibration", Tuple[float, float, float, float], Tuple[float, float, float, float, float]]

def model_options() -> List[Dict[str, Any]]: ...
def depth(
    disp_q4: npt.NDArray[np.int16],
    camera: _Camera,
    min_disparity: float = 2.0,
    min_depth: float = 0.0,
    max_depth: float = 0.0,
) -> npt.NDArray[np.float32]: ...
def write_disparity(path: _Path, disp_q4: npt.NDArray[np.int16], png_scale: Literal["q4", "kitti"] = "q4") -> None: ...
def write_disparity_color(path: _Path, disp_q4: npt.NDArray[np.int16], dmin: int, ndisp: int) -> None: ...
def write_depth(path: _Path, depth_m: npt.NDArray[np.floating[Any]]) -> Dict[str, int]: ...
def write_mesh_ply(
    path: _Path,
    out: Output,
    left: npt.NDArray[np.uint8],
    camera: Optional[_Camera] = None,
    binary: bool = True,
    order: _Order = None,
    include_filled: bool = False,
    min_disparity: float = 2.0,
    min_depth: float = 0.0,
    max_depth: float = 0.0,
) -> Dict[str, int]: ...
def write_points_ply(
    path: _Path,
    disp_q4: npt.NDArray[np.int16],
    left: npt.NDArray[np.uint8],
    camera: _Camera,
    binary: bool = True,
    order: _Order = None,
    state: Optional[npt.NDArray[np.uint8]] = None,
    min_disparity: float = 2.0,
    min_depth: float = 0.0,
    max_depth: float = 0.0,
) -> int: ...
def read_image(path: _Path) -> npt.NDArray[np.uint8]: ...

class Calibration:
    focal_px: float
    baseline_m: float
    cx_px: float
    cy_px: float
    doffs_px: float
    width: int
    height: int
    path: str
    @property
    def format(self) -> str: ...

def read_calibration(path: _Path, format: str = "auto", unit_m: float = 1.0) -> Calibration: ...
