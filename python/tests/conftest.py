"""Shared fixtures: the repository, its test data, and the `dpdnl` CLI binary.

The CLI is looked up as $DPDNL_BIN, then target/release/dpdnl under $CARGO_TARGET_DIR and the
repository. Tests that compare with it are skipped when it is absent, unless
DPDNL_REQUIRE_CLI=1 (python/test.sh sets it after building the binary): then they fail.
"""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"


def _find_cli():
    env = os.environ.get("DPDNL_BIN")
    cands = [Path(env)] if env else []
    if os.environ.get("CARGO_TARGET_DIR"):
        cands.append(Path(os.environ["CARGO_TARGET_DIR"]) / "release" / "dpdnl")
    cands.append(REPO / "target" / "release" / "dpdnl")
    for c in cands:
        if c.is_file() and os.access(c, os.X_OK):
            return c
    return None


@pytest.fixture(scope="session")
def cli():
    """A function running `dpdnl ARGS…` (checked) and returning its CompletedProcess."""
    exe = _find_cli()
    if exe is None:
        msg = "the dpdnl CLI is not built (cargo build --release), and DPDNL_BIN is not set"
        if os.environ.get("DPDNL_REQUIRE_CLI") == "1":
            pytest.fail(msg)
        pytest.skip(msg)

    def run(*args, cwd=None, check=True):
        p = subprocess.run(
            [str(exe), *map(str, args)], cwd=cwd, capture_output=True, text=True
        )
        if check and p.returncode != 0:
            raise AssertionError(f"dpdnl {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p

    return run


@pytest.fixture
def cli_json(cli):
    """`dpdnl …` whose stdout is one JSON object."""

    def run(*args, **kw):
        return json.loads(cli(*args, **kw).stdout)

    return run


@pytest.fixture
def crosscheck_dir(tmp_path):
    """A scratch copy of tests/data/crosscheck (scripts include files relative to the cwd)."""
    d = tmp_path / "crosscheck"
    shutil.copytree(DATA / "crosscheck", d)
    return d
