"""Fixtures shared by the tests: `cli` runs the `camloc` command line; `localizer` is the
embedded model under the default camera height, `alone` localizes each pose on its own.

`cli` runs the `camloc` binary named by the environment variable CAMLOC_BIN (.ci/run sets it),
else `target/debug/camloc` of the repository; without either the tests that use it are skipped
with a visible reason.
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

import camloc

ROOT = Path(__file__).resolve().parents[3]


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
