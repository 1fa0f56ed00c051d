"""The window from Python: ``strata.view`` in a real window under Xvfb, run by a script,
on a model file's grid and on a grid made in memory."""

import ast
import shutil
import struct
import subprocess
import sys
import textwrap

import pytest

from conftest import SAMPLE


def png_size(path) -> tuple[int, int]:
    """Width and height from a PNG's header."""
    with open(path, "rb") as f:
        header = f.read(24)
    assert header[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is no PNG"
    return struct.unpack(">II", header[16:24])


def test_view_opens_the_window_runs_its_script_and_returns_frame_times(tmp_path):
    if shutil.which("xvfb-run") is None:
        pytest.fail("xvfb-run is needed to test the window: apt-get install xvfb")
    (tmp_path / "file.txt").write_text("set layers [1,2]\nscreenshot file.png 320x240\n")
    (tmp_path / "memory.txt").write_text("orbit 90 3\nscreenshot memory.png 200x150\n")
    # One window per process (winit): each view runs in its own interpreter.
    for code in [
        f"grid = strata.open({str(SAMPLE)!r})\n"
        "print(strata.view(grid, script='file.txt', size=(640, 480)))",
        "print(strata.view(strata.synth(12, 8, 3), script='memory.txt', size=(640, 480)))",
    ]:
        program = "import strata\n" + textwrap.dedent(code)
        run = subprocess.run(
            ["xvfb-run", "-a", sys.executable, "-c", program],
            cwd=tmp_path, capture_output=True, text=True, timeout=300,
        )
        assert run.returncode == 0, run.stderr
        stats = ast.literal_eval(run.stdout.strip().splitlines()[-1])
        assert stats["frames"] >= 3, stats
        assert 0 < stats["median_ms"] <= stats["worst_ms"], stats
    assert png_size(tmp_path / "file.png") == (320, 240)
    assert png_size(tmp_path / "memory.png") == (200, 150)
