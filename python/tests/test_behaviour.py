"""The module's own promises (docs/python.md): views without copies, one conversion of other
dtypes and strides, threads sharing a Context, the documented exceptions, lifetimes."""

import concurrent.futures
import gc
import json

import numpy as np
import pytest

import msmcl
from conftest import DATA, FORMATS, RAILING, RAILING_VIEW, random_depth


@pytest.mark.parametrize("format, dtype, shape", [
    ("vsm32", np.uint16, (24, 40, 2)), ("vsm64", np.float32, (24, 40, 2)), ("evsm2_32", np.float16, (24, 40, 2)),
    ("evsm4_64", np.float16, (24, 40, 4)), ("evsm4_128", np.float32, (24, 40, 4)), ("esm32", np.float32, (24, 40))])
def test_filterable_texture_arrays_are_their_channels(ctx, rng, format, dtype, shape):
    # The VSM, EVSM and ESM formats: each channel in its storage type, viewing the texel words.
    texture = ctx.filter(random_depth(rng, 24, 40), format=format)
    view = texture.array
    assert (view.dtype, view.shape) == (np.dtype(dtype), shape)
    assert view.nbytes == texture.words.nbytes and np.shares_memory(view, texture.words)
    # The first channel (a filtered warp or moment) is finite everywhere.
    first = view[..., 0] if view.ndim == 3 else view
    assert np.all(np.isfinite(first.astype(np.float64)))


def test_devices_and_context(ctx):
    devices = msmcl.devices()
    assert devices, "no OpenCL device"
    assert {"index", "name", "type", "platform", "driver_version"} <= set(devices[0])
    assert ctx.device["name"] in [d["name"] for d in devices]
    assert msmcl.Context(ctx.device["index"]).device["index"] == ctx.device["index"]


@pytest.mark.parametrize("format", FORMATS)
def test_texture_arrays_are_views_of_the_texture(ctx, rng, format):
    texture = ctx.filter(random_depth(rng, 24, 40), format=format)
    view = texture.array
    expected = {"moments128": (np.float32, (24, 40, 4)), "msm64": (np.uint16, (24, 40, 4)),
                "nlq64": (np.uint16, (24, 40, 4)), "nlq32": (np.uint32, (24, 40))}[format]
    assert (view.dtype, view.shape) == (np.dtype(expected[0]), expected[1])
    assert view.flags["C_CONTIGUOUS"] and not view.flags["OWNDATA"]
    # Every view is of the one buffer: .array twice, and .words, share their first byte.
    assert np.shares_memory(view, texture.array) and np.shares_memory(view, texture.words)
    assert view.__array_interface__["data"][0] == texture.words.__array_interface__["data"][0]
    # A change through one view is a change of the texture, seen by the other views and decode().
    decoded = texture.decode()
    texture.words[0, 0, :] = 0
    assert not np.any(view[0, 0]) and not np.any(texture.array[0, 0])
    assert np.array_equal(texture.decode()[1:], decoded[1:])
    table = ctx.build_sat(random_depth(rng, 16, 16))
    assert table.array.shape == (16, 16, 4) and not table.array.flags["OWNDATA"]
    assert np.shares_memory(table.array, table.array)


def test_decode_gives_the_moments(ctx, rng):
    depth = random_depth(rng, 32, 32)
    moments = ctx.filter(depth, format="moments128")
    np.testing.assert_array_equal(moments.decode(), moments.array.astype(np.float64))
    # Unblurred, one sample: b1 is the internal depth 2d - 1 of each texel.
    sharp = ctx.filter(depth, format="moments128", sigma=0)
    np.testing.assert_allclose(sharp.decode()[:, :, 0], 2.0 * depth - 1.0, atol=1e-6)
    y = ctx.filter(depth, format="nlq64").decode()
    assert y.shape == (32, 32, 4) and y.dtype == np.float64
    assert np.all((y[:, :, 0] >= -1) & (y[:, :, 0] <= y[:, :, 1] + 1e-6) & (y[:, :, 1] <= 1))


def test_other_dtypes_and_strides_are_converted_once(ctx, rng):
    depth = random_depth(rng, 30, 50, samples=2)
    reference = ctx.filter(depth, format="msm64").words
    for variant in [depth.astype(np.float64), depth.astype(np.float16).astype(np.float64),
                    np.asfortranarray(depth), depth[::-1][::-1], depth.tolist()]:
        expected = ctx.filter(np.asarray(variant, dtype=np.float32), format="msm64").words
        np.testing.assert_array_equal(ctx.filter(variant, format="msm64").words, expected)
    np.testing.assert_array_equal(ctx.filter(np.asfortranarray(depth), format="msm64").words, reference)
    # A strided view (every other column) is filtered as its contiguous copy.
    wide = random_depth(rng, 30, 100)
    np.testing.assert_array_equal(ctx.filter(wide[:, ::2], format="nlq32").words,
                                  ctx.filter(np.ascontiguousarray(wide[:, ::2]), format="nlq32").words)
    # Receivers in float64, reversed rows.
    texture = ctx.filter(depth)
    receivers = msmcl.read_receivers(RAILING_VIEW)[:, :, :].astype(np.float64)
    np.testing.assert_array_equal(ctx.shade(texture, receivers[::-1]),
                                  ctx.shade(texture, np.ascontiguousarray(receivers[::-1], dtype=np.float32)))


