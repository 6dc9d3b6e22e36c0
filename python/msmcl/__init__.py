"""msmcl: moment shadow maps on OpenCL, numpy arrays in and out.

Filter depth maps into moment shadow maps (moments128, msm64, nlq64, nlq32), shade receivers,
build summed-area tables for soft shadows, render single scattering, and read and write the
files of the ``msmcl`` command line with the same bytes. See docs/python.md.

    import msmcl
    ctx = msmcl.Context()                       # or Context("cpu"), Context("gpu"), Context(0)
    depth = msmcl.read_depth("map.exr")         # float32 (H, W) or (H, W, S)
    texture = ctx.filter(depth, format="nlq64") # msmcl.Texture; texture.array is a view
    shadow = ctx.shade(texture, msmcl.read_receivers("view.exr"))
    msmcl.write_texture("map.ktx2", texture)
"""

from ._msmcl import (
    Context,
    DeviceError,
    Error,
    InputError,
    SatTable,
    Texture,
    __version__,
    devices,
    info,
    read_depth,
    read_image,
    read_receivers,
    read_texture,
    write_depth,
    write_receivers,
    write_texture,
)

__all__ = [
    "Context",
    "DeviceError",
    "Error",
    "InputError",
    "SatTable",
    "Texture",
    "__version__",
    "devices",
    "info",
    "read_depth",
    "read_image",
    "read_receivers",
    "read_texture",
    "write_depth",
    "write_receivers",
    "write_texture",
]

