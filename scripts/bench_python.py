"""The measurement of scripts/bench-python (a file, not stdin: dask's
worker processes import the main module)."""

import json
import os
import platform
import time


def main():
    import axijoint

    scene = "geo/pile_soil_gravity.json"
    base = {"loads[0].force": [0, 0, 3.0]}  # uplift beyond capacity
    grid = {
        "joints.pile_side.law.cohesion": [0.005, 0.01, 0.02, 0.04],
        "joints.pile_side.law.friction_deg": [15, 20, 25, 30],
    }
    off = {"outputs": {"csv": False, "plots": False, "vtu": False, "gmsh_views": False}}
    cells = axijoint.grid_cells(grid)

    # Serial: one process, one run after the other (each run's harmonics in
    # parallel, as the binary does).
    start = time.perf_counter()
    serial = []
    for cell in cells:
        try:
            r = axijoint.run(scene, overrides={**base, **off, **cell}, without_joints=False)
            serial.append(r.limit_load_factor)
            r.close()
        except axijoint.Error as e:
            serial.append(f"error {e.exit_status}")
    t_serial = time.perf_counter() - start

    # dask: a LocalCluster of 2 worker processes, 1 thread each, each run
    # on one rayon thread (sweep's default; the cluster's start counted).
    start = time.perf_counter()
    table = axijoint.sweep(scene, grid, overrides=base, n_workers=2, progress=False)
    t_dask = time.perf_counter() - start

    # The same with every core for each run (rayon's default): 2 runs at
    # once on 2 cores, 2 threads each.
    start = time.perf_counter()
    table1 = axijoint.sweep(scene, grid, overrides=base, n_workers=2, threads_per_cell=os.cpu_count(), progress=False)
    t_dask1 = time.perf_counter() - start

    same = [a == b == c for a, b, c in zip(serial, table["limit_load_factor"], table1["limit_load_factor"])]
    print(json.dumps({
        "cells": len(cells),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "serial_s": round(t_serial, 2),
        "localcluster_2_workers_1_thread_per_cell_s": round(t_dask, 2),
        "ratio_serial_over_dask": round(t_serial / t_dask, 2),
        "localcluster_2_workers_all_threads_per_cell_s": round(t_dask1, 2),
        "ratio_serial_over_dask_all_threads": round(t_serial / t_dask1, 2),
        "cell_seconds_in_sweep": round(float(table["seconds"].sum()), 2),
        "same_limit_load_factors": all(same),
    }, indent=2))
    print(table[list(grid) + ["limit_load_factor", "seconds"]].to_string())


if __name__ == "__main__":
    main()
