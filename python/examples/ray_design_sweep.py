"""The design sweep of `dask_design_sweep.py` on Ray: the same partitions, each a Ray task running
`Mechanism.batch`, gathered into the same table. Run it with `python ray_design_sweep.py` where Ray
installs (`pip install ray`)."""

import ray

from dask_design_sweep import gather, grid, partitions, summarise


@ray.remote
def summarise_remote(part):
    return summarise(part)


def design_sweep(sets, k=4):
    return gather(ray.get([summarise_remote.remote(p) for p in partitions(sets, k)]))


if __name__ == "__main__":
    ray.init(num_cpus=2)
    table = design_sweep(grid())
    print(f"{len(table['l1'])} designs, {int(table['every_row'].sum())} assemble over the whole turn")
