"""`axijoint.sweep`: the cartesian product of parameter values, run on a
dask.distributed cluster, one table row per combination."""

from __future__ import annotations

import itertools
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any, Mapping, Sequence

# Report files a sweep does not need: summary.json alone is written.
_GUARD = (
    "a script that calls axijoint.sweep must call it under `if __name__ == \"__main__\":` "
    "(each worker process of the local cluster imports the script again), "
    "or pass the address of a running cluster as `client`"
)

_NO_FILES = {"outputs.csv": False, "outputs.plots": False, "outputs.vtu": False, "outputs.gmsh_views": False}


def _cell(path: str, text: str | None, params: dict, threads: int | None) -> dict:
    """One combination, on a worker: never raises; the row says what happened."""
    import axijoint

    if threads is not None and "RAYON_NUM_THREADS" not in os.environ:
        # Read once, when the worker's first run starts rayon's pool.
        os.environ["RAYON_NUM_THREADS"] = str(threads)
    start = time.perf_counter()
    row: dict[str, Any] = {}
    try:
        if text is None:
            try:
                doc = json.loads(Path(path).read_text())
            except (OSError, ValueError, UnicodeDecodeError):
                doc = None  # the binary's message below
        else:
            doc = json.loads(text)
        if doc is None:
            scene_text = None
        else:
            for key, value in {**_NO_FILES, **params}.items():
                axijoint.set_key(doc, key, value)
            scene_text = json.dumps(doc, indent=2)
        with tempfile.TemporaryDirectory(prefix="axijoint-sweep-") as tmp:
            out = Path(tmp) / "run"
            axijoint._native.run(path, scene_text, str(out), True, False)
            s = json.loads((out / "summary.json").read_text())
            members = json.loads((out / "solution.json").read_text()).get("members", [])
        row.update(converged=bool(s.get("converged", True)), error=None, exit_status=0)
        complete = s.get("complete", True) is not False
        if not complete:
            row["exit_status"] = 3 if s.get("limit_load_factor") is not None else 6
        row["complete"] = complete
        row["load_factor"] = s.get("load_factor")
        row["limit_load_factor"] = s.get("limit_load_factor")
        for face, d in (s.get("loaded_faces") or {}).items():
            for c, v in zip(("ux", "uy", "uz"), d):
                row[f"{face}_{c}"] = v
        for joint, areas in (s.get("joints") or {}).items():
            for state in ("open", "slip", "stick"):
                row[f"{joint}_{state}_area"] = areas.get(f"{state}_area")
        row["max_displacement"] = s.get("max_displacement")
        for body, m in (s.get("members") or {}).items():
            for part in ("shaft", "base"):
                for c, v in zip(("x", "y", "z"), m["split"][part]):
                    row[f"{body}_{part}_{c}"] = v
            row[f"{body}_max_moment"] = m["max_moment"]
            row[f"{body}_max_moment_z"] = m["max_moment_z"]
            row[f"{body}_head_ux"] = m["head_displacement"][0]
            row[f"{body}_head_uz"] = m["head_displacement"][2]
        from ._api import _reaction, _stations

        for m in members:
            # The whole tables, a DataFrame per cell.
            row[f"{m['body']}_stations"] = _stations(m)
            row[f"{m['body']}_reaction"] = _reaction(m, None)
    except BaseException as e:  # a pyo3 panic is a BaseException
        if isinstance(e, (KeyboardInterrupt, SystemExit)):
            raise
        row = {"converged": False, "error": str(e), "exit_status": getattr(e, "exit_status", 1)}
    row["seconds"] = time.perf_counter() - start
    return row


def grid_cells(grid: Mapping[str, Sequence[Any]]) -> list[dict]:
    """The cartesian product of `grid` (key path -> values), the last key
    varying fastest."""
    keys = list(grid)
    for k in keys:
        if isinstance(grid[k], (str, bytes)) or not hasattr(grid[k], "__iter__"):
            raise TypeError(f"grid[{k!r}]: a list of values, not {grid[k]!r}")
    return [dict(zip(keys, values)) for values in itertools.product(*(list(grid[k]) for k in keys))]


def sweep(
    scene,
    grid: Mapping[str, Sequence[Any]],
    client=None,
    *,
    overrides: Mapping[str, Any] | None = None,
    base_dir=None,
    n_workers: int | None = None,
    threads_per_cell: int | None = None,
    progress: bool = True,
):
    """Runs every combination of `grid` on a dask.distributed cluster; returns
    a pandas DataFrame, one row per combination in product order.

    `grid`: key paths (as `run`'s overrides) to lists of values. `client`: a
    `dask.distributed.Client`, a scheduler address (`"tcp://host:8786"`), or
    None for a LocalCluster of `n_workers` processes (default: the number
    of cores), one thread each, closed at the end. `overrides` apply to
    every cell. `threads_per_cell`: rayon threads of each run, set in each
    worker before its first run; None: 1 on the LocalCluster made here
    (one core per worker), rayon's default (every core) on a given client.

    Columns: the grid's keys; `converged`, `error` (the message of a failed
    cell, else None), `exit_status` (as the binary's; 3 for a limit load
    factor below 1), `complete`, `load_factor`, `limit_load_factor`,
    `<face>_ux`, `_uy`, `_uz` per loaded face, `<joint>_open_area`,
    `_slip_area`, `_stick_area` per joint, `max_displacement`, per member
    of `outputs.members` its reactions `<body>_shaft_x`, `_y`, `_z` and
    `<body>_base_x`, ..., `<body>_max_moment` (and `_max_moment_z`),
    `<body>_head_ux`, `_head_uz`, and the whole tables as a DataFrame per
    cell, `<body>_stations` (as `Result.members`) and `<body>_reaction` (as
    `Result.reaction`); `seconds` (the cell's wall time). A failing cell gives a row with its error and
    never stops the sweep. Only summary.json is written per cell, in a
    temporary folder (outputs.csv, plots, vtu and gmsh_views off), and the
    comparison run without joints is skipped.
    """
    import pandas as pd
    from dask.distributed import Client, LocalCluster

    from ._api import _overrides, _scene_source

    cells = grid_cells(grid)
    path, text = _scene_source(scene, base_dir, _overrides(overrides, {}))
    path = os.path.abspath(path)  # workers may start in another folder

    own_cluster = own_client = None
    if client is None:
        import __main__

        if getattr(__main__, "__name__", None) == "__mp_main__":
            # A worker process importing the user's script again.
            raise RuntimeError(_GUARD)
        workers = n_workers or os.cpu_count() or 1
        try:
            own_cluster = LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
            )
        except Exception as e:
            raise RuntimeError(f"the local dask cluster did not start ({e}); {_GUARD}") from e
        client = own_client = Client(own_cluster)
        if threads_per_cell is None:
            threads_per_cell = 1
    elif isinstance(client, str):
        client = own_client = Client(client)
    try:
        futures = client.map(
            _cell,
            [path] * len(cells),
            [text] * len(cells),
            cells,
            [threads_per_cell] * len(cells),
            pure=False,
        )
        if progress:
            from dask.distributed import progress as show

            show(futures)
        rows = []
        for cell, f in zip(cells, futures):
            try:
                row = f.result()
            except Exception as e:  # the worker died or could not run the cell
                row = {"converged": False, "error": f"{type(e).__name__}: {e}", "exit_status": None}
            rows.append({**cell, **row})
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()
    frame = pd.DataFrame(rows)
    first = list(grid) + ["converged", "error", "exit_status"]
    return frame[first + [c for c in frame.columns if c not in first]]
