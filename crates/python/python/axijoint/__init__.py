"""axijoint from Python: run a scene, read its results, sweep parameters.

    import axijoint
    r = axijoint.run("geo/pile_footing.json", overrides={"mesh.parameters.size": 0.5})
    r.summary["max_displacement"]
    r.cut("a-a", 0)           # pandas DataFrame, the columns of cut_a-a_theta0.csv
    r.joint("pile_side")      # joint_pile_side.csv
    r.displacement            # numpy array [M + 1, 2, nodes, 3]

    table = axijoint.sweep("geo/pile_footing.json",
                           {"joints.pile_side.law.cohesion": [0.25, 0.5]})

The solver is the axijoint library itself (a Rust extension, no
subprocess); the GIL is released while it solves. docs/python.md has the
whole story.
"""

from ._native import (
    BeyondCapacity,
    Error,
    GmshFailure,
    InputError,
    IOFailure,
    NumericalFailure,
    set_mesh_cache,
)

# Every error carries the binary's exit status: the library sets it on
# each instance, the class gives it to errors raised here in Python (a bad
# override path, a missing load case).
Error.exit_status = 1
InputError.exit_status = 1
BeyondCapacity.exit_status = 3
GmshFailure.exit_status = 4
IOFailure.exit_status = 5
NumericalFailure.exit_status = 6

from ._api import DICT_SCENE_NAME, Cases, Result, run, set_key  # noqa: E402
from ._sweep import grid_cells, sweep  # noqa: E402

__all__ = [
    "run",
    "sweep",
    "Result",
    "Cases",
    "Error",
    "InputError",
    "BeyondCapacity",
    "GmshFailure",
    "IOFailure",
    "NumericalFailure",
    "set_key",
    "set_mesh_cache",
    "grid_cells",
    "DICT_SCENE_NAME",
]
