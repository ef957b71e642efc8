import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def mechgen_bin():
    """The `mechgen` command of this checkout (MECHGEN_BIN, or target/debug/mechgen)."""
    path = pathlib.Path(os.environ.get("MECHGEN_BIN", ROOT / "target" / "debug" / "mechgen"))
    assert path.exists(), f"build the command first (cargo build): {path}"
    return path