def test_four_threads_sharing_a_context_give_single_threaded_results(ctx, rng):
    maps = [random_depth(rng, 64 + 8 * i, 80, samples=[1, 2, 4, 8][i % 4]) for i in range(8)]
    receivers = np.stack(np.meshgrid(np.linspace(0, 80, 40), np.linspace(0, 64, 30)), axis=2)
    receivers = np.concatenate([receivers, np.full(receivers.shape[:2] + (1,), 0.5)], axis=2).astype(np.float32)

    def work(job):
        depth, format = job
        texture = ctx.filter(depth, format=format)
        table = ctx.build_sat(depth)
        return (texture.words.copy(), ctx.shade(texture, receivers, lookup="dither", frame=1), table.array.copy(),
                ctx.soft_shade(table, receivers, light_size=20))

    jobs = [(depth, FORMATS[i % 4]) for i, depth in enumerate(maps)] * 2
    alone = [work(job) for job in jobs]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        together = list(pool.map(work, jobs))
    for job, (a, b) in enumerate(zip(alone, together)):
        for part, (x, y) in enumerate(zip(a, b)):
            np.testing.assert_array_equal(x, y, err_msg=f"job {job}, result {part}")


def test_bad_dtype_shape_format_and_file_raise_input_error(ctx, rng, tmp_path):
    assert issubclass(msmcl.InputError, msmcl.Error) and issubclass(msmcl.InputError, ValueError)
    assert issubclass(msmcl.DeviceError, msmcl.Error) and issubclass(msmcl.Error, Exception)
    depth = random_depth(rng, 16, 16)
    with pytest.raises(msmcl.InputError, match=r"float32 array of shape \(H, W\) or \(H, W, S\).*complex128 of shape \(16, 16\)"):
        ctx.filter(depth.astype(np.complex128))
    with pytest.raises(msmcl.InputError, match=r"float32 array .*<U1 of shape \(2,\)"):
        ctx.filter(["a", "b"])
    with pytest.raises(msmcl.InputError, match=r"got float32 of shape \(256,\)"):
        ctx.filter(depth.reshape(-1))
    with pytest.raises(msmcl.InputError, match="unsupported sample count 3"):
        ctx.filter(np.stack([depth] * 3, axis=2))  # 3 samples per texel
    with pytest.raises(msmcl.InputError, match=r"receivers .*\(N, 3\) or \(H, W, 3\).*shape \(4, 2\)"):
        ctx.shade(ctx.filter(depth), np.zeros((4, 2), np.float32))
    with pytest.raises(msmcl.InputError, match="unknown format 'nlq16'"):
        ctx.filter(depth, format="nlq16")
    with pytest.raises(msmcl.InputError, match="unknown lookup"):
        ctx.shade(ctx.filter(depth), np.zeros((4, 3), np.float32), lookup="trilinear")
    with pytest.raises(msmcl.InputError, match="depth_range"):
        ctx.filter(depth, depth_range=(0, 2))
    with pytest.raises(msmcl.InputError, match="outside the depth range"):
        ctx.filter(depth + 2)  # depths outside [0, 1]
    with pytest.raises(msmcl.InputError, match="missing.exr"):
        msmcl.read_depth(tmp_path / "missing.exr")
    (tmp_path / "bad.exr").write_bytes(b"not an image")
    with pytest.raises(msmcl.InputError, match="bad.exr") as caught:
        msmcl.read_texture(tmp_path / "bad.exr")
    assert caught.value.cl_error is None and caught.value.code is None
    with pytest.raises(msmcl.InputError, match="extension"):
        msmcl.write_texture(tmp_path / "out.png", ctx.filter(depth))
    with pytest.raises(msmcl.InputError, match="key"):
        ctx.scatter({"light": {}}, depth, depth)
    assert not (tmp_path / "out.png").exists()


def test_a_device_that_matches_nothing_raises_device_error():
    with pytest.raises(msmcl.DeviceError) as caught:
        msmcl.Context("no such device anywhere")
    assert isinstance(caught.value, msmcl.Error) and caught.value.cl_error is None


def test_textures_and_views_outlive_their_context(rng):
    depth = random_depth(rng, 40, 40, samples=4)
    receivers = msmcl.read_receivers(RAILING_VIEW)
    context = msmcl.Context()
    texture = context.filter(depth, format="nlq32")
    shadow = context.shade(texture, receivers)
    words = texture.words.copy()
    del context
    gc.collect()
    # The texture is host memory of its own; a new Context shades it as the first did.
    np.testing.assert_array_equal(texture.words, words)
    np.testing.assert_array_equal(msmcl.Context().shade(texture, receivers), shadow)
    # A view keeps its texture alive.
    view = texture.array
    del texture
    gc.collect()
    np.testing.assert_array_equal(view, words[:, :, 0])


def test_docstrings_and_stub(ctx):
    assert "depth_range" in msmcl.Context.filter.__doc__ and "Texture" in msmcl.Context.filter.__doc__
    assert msmcl.Texture.__module__ == "msmcl" and msmcl.Context.__module__ == "msmcl"
    import importlib.resources

    stub = importlib.resources.files("msmcl").joinpath("__init__.pyi").read_text()
    for name in msmcl.__all__:
        assert name in stub, name
    assert repr(ctx).startswith("<msmcl.Context ")


def test_read_texture_tells_maps_from_tables(ctx, tmp_path):
    depth = msmcl.read_depth(RAILING)
    msmcl.write_texture(tmp_path / "t.exr", ctx.build_sat(depth, max_kernel=100))
    table = msmcl.read_texture(tmp_path / "t.exr")
    assert isinstance(table, msmcl.SatTable) and table.max_kernel == 100
    msmcl.write_texture(tmp_path / "m.dds", ctx.filter(depth, format="msm64"))
    with pytest.raises(msmcl.InputError, match="--format"):
        msmcl.read_texture(tmp_path / "m.dds")
    assert msmcl.read_texture(tmp_path / "m.dds", format="msm64").format == "msm64"
    info = msmcl.info(tmp_path / "m.dds")
    assert info["kind"] == "moment shadow map" and json.dumps(info)
