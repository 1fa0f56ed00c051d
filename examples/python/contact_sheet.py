"""Fifty generated realizations drawn with one scene into a contact sheet.

    python examples/python/contact_sheet.py [OUT.png] [--workers N]

With --workers N the pictures are drawn on a Dask LocalCluster of N worker processes
(each keeping its own renderer); without it, here, one after another.
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import strata


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("output", nargs="?", default="contact-sheet.png")
    parser.add_argument("--workers", type=int, default=0)
    parser.add_argument("--count", type=int, default=50)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as folder:
        paths = []
        for seed in range(1, args.count + 1):
            path = Path(folder) / f"realization-{seed:02}.grdecl"
            strata.synth(nx=60, ny=40, nz=10, faults=4, seed=seed).save(path)
            paths.append(path)

        scene = strata.Scene(sides=True, size=[320, 240], isolines={"property": "PORO"}, wire={"thickness": 1.0})
        start = time.perf_counter()
        if args.workers:
            from distributed import Client, LocalCluster

            with LocalCluster(n_workers=args.workers, threads_per_worker=1, dashboard_address=None) as cluster:
                with Client(cluster) as client:
                    pictures = strata.render_ensemble(paths, scene, client=client)
        else:
            pictures = strata.render_ensemble(paths, scene)
        print(f"{len(pictures)} realizations drawn in {time.perf_counter() - start:.1f} s")

    columns = 10
    rows = -(-len(pictures) // columns)
    h, w, _ = pictures[0].shape
    sheet = np.full((rows * h, columns * w, 4), 255, np.uint8)
    for n, picture in enumerate(pictures):
        r, c = divmod(n, columns)
        sheet[r * h : (r + 1) * h, c * w : (c + 1) * w] = picture
    strata.Picture(sheet).save(args.output)
    print(f"{args.output}: {columns} x {rows} pictures of {w} x {h}")


# Dask starts its worker processes by importing this file again: the guard keeps them
# from running the script themselves.
if __name__ == "__main__":
    main()
