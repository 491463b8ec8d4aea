"""Fixtures shared by the tests: `cli` runs the `camloc` command line; `localizer` is the
embedded model under the default camera height, `alone` localizes each pose on its own;
`walk_keypoints` is a held-out CMU walk seen by one camera (skipped without the data).

`cli` runs the `camloc` binary named by the environment variable CAMLOC_BIN (.ci/run sets it),
else `target/debug/camloc` of the repository; without either the tests that use it are skipped
with a visible reason.
"""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import camloc

ROOT = Path(__file__).resolve().parents[3]
DATA = Path(os.environ.get("CAMLOC_DATA", ROOT.parent / "shared" / "data"))

# The subjects the project's evaluations hold out (xtask/src/generalise.rs, TEST_SUBJECTS).
HELD_OUT = ["06", "09", "16", "17", "35", "47", "113", "127", "141"]


@pytest.fixture(scope="module")
def cli():
    """Runs `camloc ARGS... --json` and returns (exit code, parsed standard output)."""
    given = os.environ.get("CAMLOC_BIN")
    binary = Path(given) if given else ROOT / "target" / "debug" / "camloc"
    if not binary.is_file():
        if given:
            pytest.fail(f"CAMLOC_BIN={given} is not a file")
        pytest.skip(f"no camloc binary at {binary} (build it with `cargo build -p camloc-cli`)")

    def run(*args):
        done = subprocess.run(
            [str(binary), *map(str, args), "--json"], capture_output=True, text=True, check=False
        )
        assert done.returncode in (0, 1), done.stderr
        return done.returncode, json.loads(done.stdout)

    return run


@pytest.fixture(scope="module")
def localizer():
    return camloc.Localizer()


@pytest.fixture(scope="module")
def alone():
    """Each pose on its own (the default reads a call's poses together)."""
    return camloc.Localizer(camera_height="any")


def held_out_walk():
    """A walk of a held-out subject, chosen by its description in the CMU index ("walk")."""
    index = DATA / "cmu" / "cmu-mocap-index-text.txt"
    folder = DATA / "cmu" / "bvh"
    if not index.is_file() or not folder.is_dir():
        pytest.skip(f"SKIPPED: the CMU walk test: {DATA / 'cmu'} not found (set CAMLOC_DATA)")
    walks = set()
    for line in index.read_text(encoding="utf-8", errors="replace").splitlines():
        trial, _, description = line.partition("\t")
        if description.strip().lower() == "walk":
            walks.add(trial.strip())
    for path in sorted(folder.glob("*.bvh")):
        subject = path.stem.split("_")[0]
        if path.stem in walks and subject in HELD_OUT:
            return path
    pytest.skip("no walk of a held-out subject in the CMU folder")


@pytest.fixture(scope="module")
def walk_keypoints():
    """(clip name, (200, 15, 2) keypoints) of a held-out CMU walk seen by one fixed camera: 4 m
    from the mean pelvis, 10 degrees above it, at 200 degrees of azimuth in the clip's ground
    plane (the walker's facing is the clip's own), 1000 px focal length."""
    clip = held_out_walk()
    truth = camloc.read_bvh(clip)["points3d"][:200]
    assert truth.shape == (200, 15, 3)
    a, e = np.radians(200.0), np.radians(10.0)
    towards = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    z = -towards
    x = np.cross(z, [0, 0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    centre = truth[:, 0].mean(axis=0) + 4.0 * towards
    local = (truth - centre) @ np.stack([x, y, z]).T
    return clip.name, 1000.0 * local[..., :2] / local[..., 2:] + [960.0, 540.0]
