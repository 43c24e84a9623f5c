"""Shared fixtures: the repository's scenes and the `glint` command-line binary."""

import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def scenes() -> pathlib.Path:
    return ROOT / "scenes"


@pytest.fixture(scope="session")
def glint_bin() -> str:
    """The CLI to compare with: $GLINT_BIN (CI sets it, and then it must exist), else a
    build under the cargo target folder, else `glint` on PATH; skipped when there is none."""
    given = os.environ.get("GLINT_BIN")
    if given:
        assert os.access(given, os.X_OK), f"GLINT_BIN={given} is not an executable"
        return given
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("release", "debug"):
        candidate = target / profile / "glint"
        if candidate.exists():
            return str(candidate)
    on_path = shutil.which("glint")
    if on_path is None:
        pytest.skip("no glint binary: build it with `cargo build -p glint-cli` or set GLINT_BIN")
    return on_path
