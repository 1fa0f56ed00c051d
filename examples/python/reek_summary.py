"""Reek in a notebook's steps: open the model, tabulate its properties with pandas,
and save three views with porosity isolines.

    python examples/python/reek_summary.py [DATA_FOLDER] [OUT_FOLDER]

DATA_FOLDER holds reek/REEK.EGRID and reek/reek_sim_poro.grdecl (../shared/data by
default); the pictures go to OUT_FOLDER (the current folder by default).
"""

import sys
from pathlib import Path

import numpy as np
import pandas as pd

import strata

data = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[3] / "shared" / "data")
out = Path(sys.argv[2] if len(sys.argv) > 2 else ".")

# %% Open the grid with the porosity deck that goes with it.
grid = strata.open(data / "reek" / "REEK.EGRID", props=[data / "reek" / "reek_sim_poro.grdecl"])
nx, ny, nz = grid.dims
print(f"{grid.path}: {nx} x {ny} x {nz} cells, {grid.active_count} active")

# %% One row per property over the active cells, then porosity layer by layer.
table = pd.DataFrame(
    {name: pd.Series(values.compressed()).describe() for name, values in grid.properties.items()}
).T
print(table[["count", "mean", "std", "min", "50%", "max"]].to_string(float_format="{:.4g}".format))
poro = grid.properties["PORO"]
layers = pd.DataFrame(
    {"active cells": poro.count(axis=(0, 1)), "mean PORO": poro.mean(axis=(0, 1)).filled(np.nan)},
    index=pd.RangeIndex(1, nz + 1, name="layer"),
)
print(layers.to_string(float_format="{:.4f}".format))

# %% Three views of one scene: isolines of porosity every 0.02, each fifth one major.
scene = strata.Scene(
    sides=True,
    size=[960, 720],
    isolines={"property": "PORO", "spacing": 0.02, "major_every": 5},
    wire={"color": "#ffffff40"},
)
views = {
    "reek-oblique.png": {"azimuth": 30, "elevation": 35},
    "reek-from-south.png": {"azimuth": 180, "elevation": 15},
    "reek-map.png": {"azimuth": 0, "elevation": 89},
}
for name, camera in views.items():
    # The same grid, another camera: nothing is read or built again.
    picture = strata.render(grid, scene, camera=camera)
    picture.save(out / name)
    print(f"{out / name}: {picture.shape[1]} x {picture.shape[0]}")
