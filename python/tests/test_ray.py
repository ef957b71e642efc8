"""The Ray example on a local Ray instance of 2 CPUs equals the same sweep in one process with
`batch`, exactly. Skipped where Ray is not installed (CI installs Dask only; Ray is large)."""

import pathlib
import sys

import numpy as np
import pytest

EXAMPLES = str(pathlib.Path(__file__).resolve().parents[1] / "examples")
sys.path.insert(0, EXAMPLES)


def test_the_ray_design_sweep_equals_one_batch():
    ray = pytest.importorskip("ray")
    import dask_design_sweep as dask_example
    import ray_design_sweep as example

    sets = dask_example.grid(8)
    # The workers import the example modules from the same folder.
    ray.init(num_cpus=2, include_dashboard=False, runtime_env={"env_vars": {"PYTHONPATH": EXAMPLES}})
    try:
        table = example.design_sweep(sets, k=4)
    finally:
        ray.shutdown()
    alone = dask_example.summarise(sets)
    assert set(table) == set(alone)
    for c in alone:
        a, b = np.asarray(table[c], dtype=float), np.asarray(alone[c], dtype=float)
        assert ((a == b) | (np.isnan(a) & np.isnan(b))).all(), c
    assert table["every_row"].sum() > 0
