"""Fixtures of the module's tests: the CLI to compare with, the shipped data, one Context,
seeded random depth maps. Run by ctest (`python_module`), which sets MSMCL_CLI and
MSMCL_SOURCE_DIR and puts the built package on PYTHONPATH."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import msmcl

SOURCE_DIR = pathlib.Path(os.environ.get("MSMCL_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = SOURCE_DIR / "data"
# The shipped 256^2 map with 4 samples per texel, and its view's 160x120 receivers.
RAILING = DATA / "railing_256x256_4x.exr"
RAILING_VIEW = DATA / "railing_view_160x120.exr"
FORMATS = ["moments128", "msm64", "nlq64", "nlq32"]
# One seed for every random map of a run, printed so that a failure can be replayed
# (MSMCL_TEST_SEED=<seed>).
SEED = int(os.environ.get("MSMCL_TEST_SEED", np.random.SeedSequence().entropy % (1 << 32)))


def pytest_report_header(config):
    return f"msmcl {msmcl.__version__}, random seed {SEED} (MSMCL_TEST_SEED to replay)"


def cli(*arguments):
    """Runs the msmcl CLI; fails the test with its stderr when it fails."""
    command = [os.environ["MSMCL_CLI"], *map(str, arguments)]
    run = subprocess.run(command, capture_output=True, text=True)
    assert run.returncode == 0, f"{' '.join(command)}: exit {run.returncode}\n{run.stderr}"
    return run.stdout


@pytest.fixture(scope="session")
def ctx():
    """One Context on the default device, as the CLI picks it."""
    return msmcl.Context()


@pytest.fixture
def rng(request):
    """A generator seeded from the run's seed and the test's name."""
    print(f"random seed {SEED} ({request.node.name})")
    return np.random.default_rng([SEED, sum(map(ord, request.node.name))])


def random_depth(rng, height, width, samples=1):
    """Depths in [0, 1]: smooth terrain plus a few occluding boxes, so that every format has
    edges and flat regions to encode."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    phase = rng.uniform(0, 2 * np.pi, 2)
    depth = 0.6 + 0.2 * np.sin(x / 7 + phase[0]) * np.cos(y / 11 + phase[1])
    for _ in range(6):
        x0, y0 = rng.integers(0, width), rng.integers(0, height)
        depth[y0 : y0 + height // 5, x0 : x0 + width // 5] = rng.uniform(0.1, 0.4)
    depth = np.repeat(depth[:, :, None], samples, axis=2) + rng.uniform(0, 1e-3, (height, width, samples))
    depth = np.clip(depth, 0, 1).astype(np.float32)
    return depth if samples > 1 else depth[:, :, 0]
