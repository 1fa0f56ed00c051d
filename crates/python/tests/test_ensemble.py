"""An ensemble drawn serially and on a Dask cluster of two worker processes gives the
same pictures, in the same order."""

import time

import numpy as np
import pytest

import strata

distributed = pytest.importorskip("distributed", reason="dask[distributed] is installed by scripts/test.sh")


def test_a_local_cluster_draws_what_the_serial_run_draws(tmp_path, capsys):
    paths = []
    for seed in range(1, 7):
        path = tmp_path / f"real-{seed}.grdecl"
        strata.synth(nx=30, ny=20, nz=4, faults=3, seed=seed).save(path)
        paths.append(path)
    scene = strata.Scene(sides=True, size=[240, 180], isolines={"property": "PORO"})
    start = time.perf_counter()
    serial = strata.render_ensemble(paths, scene)
    serial_s = time.perf_counter() - start
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        client.run(lambda: None)  # workers started before the clock
        start = time.perf_counter()
        spread = strata.render_ensemble(paths, scene, client=client)
        spread_s = time.perf_counter() - start
        # Each worker kept one engine: one per process, reused for its realizations.
        frames = client.run(lambda: strata._engine().counters()[2])
    assert len(spread) == len(serial) == len(paths)
    for one, other in zip(serial, spread):
        assert isinstance(other, strata.Picture)
        assert np.array_equal(one, other)
    assert not np.array_equal(serial[0], serial[1]), "the realizations differ"
    assert sum(frames.values()) == len(paths)
    with capsys.disabled():
        print(
            f"\nrender_ensemble, {len(paths)} realizations: serial {serial_s:.2f} s, "
            f"LocalCluster of 2 worker processes {spread_s:.2f} s"
        )
