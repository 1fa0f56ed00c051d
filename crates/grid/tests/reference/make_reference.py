#!/usr/bin/env python3
"""Independent reference values for the shared real models, read by `resdata` and `xtgeo`.

`crates/grid/tests/shared_models.rs` checks strata's readers against what this script
writes next to itself:

* `reference.json`: per model file its dimensions, active count, bounding boxes, the
  quantization parameters of its corner file, and (where asked for) report steps,
  solution values and property checksums/samples;
* `<name>.corners.u16.gz`: the 8 corners of **every** cell in map coordinates (x, y,
  depth positive down; MAPAXES applied), quantized to u16 `q` relative to the bounding
  box of all cells' corners. A value decodes as `lo[a] + q * (hi[a] - lo[a]) / 65535`,
  so the quantization error is at most half of `(hi[a] - lo[a]) / 65535` per axis (the
  JSON records it relative to the extent: below 1e-5, against the 1e-3 the test
  allows). Laid out for gzip, which is all the Rust test has to undo it: 24 planes,
  plane `3 * c + a` (corner `c` in Eclipse order `di + 2 dj + 4 dk`, `dk = 0` the top;
  axis `a` in x, y, depth) over the cells in file order (`i` fastest); within a plane
  each cell stores `d = q[cell] - q[cell - 1]` (wrapping u16, `q[-1] = 0`), neighbours
  being close; the plane is `n` high bytes of `d` followed by `n` low bytes;
* `<name>.actnum.gz`: one byte per cell, 1 active / 0 inactive, file order.

Which reader, and why:

* Corner-point files (EGRID and GRDECL): `resdata` (`Grid(path)` for EGRID,
  `Grid.load_from_grdecl` for text). It keeps the full ZCORN (every cell's own 8
  depths, vertical splits included), reads ACTNUM, and applies MAPAXES as
  `origin + x * unit(x_axis - origin) + y * unit(y_axis - origin)`, the same rule as
  Eclipse and xtgeo. Like Eclipse it holds COORD, ZCORN and MAPAXES in float32; for
  text decks with UTM coordinates that rounds by up to half a float32 step (0.25 m
  near 6e6), which this script measures against xtgeo (which parses MAPAXES in double)
  and records as `xtgeo_max_dev_over_extent`: a few 1e-5 of the extent at most.
* xtgeo is the cross-check, not the reference: it rebuilds ZCORN as if vertically
  adjacent cells shared their corners (it warns when they do not), and for an EGRID
  with GRIDUNIT FEET and no MAPUNITS (BENCH_SPE9) it converts depths to metres but
  not x and y (`xtgeo_zcorn` falls back to metres for the missing map units while
  `xtgeo_coord` uses the grid units), so its depths there are 0.3048 of the file's.
  That model's xtgeo deviation is recorded with this note instead of being asserted.
* SPE10 model 2 (`SPE10_MODEL2.DATA`): neither package reads a DATA deck whose
  PHI/PERM INCLUDE files are missing, so this script reads the block-centred grid
  itself with numpy (`read_block_centred_deck`: DIMENS, DX/DY/DZ/TOPS with `N*value`
  repeats, `--` comments, INCLUDE relative to the deck, skipping the missing ones) and
  converts it to corners the Eclipse way: x from the running sum of DX along i, y from
  the running sum of DY along j, depth from TOPS to TOPS + DZ. The deck has no
  EQUALS/BOX/ADD/MULTIPLY/COPY; the reader refuses them rather than misread a deck that
  has them. The result is cross-checked against `xtgeo.create_box_grid` with the same
  (uniform) increments and the deck's first TOPS.

Every cell is stored for every model, SPE10 model 2 (1.1 M cells) included: in the
delta-coded planar layout its regular planes compress to about 130 kB.

Run from anywhere: `python3 crates/grid/tests/reference/make_reference.py`.
"""

from __future__ import annotations

