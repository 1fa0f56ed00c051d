#!/usr/bin/env python3
"""Reference readings of `../shared/data/roff` and `../shared/data/eclipse_variants`,
for `crates/grid/tests/formats.rs`.

Written next to the other references (`crates/grid/tests/reference/`), in the same
layout (`make_reference.py` there documents it and provides `write_corners`):
`formats.json` (per file: dims, active count, extent, zone names, properties and report
steps as checksums and samples) and `<name>.corners.u16.gz` / `<name>.actnum.gz`.

* ROFF files: xtgeo (`grid_from_file`, `gridproperties_from_file`), the format's
  reference reader. `emerald_bigend.roffbin` is not read by xtgeo ("Array must have
  native byteorder"); the test compares it with the little-endian copy instead.
  ASCII code names: roffio turns an empty `""` into `"`, so codes are taken from the
  binary twin where there is one.
* Eclipse files (EGRID, FEGRID, GRID, INIT, FINIT, UNRST): resdata. Intersect's
  (`IX_BO`) INIT and UNRST arrays hold fewer cells than its EGRID's ACTNUM; xtgeo maps
  them through PORV > 0 (`get_actnum_from_porv`), and so does the reference here:
  xtgeo's PORO and PRESSURE per cell.
* The ROFF strata writes (`strata_written.roff`, made by the Rust test
  `write_reference_roff` into the target folder and passed as argument) is read by
  xtgeo once; its summary is stored as `strata_written`.

Run: `python3 scripts/make_formats_reference.py [path/to/strata_written.roff]` with
xtgeo, resdata and six installed.
"""

from __future__ import annotations

import importlib.util
import json
import sys
import warnings
from pathlib import Path

import numpy as np
import resdata
import xtgeo
from resdata.grid import Grid
from resdata.resfile import ResdataFile

ROOT = Path(__file__).resolve().parent.parent
REF = ROOT / "crates/grid/tests/reference"
DATA = (ROOT / "../shared/data").resolve()

spec = importlib.util.spec_from_file_location("make_reference", REF / "make_reference.py")
mr = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mr)

ROFF = {
    "roff_b_grid": "roff/b_grid.roff",
    "roff_banal6": "roff/banal6.roff",
    "roff_banal6_asc": "roff/banal6.roffasc",
    "roff_dual_grid": "roff/dual_grid.roff",
    "roff_dual_grid_w_props": "roff/dual_grid_w_props.roff",
    "roff_eme_hole": "roff/eme_small_w_hole_grid_params.roff",
    "roff_emerald_litend": "roff/emerald_litend.roffbin",
    "roff_reek2_zerolayer": "roff/reek2_grid_w_zerolayer.roff",
    "roff_reek": "roff/reek_grd_w_props.roff",
    "roff_reek_asc": "roff/reek_grd_w_props.roffasc",
    "roff_sixcells_asc": "roff/sixcells.roffasc",
    "roff_twocell": "roff/twocell.roff",
}
ECL = {
    "ecl_b_grid": "eclipse_variants/B.GRID",
    "ecl_e100_fegrid": "eclipse_variants/E100_BO.FEGRID",
    "ecl_e100_grid": "eclipse_variants/E100_BO.GRID",
    "ecl_e300_egrid": "eclipse_variants/E300_BO.EGRID",
    "ecl_e300_grid": "eclipse_variants/E300_BO.GRID",
    "ecl_ix_egrid": "eclipse_variants/IX_BO.EGRID",
    "ecl_ix_grid": "eclipse_variants/IX_BO.GRID",
}
# Result files read with a grid: name -> (grid entry, INIT, UNRST or None)
RESULTS = {
    "ecl_e100_fegrid": ("eclipse_variants/E100_BO.FINIT", None),
    "ecl_e300_egrid": ("eclipse_variants/E300_BO.INIT", "eclipse_variants/E300_BO.UNRST"),
    "ecl_ix_egrid": ("eclipse_variants/IX_BO.INIT", "eclipse_variants/IX_BO.UNRST"),
}


def summary(values: np.ndarray, stride: int) -> dict:
    """Checksums of the defined values of a per-cell array (file order, NaN undefined)
    and samples (global index, value) every `stride` defined cells."""
    cells = np.nonzero(~np.isnan(values))[0]
    v = values[cells]
    return {
        "count": int(v.size),
        "sum": float(v.sum()),
        "min": float(v.min()) if v.size else 0.0,
        "max": float(v.max()) if v.size else 0.0,
        "samples": [[int(cells[a]), float(v[a])] for a in range(0, v.size, stride)],
    }


def file_order(a) -> np.ndarray:
    """An xtgeo (ncol, nrow, nlay) array, masked where undefined, in file order (i fastest)."""
    return np.ma.filled(np.ma.asarray(a, dtype=np.float64), np.nan).transpose(2, 1, 0).ravel()


def geometry(name: str, corners: np.ndarray, actnum: np.ndarray, dims) -> dict:
    lo, hi = mr.bbox(corners[actnum] if actnum.any() else corners)
    ext = mr.extent(lo, hi)
    entry = {"dims": list(dims), "cells": int(np.prod(dims)), "active": int(actnum.sum()), "extent": ext}
    entry.update(mr.write_corners(name, corners, actnum))
    entry["quant_max_error_over_extent"] = entry["quant_max_error"] / ext
    return entry


