"""Shared fixtures: the repository's sample model and the real models in ../shared/data."""

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SAMPLE = ROOT / "data" / "sample.grdecl"
DATA = Path(os.environ.get("STRATA_DATA", ROOT.parent / "shared" / "data"))


@pytest.fixture
def data() -> Path:
    """The folder of real models; the test skips, saying so, without it."""
    if not DATA.is_dir():
        pytest.skip(f"{DATA} is absent: the real models (Reek, SPE9) are not here")
    return DATA
