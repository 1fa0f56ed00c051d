"""`strata.open` against `xtgeo.grid_from_file` on one EGRID, in one run; prints JSON.

    cargo run --release -- synth --nx 200 --ny 200 --nz 50 -o /tmp/synth-2m.egrid
    python scripts/bench_python.py /tmp/synth-2m.egrid [--repeat 3]

Measure with a release wheel (`pip install ./crates/python`). Each reader runs
`--repeat` times, alternating; the best and median times are given. `strata.open`
reads the grid with its INIT/UNRST beside it when present (a synth file has none);
the corners, which xtgeo computes only when asked too, are timed apart.
"""

import argparse
import json
import statistics
import time

import numpy as np
import xtgeo

import strata

parser = argparse.ArgumentParser()
parser.add_argument("egrid")
parser.add_argument("--repeat", type=int, default=3)
args = parser.parse_args()

times = {"strata.open": [], "xtgeo.grid_from_file": []}
for _ in range(args.repeat):
    start = time.perf_counter()
    grid = strata.open(args.egrid)
    times["strata.open"].append(time.perf_counter() - start)
    start = time.perf_counter()
    xgrid = xtgeo.grid_from_file(args.egrid)
    times["xtgeo.grid_from_file"].append(time.perf_counter() - start)

start = time.perf_counter()
corners = grid.corners
corner_s = time.perf_counter() - start
nx, ny, nz = grid.dims
print(json.dumps({
    "file": args.egrid,
    "dims": [nx, ny, nz],
    "cells": nx * ny * nz,
    "repeat": args.repeat,
    "seconds": {name: {"best": min(t), "median": statistics.median(t)} for name, t in times.items()},
    "strata_over_xtgeo_best": min(times["strata.open"]) / min(times["xtgeo.grid_from_file"]),
    "strata_corners_seconds": corner_s,
    "corners_shape": list(corners.shape),
    "zcorn_zero_copy": bool(np.shares_memory(grid.zcorn, grid.zcorn)),
    "same_dims": list(xgrid.dimensions) == [nx, ny, nz],
}, indent=2))
