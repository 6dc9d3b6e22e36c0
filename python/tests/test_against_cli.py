"""The module gives what the CLI gives: the same file bytes for every format and container,
the same shading, tables, soft shadows, scattering and `info` (exact equality throughout:
both run the same library code on the same device)."""

import json

import numpy as np
import pytest

import msmcl
from conftest import DATA, FORMATS, RAILING, RAILING_VIEW, cli, random_depth


@pytest.mark.parametrize("format", FORMATS)
def test_texture_files_equal_the_cli_bytes(ctx, tmp_path, format):
    depth = msmcl.read_depth(RAILING)
    assert depth.shape == (256, 256, 4) and depth.dtype == np.float32
    texture = ctx.filter(depth, format=format)
    assert (texture.format, texture.width, texture.height, texture.samples) == (format, 256, 256, 4)
    for container in ["exr", "ktx2", "dds"]:
        cli("filter", RAILING, tmp_path / f"cli.{container}", "--format", format)
        msmcl.write_texture(tmp_path / f"py.{container}", texture)
        assert (tmp_path / f"py.{container}").read_bytes() == (tmp_path / f"cli.{container}").read_bytes(), container
    # And back: the CLI's file reads as the same texels.
    read = msmcl.read_texture(tmp_path / "cli.ktx2")
    assert read.format == format and np.array_equal(read.array, texture.array)
    assert read.sigma == pytest.approx(2.4) and read.depth_range == (0, 1)


def test_random_maps_with_options_equal_the_cli_bytes(ctx, tmp_path, rng):
    # One sample, sigma 1.5, depth range -1,1, written by the module and filtered by both.
    depth = random_depth(rng, 75, 93) * 2 - 1
    msmcl.write_depth(tmp_path / "depth.exr", depth)
    assert np.array_equal(msmcl.read_depth(tmp_path / "depth.exr", depth_range=(-1, 1)), depth)
    for format in FORMATS:
        cli("filter", tmp_path / "depth.exr", tmp_path / "cli.exr", "--format", format, "--sigma", "1.5",
            "--depth-range=-1,1")
        texture = ctx.filter(depth, format=format, sigma=1.5, depth_range=(-1, 1))
        msmcl.write_texture(tmp_path / "py.exr", texture)
        assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes(), format


def test_translucent_layers_equal_the_cli_bytes(ctx, tmp_path, rng):
    depth = random_depth(rng, 40, 48, samples=2)
    layer = (np.clip(depth * 0.5, 0, 1), rng.uniform(0, 1, depth.shape).astype(np.float32))
    # The CLI reads the layers from the channels layer<k>.sample<s>.Z and .A.
    msmcl.write_depth(tmp_path / "layered.exr", depth, layers=[layer])
    read_depth, read_layers = msmcl.read_depth(tmp_path / "layered.exr", translucent=True)
    assert np.array_equal(read_depth, depth) and len(read_layers) == 1
    assert np.array_equal(read_layers[0][0], layer[0]) and np.array_equal(read_layers[0][1], layer[1])
    for format in ["moments128", "nlq64"]:
        cli("filter", tmp_path / "layered.exr", tmp_path / "cli.exr", "--format", format)
        msmcl.write_texture(tmp_path / "py.exr", ctx.filter(depth, format=format, layers=[layer]))
        assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes(), format


@pytest.mark.parametrize("format", FORMATS)
def test_shading_equals_msmcl_shade(ctx, tmp_path, format):
    cli("filter", RAILING, tmp_path / "map.ktx2", "--format", format)
    texture = msmcl.read_texture(tmp_path / "map.ktx2")
    receivers = msmcl.read_receivers(RAILING_VIEW)
    assert receivers.shape == (120, 160, 3)
    for lookup in ["nearest", "bilinear", "dither"]:
        cli("shade", tmp_path / "map.ktx2", RAILING_VIEW, tmp_path / "shadow.exr", "--lookup", lookup, "--frame", "3")
        expected = msmcl.read_image(tmp_path / "shadow.exr")["Y"]
        shadow = ctx.shade(texture, receivers, lookup=lookup, frame=3)
        assert shadow.shape == (120, 160) and shadow.dtype == np.float32
        np.testing.assert_array_equal(shadow, expected, err_msg=lookup)
    # A flat list of receivers gives the same intensities (but for dither, whose pixels differ).
    flat = ctx.shade(texture, receivers.reshape(-1, 3), lookup="bilinear")
    np.testing.assert_array_equal(flat, ctx.shade(texture, receivers).reshape(-1))


