"""A design sweep on a Dask cluster: a grid of four-bar param sets split into partitions, each
partition solved with `Mechanism.batch` on a worker (every core of it, the GIL released),
summarised per set (how many rows assembled, the coupler point's extent), gathered into one
table. Run it with `python dask_design_sweep.py` (a local cluster of 2 worker processes)."""

import numpy as np

import mechgen


def grid(n=12):
    """Crank and coupler lengths around the file's four-bar: n x n param sets."""
    l1, l2 = np.meshgrid(np.linspace(0.08, 0.12, n), np.linspace(0.30, 0.40, n))
    return {"l1": l1.ravel(), "l2": l2.ravel()}


def summarise(sets, name="four_bar", step=10.0):
    """One partition: its sets swept by `batch`, one summary row per set."""
    m = mechgen.mechanisms()[name]
    cols = m.batch(sets, start=0.0, stop=360.0, step=step)
    ok = cols["status"] == "ok"
    px = np.where(ok, cols["P_x"], np.nan)
    py = np.where(ok, cols["P_y"], np.nan)
    rows = ok.sum(axis=1)
    whole = rows == ok.shape[1]
    span = lambda a: np.where(rows > 0, np.nanmax(a, axis=1) - np.nanmin(a, axis=1), np.nan)
    return {**sets, "ok_rows": rows, "every_row": whole, "P_x_extent": span(px), "P_y_extent": span(py)}


def partitions(sets, k):
    """`sets` split into `k` consecutive parts."""
    n = len(next(iter(sets.values())))
    bounds = np.linspace(0, n, k + 1).astype(int)
    return [{p: v[a:b] for p, v in sets.items()} for a, b in zip(bounds[:-1], bounds[1:])]


def gather(parts):
    """The partitions' summaries as one table (column -> array), in order."""
    return {c: np.concatenate([p[c] for p in parts]) for c in parts[0]}


def design_sweep(client, sets, k=4):
    """The sweep on `client`'s cluster: one task per partition, then gathered."""
    futures = [client.submit(summarise, part) for part in partitions(sets, k)]
    return gather(client.gather(futures))


if __name__ == "__main__":
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1) as cluster, Client(cluster) as client:
        table = design_sweep(client, grid())
    assembled = int(table["every_row"].sum())
    print(f"{len(table['l1'])} designs, {assembled} assemble over the whole turn")
    best = np.nanargmax(np.where(table["every_row"], table["P_y_extent"], np.nan))
    print(f"tallest coupler path: l1 = {table['l1'][best]:.4f}, l2 = {table['l2'][best]:.4f}, "
          f"height {table['P_y_extent'][best]:.4f}")