import gzip
import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import resdata
import xtgeo
from resdata.grid import Grid
from resdata.resfile import ResdataFile

HERE = Path(__file__).resolve().parent
DATA = (HERE / "../../../../../shared/data").resolve()

# Deviation between resdata and xtgeo above which this script stops: float32 storage
# explains up to a few 1e-5; anything near the tests' 1e-3 would mean a reader disagrees.
XTGEO_AGREEMENT = 1e-4

# name -> (path relative to the data folder, reader, xtgeo cross-check note or None)
MODELS = {
    "reek_egrid": ("reek/REEK.EGRID", "resdata", None),
    "reek_grdecl": ("reek/reek_sim_grid.grdecl", "resdata", None),
    "spe9_egrid": (
        "spe9/BENCH_SPE9.EGRID",
        "resdata",
        "xtgeo converts this FEET grid's depths (not x, y) to metres: "
        "MAPUNITS is absent, xtgeo_zcorn falls back to metres, xtgeo_coord does not",
    ),
    "spe9_grdecl": ("spe9/xtgeo_SPE9.GRDECL", "resdata", None),
    "emerald_grdecl": ("emerald/emerald.grdecl", "resdata", None),
    "emerald_hole_grdecl": (
        "emerald/eme_small_w_hole_grid_params.grdecl",
        "resdata",
        None,
    ),
    "simpleb8_egrid": ("simpleb8/E100_BO.EGRID", "resdata", None),
    "simpleb8_grdecl": ("simpleb8/simpleb8.grdecl", "resdata", None),
    "spe10model2_data": ("spe10model2/SPE10_MODEL2.DATA", "numpy-block-centred", None),
}


def resdata_corners(path: Path) -> tuple[tuple[int, int, int], np.ndarray, np.ndarray]:
    """Dimensions, corners (ncell, 8, 3) in map coordinates and ACTNUM, by resdata."""
    if path.suffix.upper() == ".EGRID":
        grid = Grid(str(path))  # apply_mapaxes=True is the default
    else:
        grid = Grid.load_from_grdecl(str(path))
    nx, ny, nz, _ = grid.get_dims()
    index = grid.export_index(active_only=False)
    # export_index lists every cell in global order (i fastest); check it, since the
    # corner planes are written in that order.
    want = np.arange(nx * ny * nz)
    ijk = index[["i", "j", "k"]].to_numpy()
    assert (ijk[:, 0] + nx * (ijk[:, 1] + ny * ijk[:, 2]) == want).all()
    corners = np.asarray(grid.export_corners(index), dtype=np.float64).reshape(-1, 8, 3)
    actnum = index["active"].to_numpy() >= 0
    return (nx, ny, nz), corners, actnum


