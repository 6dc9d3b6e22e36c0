"""Type stubs of msmcl (docs/python.md)."""

import os
from typing import Any, Literal, Mapping, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

FormatName = Literal["moments128", "msm64", "nlq64", "nlq32"]
DepthRange = Union[tuple[int, int], tuple[float, float], str]
ArrayLike = npt.ArrayLike
PathLike = Union[str, os.PathLike[str]]

class Error(Exception):
    """Base of every error msmcl raises."""

    cl_error: str | None
    """The OpenCL error name ('CL_OUT_OF_RESOURCES', ...) or None."""
    code: int | None
    """The OpenCL error code or None."""
    build_log: str | None
    """A failed program build's log, else None."""

class InputError(Error, ValueError):
    """Unusable input: bad dtype or shape, unknown format or option, a bad or missing file."""

class DeviceError(Error):
    """An OpenCL call or program build failed, or no device matches the request."""

def devices() -> list[dict[str, Any]]:
    """Every OpenCL device: index 'P:D', name, type 'gpu'|'cpu'|'other', platform, vendor,
    driver_version, opencl_version, compute_units, global_mem_bytes, local_mem_bytes,
    max_work_group_size, host_unified_memory."""

class Texture:
    """A filtered moment shadow map in host memory (or a texture array of `layers` maps)."""

    @property
    def format(self) -> FormatName: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def layers(self) -> int:
        """Array layers (1: a plain 2D map)."""
    @property
    def sigma(self) -> float: ...
    @property
    def samples(self) -> int: ...
    @property
    def depth_range(self) -> tuple[int, int]: ...
    @property
    def array(self) -> npt.NDArray[np.float32] | npt.NDArray[np.uint16] | npt.NDArray[np.uint32]:
        """A writable view of the texels (no copy): moments128 float32 (H, W, 4); msm64, nlq64
        uint16 (H, W, 4); nlq32 uint32 (H, W). A texture array has a leading axis L."""
    @property
    def words(self) -> npt.NDArray[np.uint32]:
        """The texel words, uint32 (H, W, words per texel), the same memory as .array."""
    def decode(self) -> npt.NDArray[np.float64]:
        """(H, W, 4): b1..b4 (moments128, msm64) or y1, y2, v2, xi4 (nlq64, nlq32)."""
    def layer(self, index: int) -> Texture:
        """Array layer `index` as a texture of its own (a copy)."""

class SatTable:
    """An integer modular summed-area table of moments (or a texture array of tables)."""

    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def layers(self) -> int: ...
    @property
    def max_kernel(self) -> int:
        """N: texels of the largest rectangle the table may be queried for."""
    @property
    def scale(self) -> int: ...
    @property
    def samples(self) -> int: ...
    @property
    def depth_range(self) -> tuple[int, int]: ...
    @property
    def array(self) -> npt.NDArray[np.uint32]:
        """A writable view of the table words, uint32 (H, W, 4) (no copy)."""
    def layer(self, index: int) -> SatTable: ...