def test_sat_and_soft_shadows_equal_the_cli(ctx, tmp_path):
    cli("sat", RAILING, tmp_path / "cli.ktx2", "--max-kernel", "729")
    table = ctx.build_sat(msmcl.read_depth(RAILING), max_kernel=729)
    assert (table.width, table.height, table.max_kernel, table.samples) == (256, 256, 729, 4)
    for container in ["exr", "ktx2"]:
        if container != "ktx2":
            cli("sat", RAILING, tmp_path / f"cli.{container}", "--max-kernel", "729")
        msmcl.write_texture(tmp_path / f"py.{container}", table)
        assert (tmp_path / f"py.{container}").read_bytes() == (tmp_path / f"cli.{container}").read_bytes()
    receivers = msmcl.read_receivers(RAILING_VIEW)
    for options, flags in [({}, []), ({"published": True}, ["--published"]),
                           ({"search_size": 9, "depth_bias": 2e-3}, ["--search-size", "9", "--depth-bias", "2e-3"])]:
        cli("soft", tmp_path / "cli.ktx2", RAILING_VIEW, tmp_path / "soft.exr", "--light-size", "40", *flags)
        soft = ctx.soft_shade(msmcl.read_texture(tmp_path / "cli.ktx2"), receivers, light_size=40, **options)
        np.testing.assert_array_equal(soft, msmcl.read_image(tmp_path / "soft.exr")["Y"], err_msg=str(flags))


def scatter_inputs(rng, scene):
    """A random light depth map (160^2, 2 samples) and a camera depth buffer away from the near plane."""
    shadow_map = random_depth(rng, 160, 160, samples=2)
    camera = scene["camera"]
    camera_depth = rng.uniform(0.95, 0.999, (camera["height"], camera["width"])).astype(np.float32)
    return shadow_map, camera_depth


@pytest.mark.parametrize("scene_name", ["hall", "pergola"])
def test_scattering_equals_the_cli(ctx, tmp_path, rng, scene_name):
    scene_file = DATA / "scatter" / f"{scene_name}.json"
    scene = json.loads(scene_file.read_text())
    shadow_map, camera_depth = scatter_inputs(rng, scene)
    msmcl.write_depth(tmp_path / "light.exr", shadow_map)
    msmcl.write_depth(tmp_path / "camera.exr", camera_depth)
    for options, flags in [({}, []), ({"moments": 4, "filtered": False}, ["--moments", "4", "--no-filter"]),
                           ({"ray_march": 32, "jitter": 5}, ["--ray-march", "32", "--jitter", "5"])]:
        cli("scatter", scene_file, tmp_path / "light.exr", tmp_path / "camera.exr", tmp_path / "out.exr", *flags)
        radiance = ctx.scatter(scene, shadow_map, camera_depth, **options)
        assert radiance.shape == (scene["camera"]["height"], scene["camera"]["width"])
        np.testing.assert_array_equal(radiance, msmcl.read_image(tmp_path / "out.exr")["Y"], err_msg=str(flags))
    # The scene's path does as well as its dict.
    np.testing.assert_array_equal(ctx.scatter(scene_file, shadow_map, camera_depth),
                                  ctx.scatter(scene, shadow_map, camera_depth))


def test_texture_arrays_equal_the_cli(ctx, tmp_path, rng):
    maps = [random_depth(rng, 64, 48, samples=4) for _ in range(3)]
    for i, depth in enumerate(maps):
        msmcl.write_depth(tmp_path / f"c{i}.exr", depth)
    inputs = [tmp_path / f"c{i}.exr" for i in range(3)]
    cli("filter", *inputs, "--array", tmp_path / "cli.ktx2", "--format", "nlq32")
    array = ctx.filter_array(np.stack(maps), format="nlq32")
    assert array.layers == 3 and array.array.shape == (3, 64, 48)
    msmcl.write_texture(tmp_path / "py.ktx2", array)
    assert (tmp_path / "py.ktx2").read_bytes() == (tmp_path / "cli.ktx2").read_bytes()
    for i, depth in enumerate(maps):
        np.testing.assert_array_equal(array.layer(i).array, ctx.filter(depth, format="nlq32").array)
    cli("sat", *inputs, "--array", tmp_path / "cli_sat.ktx2")
    msmcl.write_texture(tmp_path / "py_sat.ktx2", ctx.build_sat_array(maps))
    assert (tmp_path / "py_sat.ktx2").read_bytes() == (tmp_path / "cli_sat.ktx2").read_bytes()


def test_info_equals_msmcl_info(ctx, tmp_path):
    cli("filter", RAILING, tmp_path / "map.ktx2", "--format", "msm64")
    cli("sat", RAILING, tmp_path / "table.exr")
    for path in [RAILING, RAILING_VIEW, tmp_path / "map.ktx2", tmp_path / "table.exr", DATA / "scatter" / "hall.json"]:
        assert msmcl.info(path) == json.loads(cli("info", "--json", path))[0], path