def xtgeo_corners(path: Path) -> tuple[np.ndarray, list[str]]:
    """Corners (ncell, 8, 3) in map coordinates by xtgeo, and its warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        grid = xtgeo.grid_from_file(str(path))
    planes = [np.ma.filled(p.values, np.nan) for p in grid.get_xyz_corners()]
    # xtgeo arrays are (ncol, nrow, nlay); to file order (i fastest) and (cell, 8, 3).
    arr = np.stack(planes, axis=-1).transpose(2, 1, 0, 3).reshape(-1, 8, 3)
    return arr.astype(np.float64), [str(w.message) for w in caught]


TOKEN = re.compile(r"'[^']*'|\"[^\"]*\"|[^\s']+")


def deck_tokens(path: Path, missing: list[str], depth: int = 0):
    """Tokens of a text deck with `--` comments removed, INCLUDE files spliced in
    (relative to the including file); a missing INCLUDE is recorded and skipped."""
    if depth > 16:
        raise ValueError(f"{path}: INCLUDE nested too deep")
    tokens = []
    for line in path.read_text(errors="replace").splitlines():
        line = line.split("--", 1)[0]
        tokens.extend(TOKEN.findall(line))
    out = []
    it = iter(tokens)
    for tok in it:
        if tok.upper() == "INCLUDE":
            name = next(it).strip("'\"")
            slash = next(it)
            if slash != "/":
                raise ValueError(f"{path}: INCLUDE {name} not closed by /")
            inc = path.parent / name
            if inc.exists():
                out.extend(deck_tokens(inc, missing, depth + 1))
            else:
                missing.append(str(inc))
        else:
            out.append(tok)
    return out


def expand_values(tokens: list[str], start: int) -> tuple[list[float], int]:
    """Numbers from `start` up to the closing `/`, with `N*value` expanded."""
    values: list[float] = []
    i = start
    while tokens[i] != "/":
        tok = tokens[i]
        if tok.endswith("/"):
            tokens[i] = "/"
            tok = tok[:-1]
            if not tok:
                continue
            tokens.insert(i, tok)
        if "*" in tok:
            n, v = tok.split("*", 1)
            values.extend([float(v)] * int(n))
        else:
            values.append(float(tok))
        i += 1
    return values, i + 1


def read_block_centred_deck(path: Path) -> tuple[tuple[int, int, int], np.ndarray, list[str]]:
    """Dimensions and corners (ncell, 8, 3) of a block-centred DATA deck (DX/DY/DZ/TOPS),
    and the INCLUDE files that were missing. Reads RUNSPEC and GRID only (up to PROPS or
    EDIT); other keywords there are stepped over token by token, which is safe for this
    deck because none of their values is a word it looks for."""
    missing: list[str] = []
    tokens = deck_tokens(path, missing)
    arrays: dict[str, np.ndarray] = {}
    dims = None
    i = 0
    while i < len(tokens):
        key = tokens[i].upper()
        if key in ("PROPS", "EDIT"):
            break  # the grid is complete; the rest of the deck is not geometry
        if key == "DIMENS":
            vals, i = expand_values(tokens, i + 1)
            dims = tuple(int(v) for v in vals[:3])
        elif key in ("DX", "DY", "DZ", "TOPS"):
            vals, i = expand_values(tokens, i + 1)
            arrays[key] = np.asarray(vals, dtype=np.float64)
        elif key in ("EQUALS", "BOX", "ADD", "MULTIPLY", "COPY", "ENDBOX", "DXV", "DYV", "DZV"):
            raise NotImplementedError(f"{path}: {key} is not handled by this reference reader")
        elif key in ("COORD", "ZCORN"):
            raise ValueError(f"{path}: {key}: not a block-centred deck")
        else:
            i += 1
    assert dims is not None, "DIMENS missing"
    nx, ny, nz = dims
    n = nx * ny * nz
    for key in ("DX", "DY", "DZ"):
        assert arrays[key].size == n, f"{key} has {arrays[key].size} values, want {n}"
    tops = arrays["TOPS"]
    if tops.size == nx * ny:
        # Eclipse: only the top layer given, each deeper layer starts at the base of the one above.
        full = np.empty(n)
        full[: nx * ny] = tops
        dz = arrays["DZ"]
        for k in range(1, nz):
            full[k * nx * ny : (k + 1) * nx * ny] = (
                full[(k - 1) * nx * ny : k * nx * ny] + dz[(k - 1) * nx * ny : k * nx * ny]
            )
        tops = full
    assert tops.size == n, f"TOPS has {tops.size} values, want {n}"
    shape = (nz, ny, nx)
    dx, dy, dz = (arrays[k].reshape(shape) for k in ("DX", "DY", "DZ"))
    top = tops.reshape(shape)
    # Cell (i, j, k) spans x from the sum of DX over i' < i (same j, k) to that plus DX,
    # y likewise along j, depth from TOPS to TOPS + DZ.
    x0 = np.cumsum(dx, axis=2) - dx
    y0 = np.cumsum(dy, axis=1) - dy
    corners = np.empty((nz, ny, nx, 8, 3))
    for c in range(8):
        di, dj, dk = c & 1, (c >> 1) & 1, (c >> 2) & 1
        corners[..., c, 0] = x0 + di * dx
        corners[..., c, 1] = y0 + dj * dy
        corners[..., c, 2] = top + dk * dz
    return dims, corners.reshape(-1, 8, 3), missing


def bbox(points: np.ndarray) -> tuple[list[float], list[float]]:
    p = points.reshape(-1, 3)
    return p.min(axis=0).tolist(), p.max(axis=0).tolist()


def extent(lo, hi) -> float:
    return math.sqrt(sum((h - l) ** 2 for l, h in zip(lo, hi)))


def write_corners(name: str, corners: np.ndarray, actnum: np.ndarray) -> dict:
    """Quantizes and writes the corner planes and ACTNUM; returns their description."""
    lo, hi = bbox(corners)
    lo_a, hi_a = np.asarray(lo), np.asarray(hi)
    span = np.where(hi_a > lo_a, hi_a - lo_a, 1.0)
    q = np.rint((corners - lo_a) / span * 65535.0)
    q = np.clip(q, 0, 65535).astype("<u2")
    decoded = lo_a + q.astype(np.float64) * (span / 65535.0)
    quant_err = float(np.linalg.norm(decoded - corners, axis=2).max())
    # Planar: plane 3 * c + a holds corner c, axis a of every cell; then wrapping
    # deltas along the plane, split into a high-byte and a low-byte half.
    planes = q.transpose(1, 2, 0).reshape(24, -1).astype(np.int64)
    deltas = np.diff(planes, axis=1, prepend=0).astype(np.uint16)
    split = np.concatenate([(deltas >> 8).astype(np.uint8), (deltas & 255).astype(np.uint8)], axis=1)
    corners_file = f"{name}.corners.u16.gz"
    actnum_file = f"{name}.actnum.gz"
    (HERE / corners_file).write_bytes(gzip.compress(split.tobytes(), 9, mtime=0))
    (HERE / actnum_file).write_bytes(
        gzip.compress(actnum.astype(np.uint8).tobytes(), 9, mtime=0)
    )
    return {
        "corners_file": corners_file,
        "actnum_file": actnum_file,
        "quant_lo": lo,
        "quant_hi": hi,
        "quant_max_error": quant_err,
    }


def step_date(unrst: ResdataFile, step: int) -> list[int]:
    """(year, month, day) of a report step, from INTEHEAD items 65-67 (DAY, MONTH, YEAR)."""
    head = unrst.iget_named_kw("INTEHEAD", step)
    return [int(head[66]), int(head[65]), int(head[64])]


# PRESSURE is the array asked for; it does not change between this run's two steps
# (nor do SWAT, SGAS), so RS, which does, shows that each step's own arrays are read.
SIMPLEB8_ARRAYS = ("PRESSURE", "RS")


def simpleb8_results(actnum: np.ndarray) -> dict:
    """Report steps of E100_BO.UNRST and every value of SIMPLEB8_ARRAYS, by global cell index."""
    unrst = ResdataFile(str(DATA / "simpleb8/E100_BO.UNRST"))
    active_cells = np.nonzero(actnum)[0]
    steps = []
    for s in range(unrst.num_named_kw("SEQNUM")):
        arrays = {}
        for name in SIMPLEB8_ARRAYS:
            values = np.asarray(unrst.iget_named_kw(name, s), dtype=np.float64)
            assert values.size == active_cells.size
            arrays[name] = [[int(g), float(v)] for g, v in zip(active_cells, values)]
        steps.append(
            {
                "number": int(unrst.iget_named_kw("SEQNUM", s)[0]),
                "date": step_date(unrst, s),
                "arrays": arrays,
            }
        )
    dates = [[d.year, d.month, d.day] for d in unrst.report_dates]
    assert dates == [s["date"] for s in steps], (dates, steps)
    return {"report_steps": steps}


def property_summary(values: np.ndarray, actnum: np.ndarray, stride: int) -> dict:
    """Checksums of an active-cell array and samples (global index, value) every `stride`
    active cells, so the test checks both the values and their mapping onto cells."""
    values = np.asarray(values, dtype=np.float64)
    active_cells = np.nonzero(actnum)[0]
    assert values.size == active_cells.size
    return {
        "count": int(values.size),
        "sum": float(values.sum()),
        "sum_sq": float((values * values).sum()),
        "min": float(values.min()),
        "max": float(values.max()),
        "samples": [
            [int(active_cells[a]), float(values[a])] for a in range(0, values.size, stride)
        ],
    }


def main() -> None:
    out = {
        "generator": "crates/grid/tests/reference/make_reference.py",
        "resdata_version": resdata.__version__,
        "xtgeo_version": xtgeo.__version__,
        "corner_layout": "24 planes (3 * corner + axis) over the cells, i fastest; per plane "
        "n high bytes then n low bytes of the wrapping u16 delta of q from the previous cell "
        "(0 before the first); value = quant_lo[axis] + q * (quant_hi[axis] - quant_lo[axis]) / 65535",
        "models": {},
    }
    for name, (rel, reader, xt_note) in MODELS.items():
        path = DATA / rel
        entry: dict = {"file": rel, "reader": reader}
        if reader == "resdata":
            dims, corners, actnum = resdata_corners(path)
            xt, xt_warnings = xtgeo_corners(path)
            assert not xt_warnings, (name, xt_warnings)
            dev_xt = float(np.nanmax(np.linalg.norm(xt - corners, axis=2)))
        else:
            dims, corners, missing = read_block_centred_deck(path)
            actnum = np.ones(corners.shape[0], dtype=bool)
            entry["missing_includes"] = [str(Path(m).relative_to(DATA)) for m in missing]
            nx, ny, nz = dims
            sizes = corners[0, 7] - corners[0, 0]
            box = xtgeo.create_box_grid(
                (nx, ny, nz),
                origin=tuple(corners[0, 0]),
                increment=tuple(sizes),
            )
            planes = [np.asarray(p.values) for p in box.get_xyz_corners()]
            xt = np.stack(planes, axis=-1).transpose(2, 1, 0, 3).reshape(-1, 8, 3)
            dev_xt = float(np.abs(xt - corners).max())
            xt_note = "cross-checked against xtgeo.create_box_grid with the deck's increments"
        lo, hi = bbox(corners[actnum] if actnum.any() else corners)
        ext = extent(lo, hi)
        entry["xtgeo_max_dev_over_extent"] = dev_xt / ext
        if xt_note:
            entry["xtgeo_note"] = xt_note
        elif dev_xt / ext > XTGEO_AGREEMENT:
            raise SystemExit(f"{name}: resdata and xtgeo differ by {dev_xt} ({dev_xt / ext} of extent)")
        entry.update(
            {
                "dims": list(dims),
                "cells": int(np.prod(dims)),
                "active": int(actnum.sum()),
                "bbox_min": lo,
                "bbox_max": hi,
                "extent": ext,
            }
        )
        entry.update(write_corners(name, corners, actnum))
        entry["quant_max_error_over_extent"] = entry["quant_max_error"] / ext
        if name == "simpleb8_egrid":
            entry.update(simpleb8_results(actnum))
        if name == "spe9_egrid":
            init = ResdataFile(str(DATA / "spe9/BENCH_SPE9.INIT"))
            entry["init_poro"] = property_summary(init.iget_named_kw("PORO", 0), actnum, 97)
        out["models"][name] = entry
        print(
            f"{name}: {dims} active {entry['active']} extent {ext:.3f} "
            f"xtgeo dev/extent {entry['xtgeo_max_dev_over_extent']:.3g} "
            f"quant/extent {entry['quant_max_error_over_extent']:.3g}"
        )
    (HERE / "reference.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