class Context:
    """An OpenCL device with its queue and program cache; Python threads may share one."""

    def __init__(self, device: str | int | None = None, platform: str | int | None = None) -> None:
        """device: None (MSMCL_DEVICE, else first GPU, else first CPU), 'gpu', 'cpu', an index
        (int or 'P:D') or a substring of the device name. No match raises DeviceError."""
    @property
    def device(self) -> dict[str, Any]: ...
    @property
    def programs_built(self) -> int: ...
    def set_binary_cache_dir(self, directory: str) -> None: ...
    def finish(self) -> None: ...
    def filter(
        self,
        depth: ArrayLike,
        format: FormatName = "nlq64",
        sigma: float = 2.4,
        depth_range: DepthRange = (0, 1),
        kernel: Literal["automatic", "fused_paper", "fused_cpu", "three_pass"] = "automatic",
        layers: Sequence[tuple[ArrayLike, ArrayLike]] | None = None,
    ) -> Texture:
        """Filters a depth map (H, W) or (H, W, S) into a moment shadow map, as `msmcl filter`.
        layers: translucent occluders, (depth, opacity) pairs shaped like depth."""
    def filter_array(
        self,
        depths: ArrayLike | Sequence[ArrayLike],
        format: FormatName = "nlq64",
        sigma: float = 2.4,
        depth_range: DepthRange = (0, 1),
        kernel: Literal["automatic", "fused_paper", "fused_cpu", "three_pass"] = "automatic",
    ) -> Texture:
        """L maps (L, H, W[, S]) of one size into one texture array, as `msmcl filter --array`."""
    def shade(
        self,
        texture: Texture,
        receivers: ArrayLike,
        lookup: Literal["nearest", "bilinear", "dither"] = "bilinear",
        depth_bias: float = 1e-3,
        depth_range: DepthRange | None = None,
        frame: int = 0,
    ) -> npt.NDArray[np.float32]:
        """Shadow intensity of receivers (N, 3) or (H, W, 3) of u, v, depth; shape receivers.shape[:-1]."""
    def build_sat(
        self,
        depth: ArrayLike,
        max_kernel: int = 729,
        depth_range: DepthRange = (0, 1),
        kernel: Literal["automatic", "tiled_gpu", "tiled_cpu", "row_per_thread"] = "automatic",
        layers: Sequence[tuple[ArrayLike, ArrayLike]] | None = None,
    ) -> SatTable:
        """Summed-area table of a depth map's moments, as `msmcl sat`."""
    def build_sat_array(
        self,
        depths: ArrayLike | Sequence[ArrayLike],
        max_kernel: int = 729,
        depth_range: DepthRange = (0, 1),
        kernel: Literal["automatic", "tiled_gpu", "tiled_cpu", "row_per_thread"] = "automatic",
    ) -> SatTable:
        """Tables of L maps of one size as one texture array, as `msmcl sat --array`."""
    def soft_shade(
        self,
        table: SatTable,
        receivers: ArrayLike,
        light_size: float,
        search_size: int = 0,
        min_filter_size: float = 1.0,
        depth_bias: float = 1e-3,
        depth_range: DepthRange | None = None,
        receiver_weight: float = 0.1,
        filter_parts: int = 2,
        published: bool = False,
    ) -> npt.NDArray[np.float32]:
        """Moment soft shadows of a directional light, as `msmcl soft`."""
    def scatter(
        self,
        scene: Mapping[str, Any] | PathLike,
        shadow_map: ArrayLike,
        camera_depth: ArrayLike,
        moments: Literal[4, 6] = 6,
        filtered: bool = True,
        sigma: float = 1.0,
        beta: float | Literal["adaptive"] = "adaptive",
        kernel: Literal["automatic", "rows_gpu", "rows_cpu"] = "automatic",
        filter_kernel: Literal["automatic", "fused_paper", "fused_cpu", "three_pass"] = "automatic",
        ray_march: int = 0,
        jitter: int = 0,
    ) -> npt.NDArray[np.float32]:
        """Single-scattered radiance (camera height, camera width), as `msmcl scatter`."""

@overload
def read_depth(path: PathLike, depth_range: DepthRange = (0, 1), translucent: Literal[False] = False) -> npt.NDArray[np.float32]: ...
@overload
def read_depth(
    path: PathLike, depth_range: DepthRange = (0, 1), *, translucent: Literal[True]
) -> tuple[npt.NDArray[np.float32], list[tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]]]: ...
def write_depth(
    path: PathLike, depth: ArrayLike, layers: Sequence[tuple[ArrayLike, ArrayLike]] | None = None, half: bool = False
) -> None:
    """Writes a depth map (H, W) or (H, W, S), with translucent layers, as `msmcl filter` reads it."""
def read_receivers(path: PathLike) -> npt.NDArray[np.float32]:
    """A receivers EXR as float32 (H, W, 3) of u, v, depth."""
def write_receivers(path: PathLike, receivers: ArrayLike) -> None: ...
def read_image(path: PathLike) -> dict[str, npt.NDArray[np.float32] | npt.NDArray[np.uint32]]:
    """Every channel of an EXR file as an array of the image's shape."""
def read_texture(path: PathLike, format: FormatName | None = None, max_kernel: int | None = None) -> Texture | SatTable:
    """A filtered map or summed-area table from EXR, KTX2 or DDS, as the CLI reads it."""
def write_texture(
    path: PathLike, texture: Texture | SatTable, container: Literal["exr", "ktx2", "dds"] | None = None, array: bool = False
) -> None:
    """Writes a Texture or SatTable with the bytes `msmcl filter` / `msmcl sat` write."""
def info(path: PathLike, depth_range: DepthRange = (0, 1)) -> dict[str, Any]:
    """What `msmcl info --json` says of a file, as a dict."""
