"""Models read, compared corner for corner with xtgeo, written and read back."""

import numpy as np
import pytest

import strata

from conftest import SAMPLE

xtgeo = pytest.importorskip("xtgeo", reason="xtgeo is installed by scripts/test.sh")


def xtgeo_corners(xgrid) -> np.ndarray:
    """xtgeo's own corners as (nx, ny, nz, 8, 3), in the same corner order."""
    props = xgrid.get_xyz_corners()
    stacked = np.stack([np.ma.getdata(p.values) for p in props], axis=-1)
    return stacked.reshape(*stacked.shape[:3], 8, 3)


def xtgeo_active(xgrid) -> np.ndarray:
    return np.ma.filled(xgrid.get_actnum().values, 0) == 1


def test_the_version_is_the_crates():
    assert strata.__version__.count(".") == 2


def test_the_sample_has_its_dims_mask_and_masked_properties():
    grid = strata.open(SAMPLE)
    nx, ny, nz = grid.dims
    assert grid.corners.shape == (nx, ny, nz, 8, 3)
    assert grid.active.shape == (nx, ny, nz)
    assert grid.active.sum() == grid.active_count
    poro = grid.properties["PORO"]
    assert poro.shape == (nx, ny, nz)
    assert np.array_equal(poro.mask | grid.active, np.ones_like(grid.active)), "inactive cells masked"
    assert np.isfinite(poro.compressed()).all()
    with pytest.raises(KeyError, match="no property"):
        grid.properties["NOPE"]


def test_lent_arrays_are_the_models_own_and_read_only():
    grid = strata.open(SAMPLE)
    a, b = grid.zcorn, grid.zcorn
    assert np.shares_memory(a, b), "ZCORN was copied"
    assert np.shares_memory(grid.properties["PORO"].data, grid.properties["PORO"].data)
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0, 0] = 1.0
    assert grid.corners is grid.corners, "corners are computed once"
    assert grid.corners.flags.c_contiguous


def test_a_cell_is_what_info_cell_gives():
    grid = strata.open(SAMPLE)
    cell = grid.cell(2, 3, 1)
    assert cell["cell"] == [2, 3, 1]
    assert np.allclose(cell["corners"], grid.corners[1, 2, 0])
    assert cell["active"] == bool(grid.active[1, 2, 0])
    poro = grid.properties["PORO"]
    want = None if poro.mask[1, 2, 0] else pytest.approx(float(poro[1, 2, 0]))
    assert cell["values"]["PORO"] == want
    with pytest.raises(strata.OptionError, match="outside the grid"):
        grid.cell(0, 1, 1)


# SPE9's EGRID is in feet (GRIDUNIT FEET) with no MAPUNITS: xtgeo 4 converts its
# ZCORN to metres but not its COORD (its pillars are vertical, so x and y are the
# file's either way). Its depths are compared in metres, the rest as read.
FEET = 0.3048


@pytest.mark.parametrize(
    "name, depth_factor",
    [
        ("reek/REEK.EGRID", 1.0),
        ("reek/reek_sim_grid.grdecl", 1.0),
        ("spe9/BENCH_SPE9.EGRID", FEET),
        ("spe9/xtgeo_SPE9.GRDECL", 1.0),
    ],
)
def test_real_models_agree_with_xtgeo_corner_for_corner(data, name, depth_factor):
    path = data / name
    grid = strata.open(path, grid_only=True)
    xgrid = xtgeo.grid_from_file(path)
    assert grid.dims == tuple(xgrid.dimensions)
    assert np.array_equal(grid.active, xtgeo_active(xgrid))
    ours, theirs = grid.corners.copy(), xtgeo_corners(xgrid)
    ours[..., 2] *= depth_factor
    # Both interpolate the same f32 depths on the same f64 pillars.
    assert np.allclose(ours, theirs, rtol=0, atol=1e-3), np.abs(ours - theirs).max()


def test_spe9_init_porosity_is_xtgeos(data):
    grid = strata.open(data / "spe9/BENCH_SPE9.EGRID")
    xgrid = xtgeo.grid_from_file(data / "spe9/BENCH_SPE9.EGRID")
    theirs = xtgeo.gridproperty_from_file(data / "spe9/BENCH_SPE9.INIT", name="PORO", grid=xgrid)
    ours = grid.properties["PORO"]
    assert np.array_equal(ours.mask, np.ma.getmaskarray(theirs.values))
    assert np.allclose(ours.compressed(), theirs.values.compressed(), atol=1e-6)


def test_xtgeo_grids_go_both_ways_with_the_same_corners(data):
    xgrid = xtgeo.grid_from_file(data / "reek/REEK.EGRID")
    nx, ny, nz = xgrid.dimensions
    layer = np.broadcast_to(np.arange(1, nz + 1, dtype=np.float32), (nx, ny, nz))
    mine = strata.from_xtgeo(xgrid, {"LAYER": layer})
    assert np.allclose(mine.corners, xtgeo_corners(xgrid), rtol=0, atol=1e-3)
    assert np.array_equal(mine.active, xtgeo_active(xgrid))
    i, j, k = np.argwhere(mine.active)[0]
    assert mine.properties["LAYER"][i, j, k] == k + 1
    assert mine.properties["LAYER"].count() == mine.active_count
    back = strata.open(data / "reek/REEK.EGRID").to_xtgeo()
    assert np.allclose(xtgeo_corners(back), xtgeo_corners(xgrid), rtol=0, atol=1e-3)


def test_a_generated_grid_goes_to_xtgeo_and_back():
    grid = strata.synth(nx=7, ny=5, nz=3, faults=2, seed=3)
    xgrid = grid.to_xtgeo()
    assert np.allclose(xtgeo_corners(xgrid), grid.corners, rtol=0, atol=1e-3)
    again = strata.from_xtgeo(xgrid)
    assert np.allclose(again.corners, grid.corners, rtol=0, atol=1e-3)
    assert np.allclose(again.properties["PORO"], grid.properties["PORO"])


@pytest.mark.parametrize("suffix", [".grdecl", ".egrid"])
def test_a_grid_written_reads_back_the_same(tmp_path, suffix):
    grid = strata.synth(nx=9, ny=6, nz=4, faults=3, seed=7)
    path = tmp_path / f"model{suffix}"
    grid.save(path)
    again = strata.open(path)
    assert again.dims == grid.dims
    assert np.array_equal(again.active, grid.active)
    # EGRID stores COORD as 32-bit floats: map coordinates near 7e6 keep 0.5 m steps.
    assert np.allclose(again.corners, grid.corners, rtol=1e-7 if suffix == ".egrid" else 0, atol=1e-4)
    if suffix == ".grdecl":
        assert np.allclose(again.properties["PORO"], grid.properties["PORO"], atol=1e-6)


def test_report_steps_have_numbers_dates_and_masked_arrays(data):
    grid = strata.open(data / "simpleb8/E100_BO.EGRID")
    steps = grid.steps
    assert len(steps) > 1
    assert [s.number for s in steps] == sorted(s.number for s in steps)
    assert all(s.date is not None for s in steps)
    pressure = steps[-1]["PRESSURE"]
    assert pressure.shape == grid.dims
    assert pressure.count() == grid.active_count
    assert grid.cell(1, 1, 1)["values"][f"PRESSURE@{steps[-1].number}"] == pytest.approx(
        float(pressure[0, 0, 0])
    )
