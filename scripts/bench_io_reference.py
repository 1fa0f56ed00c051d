#!/usr/bin/env python3
"""Load times of reference readers, for `strata bench io` to print beside its own.

Usage: bench_io_reference.py [--runs N] [--budget SECONDS] FILE...

For every FILE it loads the grid with `resdata` (`Grid(path)` for an EGRID,
`Grid.load_from_grdecl(path)` for a text deck) and with `xtgeo`
(`xtgeo.grid_from_file(path)`, format from the extension): one untimed load first (it
pays for lazy imports and warms the page cache), then up to N timed loads, stopping
early once a file has used BUDGET seconds with one reader (so a slow reader on a big
file still gives a number in reasonable time). The median is printed.

Prints one JSON object on stdout:
  {"files": [{"path", "resdata_s", "xtgeo_s", "resdata_runs", "xtgeo_runs"}],
   "notes": [...]}
with null for a reader that is not installed or cannot load the file (a DATA deck, a
missing INCLUDE), the reason being in "notes". It never fails for those reasons; the
caller treats a non-zero exit as a broken script.

The readers' own prints (resdata's C library writes to file descriptor 1) are sent to
stderr so that stdout holds the JSON alone.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
import warnings
from pathlib import Path


def resdata_loader():
    """A function loading a grid with resdata, or the reason there is none."""
    try:
        import resdata
        from resdata.grid import Grid
    except ImportError as e:
        return None, f"resdata not importable ({e}): resdata_s is null"

    def load(path: Path):
        if path.suffix.upper().startswith(".ROFF"):
            raise ValueError("resdata does not read ROFF")
        if path.suffix.upper() in (".EGRID", ".FEGRID", ".GRID"):
            return Grid(str(path))
        return Grid.load_from_grdecl(str(path))

    return load, f"resdata {resdata.__version__}"


def xtgeo_loader():
    """A function loading a grid with xtgeo, or the reason there is none."""
    try:
        import xtgeo
    except ImportError as e:
        return None, f"xtgeo not importable ({e}): xtgeo_s is null"

    def load(path: Path):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            roff = path.suffix.lower().startswith(".roff")
            return xtgeo.grid_from_file(str(path), fformat="roff" if roff else None)

    return load, f"xtgeo {xtgeo.__version__}"


def time_loads(load, path: Path, runs: int, budget: float) -> tuple[float, int]:
    """Median seconds of up to `runs` timed loads after an untimed one, and their count."""
    load(path)
    times: list[float] = []
    spent = 0.0
    while len(times) < runs and (not times or spent < budget):
        start = time.perf_counter()
        load(path)
        times.append(time.perf_counter() - start)
        spent += times[-1]
    return statistics.median(times), len(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--budget", type=float, default=60.0)
    parser.add_argument("files", nargs="+", type=Path)
    args = parser.parse_args()

    out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    sys.stdout = sys.stderr

    notes: list[str] = []
    loaders = {}
    for name, make in (("resdata", resdata_loader), ("xtgeo", xtgeo_loader)):
        load, note = make()
        loaders[name] = load
        notes.append(note)

    files = []
    for path in args.files:
        entry: dict = {"path": str(path)}
        for name, load in loaders.items():
            entry[f"{name}_s"] = None
            entry[f"{name}_runs"] = 0
            if load is None:
                continue
            try:
                median, count = time_loads(load, path, args.runs, args.budget)
            except Exception as e:  # any failure to load is reported, not raised
                notes.append(f"{name} cannot load {path.name}: {type(e).__name__}: {e}")
                continue
            entry[f"{name}_s"] = median
            entry[f"{name}_runs"] = count
        files.append(entry)

    json.dump({"files": files, "notes": notes}, out)
    out.write("\n")
    out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
