"""The Dask example on a LocalCluster of 2 worker processes equals the same sweep in one process
with `batch`, exactly."""

import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "examples"))

import dask_design_sweep as example  # noqa: E402


def test_the_dask_design_sweep_equals_one_batch():
    from distributed import Client, LocalCluster

    sets = example.grid(8)
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            table = example.design_sweep(client, sets, k=4)
    alone = example.summarise(sets)
    assert set(table) == set(alone)
    for c in alone:
        a, b = np.asarray(table[c], dtype=float), np.asarray(alone[c], dtype=float)
        assert ((a == b) | (np.isnan(a) & np.isnan(b))).all(), c
    assert table["every_row"].sum() > 0