# Property files without geometry, read onto a grid: grid entry -> file.
PROPERTY_FILES = {"roff_b_grid": "roff/b_poro.roff"}

# ASCII files whose binary twin holds the same grid: their corners are checked equal
# here and stored once.
TWINS = {"roff_banal6_asc": "roff_banal6", "roff_reek_asc": "roff_reek"}
CORNERS: dict[str, np.ndarray] = {}


def roff_entry(name: str, rel: str) -> dict:
    path = DATA / rel
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid = xtgeo.grid_from_file(str(path), fformat="roff")
        corners, _ = mr.xtgeo_corners(path)
        props = xtgeo.gridproperties_from_file(str(path), fformat="roff", names="all", grid=grid)
    actnum = file_order(grid.get_actnum().values) > 0
    entry = {"file": rel, "reader": "xtgeo"}
    CORNERS[name] = corners
    twin = TWINS.get(name)
    if twin:
        assert np.array_equal(corners, CORNERS[twin], equal_nan=True), name
    entry.update(geometry(twin or name, corners, actnum, grid.dimensions))
    if grid.subgrids:
        zones = [""] * grid.nlay
        for zone, layers in grid.subgrids.items():
            for k in layers:
                zones[k - 1] = zone
        entry["zones"] = zones
    entry["properties"] = {}
    if name in PROPERTY_FILES:
        entry["props_file"] = PROPERTY_FILES[name]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            props = [
                xtgeo.gridproperty_from_file(str(DATA / PROPERTY_FILES[name]), fformat="roff", grid=grid)
            ]
    for p in props:
        values = file_order(p.values)
        item = summary(values, max(1, int(actnum.sum()) // 50))
        if p.isdiscrete:
            item["codes"] = {str(int(k)): str(v) for k, v in p.codes.items()}
        entry["properties"][p.name.upper()] = item
    return entry


def ecl_entry(name: str, rel: str) -> dict:
    path = DATA / rel
    dims, corners, actnum = mr.resdata_corners_any(path)
    entry = {"file": rel, "reader": "resdata"}
    # A GRID file may leave cells out; resdata gives those all-zero corners, which are
    # not compared and are kept out of the quantization box.
    unlisted = np.nonzero(~actnum & (corners == 0).all(axis=(1, 2)))[0]
    if unlisted.size:
        entry["unlisted_cells"] = unlisted.tolist()
        corners[unlisted] = corners[np.nonzero(actnum)[0][0]]
    entry.update(geometry(name, corners, actnum, dims))
    if name in RESULTS:
        init, unrst = RESULTS[name]
        entry["init"] = init
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            grid = xtgeo.grid_from_file(str(DATA / rel))
            poro = xtgeo.gridproperty_from_file(str(DATA / init), name="PORO", grid=grid)
        entry["properties"] = {"PORO": summary(file_order(poro.values), 3)}
        if unrst:
            entry["unrst"] = unrst
            entry["report_steps"] = steps(DATA / rel, DATA / unrst)
    return entry


def steps(egrid: Path, unrst: Path) -> list:
    """Each report step's number, date and PRESSURE per cell (by xtgeo, which maps an
    Intersect run's arrays through PORV)."""
    f = ResdataFile(str(unrst))
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid = xtgeo.grid_from_file(str(egrid))
        for s in range(f.num_named_kw("SEQNUM")):
            head = f.iget_named_kw("INTEHEAD", s)
            date = [int(head[66]), int(head[65]), int(head[64])]
            p = xtgeo.gridproperty_from_file(
                str(unrst), name="PRESSURE", date=date[0] * 10000 + date[1] * 100 + date[2], grid=grid
            )
            out.append(
                {
                    "number": int(f.iget_named_kw("SEQNUM", s)[0]),
                    "date": date,
                    "pressure": summary(file_order(p.values), 1),
                }
            )
    return out


def resdata_corners_any(path: Path):
    """make_reference's resdata reading, for any file resdata's Grid opens."""
    grid = Grid(str(path))
    nx, ny, nz, _ = grid.get_dims()
    index = grid.export_index(active_only=False)
    corners = np.asarray(grid.export_corners(index), dtype=np.float64).reshape(-1, 8, 3)
    actnum = index["active"].to_numpy() >= 0
    return (nx, ny, nz), corners, actnum


mr.resdata_corners_any = resdata_corners_any


def main() -> None:
    out = {
        "generator": "scripts/make_formats_reference.py",
        "resdata_version": resdata.__version__,
        "xtgeo_version": xtgeo.__version__,
        "models": {},
    }
    for name, rel in ROFF.items():
        out["models"][name] = roff_entry(name, rel)
        twin = TWINS.get(name)
        for prop, item in out["models"][name]["properties"].items():
            if twin and "codes" in item:
                item["codes"] = out["models"][twin]["properties"][prop]["codes"]
    for name, rel in ECL.items():
        out["models"][name] = ecl_entry(name, rel)
    if len(sys.argv) > 1:
        written = Path(sys.argv[1])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            grid = xtgeo.grid_from_file(str(written), fformat="roff")
        out["strata_written"] = {
            "dims": list(grid.dimensions),
            "active": int(grid.nactive),
            "corners_sum": float(np.nansum(mr.xtgeo_corners(written)[0])),
        }
    for name, m in out["models"].items():
        print(name, m["dims"], m["active"], f"quant/extent {m['quant_max_error_over_extent']:.2g}")
    (REF / "formats.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
