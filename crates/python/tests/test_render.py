"""Pictures as numpy arrays: their size, what they show (a wireframe's measured line
width on a flat model seen from above), PNG for Jupyter, and a held engine."""

import numpy as np
import pytest

import strata

from conftest import SAMPLE

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def flat_grid(n: int = 8, cell: float = 100.0) -> strata.Grid:
    """n x n x 1 square cells, `cell` metres wide, flat at depth 1000 m."""
    xs = np.arange(n + 1) * cell
    x, y = np.meshgrid(xs, xs)  # (ny + 1, nx + 1)
    coord = np.stack([x, y, np.full_like(x, 1000.0), x, y, np.full_like(x, 1010.0)], axis=-1)
    zcorn = np.empty((2, 2 * n, 2 * n), np.float32)
    zcorn[0], zcorn[1] = 1000.0, 1010.0
    actnum = np.ones((1, n, n), bool)
    native = strata._strata._Grid.from_arrays((n, n, 1), coord, zcorn, actnum, {}, "flat")
    return strata.Grid(native)


def line_profiles(row: np.ndarray, surface: float, line: float) -> list[float]:
    """The summed coverage of each line crossed by a row of red values: the line's
    width in pixels where it crosses the row at right angles (the integral of its
    profile, as the Rust image tests measure it)."""
    coverage = np.clip((row.astype(float) - surface) / (line - surface), 0.0, 1.0)
    widths, run = [], 0.0
    for c in coverage:
        if c > 0.01:
            run += c
        elif run:
            widths.append(run)
            run = 0.0
    return widths


def test_a_picture_is_an_rgba_array_of_the_asked_size():
    picture = strata.render(SAMPLE, strata.Scene(sides=True, size=[320, 200]))
    assert isinstance(picture, strata.Picture) and isinstance(picture, np.ndarray)
    assert picture.shape == (200, 320, 4) and picture.dtype == np.uint8
    covered = (picture[..., :3] != 255).any(axis=-1).mean()
    assert 0.2 < covered < 0.95, covered
    assert picture._repr_png_().startswith(PNG_MAGIC)
    assert strata.open(SAMPLE)._repr_png_().startswith(PNG_MAGIC)


@pytest.mark.parametrize("thickness", [2.0, 4.0])
def test_the_wireframe_of_a_flat_model_from_above_has_the_asked_width(thickness):
    n, size = 8, 480
    scene = strata.Scene(
        size=[size, size],
        colour={"solid": True},
        wire={"thickness": thickness, "color": "#ffffff"},
        camera={"azimuth": 0, "elevation": 90, "distance": 1.0, "z_scale": 1.0},
    )
    picture = strata.render(flat_grid(n), scene)
    red = picture[..., 0]
    # The model covers the middle of the picture: its solid colour is the commonest
    # value there, the lines are white.
    middle = red[size // 3 : 2 * size // 3, size // 3 : 2 * size // 3]
    values, counts = np.unique(middle, return_counts=True)
    surface = float(values[np.argmax(counts)])
    assert surface < 200, "the surface is not darker than the lines"
    # A row and a column through cell centres cross the lines of one family at right
    # angles; the lines inside the model (not its outline) are measured.
    widths = []
    for scan in (red[size // 2 + 3, :], red[:, size // 2 + 3]):
        found = line_profiles(scan, surface, 255.0)
        widths += found[1:-1]
    assert len(widths) >= 2 * (n - 3), widths
    assert np.allclose(widths, thickness, atol=0.35), widths


def test_a_new_camera_on_a_held_grid_builds_nothing():
    grid = strata.synth(nx=12, ny=10, nz=3)
    engine = strata._engine()
    _, built, frames = engine.counters()
    first = strata.render(grid, size=[160, 120])
    turned = strata.render(grid, size=[160, 120], camera={"azimuth": 120})
    assert not np.array_equal(first, turned)
    assert engine.counters()[1:] == (built + 1, frames + 2)
    # Another grid is built anew, and the first drawn again is what it was.
    strata.render(strata.synth(nx=5, ny=5, nz=2), size=[160, 120])
    again = strata.render(grid, size=[160, 120])
    assert np.array_equal(again, first)


def test_a_file_drawn_after_a_grid_of_it_is_read_again(tmp_path):
    path = tmp_path / "m.egrid"
    strata.synth(nx=6, ny=5, nz=2).save(path)
    grid = strata.open(path)
    from_grid = strata.render(grid, size=[120, 90])
    from_file = strata.render(path, size=[120, 90])
    assert np.array_equal(from_grid, from_file)


def test_the_scene_round_trips_and_changes_field_by_field():
    scene = strata.Scene(sides=True, camera={"azimuth": 45})
    assert scene.camera["azimuth"] == 45 and scene.camera["elevation"] == 35
    again = strata.Scene.from_json(scene.to_json())
    assert again == scene
    turned = scene.replace(camera={"elevation": 60})
    assert turned.camera == {**scene.camera, "elevation": 60}
    assert scene.camera["elevation"] == 35, "replace makes a new scene"


def test_a_picture_saves_as_png(tmp_path):
    out = tmp_path / "p.png"
    strata.render(SAMPLE, size=[64, 48]).save(out)
    assert out.read_bytes().startswith(PNG_MAGIC)


def test_a_hierarchy_is_built_with_progress_and_drawn(tmp_path):
    out = tmp_path / "sample.lod"
    told = []
    report = strata.lod_build(SAMPLE, out, tile=8, progress=lambda done, total: told.append((done, total)))
    assert out.stat().st_size == report["bytes"] > 0
    assert report["layers"] > 0
    assert told and told[-1][0] == told[-1][1] > 0, told
    picture = strata.render(out, size=[160, 120])
    assert (picture[..., :3] != 255).any(axis=-1).mean() > 0.1
    with pytest.raises(strata.FileError, match="choose another output"):
        strata.lod_build(out, out)
