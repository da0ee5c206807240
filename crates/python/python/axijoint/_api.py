"""The implementation of `axijoint.run` and its results (the package's
`__init__` re-exports the API)."""

from __future__ import annotations

import copy
import json
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any, Mapping

from . import _native
from ._native import Error, InputError

# The name a scene given as a dict goes by (in messages and in
# solution.json), inside its base folder.
DICT_SCENE_NAME = "<scene dict>"

_PART = re.compile(r"([^.\[\]]+)((?:\[-?\d+\])*)")


def _parse_key(key: str) -> list:
    """`"loads[0].force[1]"` -> `["loads", 0, "force", 1]`."""
    steps: list = []
    for part in key.split("."):
        m = _PART.fullmatch(part)
        if not m:
            raise InputError(f"override {key!r}: not a key path like 'joints.pile_side.law.cohesion' or 'loads[0].force[0]'")
        steps.append(m.group(1))
        steps.extend(int(i) for i in re.findall(r"\[(-?\d+)\]", m.group(2)))
    return steps


def _plain(value: Any) -> Any:
    """numpy scalars and arrays as JSON values."""
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


# The scene's objects keyed by a name the user chose: an override sets a
# field of a named object that exists, it never makes one.
_NAMED = ("materials", "joints")


def _named_object(key: str, steps: list, node: Any, i: int) -> None:
    """Refuses a missing named object (`joints.<name>`) on the way of `key`,
    with the nearest existing name."""
    step = steps[i]
    if i != 1 or steps[0] not in _NAMED or not isinstance(node, dict) or step in node:
        return
    import difflib

    what = steps[0][:-1]
    near = difflib.get_close_matches(step, list(node), n=1, cutoff=0.6)
    hint = f"; did you mean {near[0]!r}?" if near else ""
    have = ", ".join(node) or "none"
    raise InputError(f"override {key!r}: the scene has no {what} {step!r}{hint} (it has: {have})")


# A joint's stiffness is one of two forms: `stiffness` ("rigid" or
# {"thickness": t}) or the springs k_xi, k_eta, k_theta.
_SPRINGS = ("k_xi", "k_eta", "k_theta")


def _one_stiffness_form(steps: list, scene: dict) -> None:
    """After setting `joints.NAME.stiffness`, drops the joint's springs;
    after setting one of its springs, drops its `stiffness`: an override
    chooses the form."""
    if len(steps) != 3 or steps[0] != "joints":
        return
    joint = scene["joints"][steps[1]]
    if steps[2] == "stiffness":
        for k in _SPRINGS:
            joint.pop(k, None)
    elif steps[2] in _SPRINGS:
        joint.pop("stiffness", None)


def set_key(scene: dict, key: str, value: Any) -> None:
    """Sets `key` (a path such as `"joints.pile_side.law.cohesion"` or
    `"loads[0].force[0]"`) of the scene dict to `value`, in place. Missing
    objects on the way are made, except a named material or joint (a
    misspelt name is refused with the nearest one); a list index must
    exist. Setting `joints.NAME.stiffness` (`"rigid"` or `{"thickness":
    t}`) removes the joint's `k_xi`, `k_eta`, `k_theta`, and setting one of
    those removes its `stiffness` (give all three)."""
    steps = _parse_key(key)
    node: Any = scene
    done = ""
    for i, step in enumerate(steps):
        _named_object(key, steps, node, i)
        last = i == len(steps) - 1
        if isinstance(step, int):
            if not isinstance(node, list) or not -len(node) <= step < len(node):
                size = f"a list of {len(node)}" if isinstance(node, list) else f"not a list ({type(node).__name__})"
                raise InputError(f"override {key!r}: {done or '.'} is {size}, no index {step}")
            where = f"{done}[{step}]"
        else:
            if not isinstance(node, dict):
                raise InputError(f"override {key!r}: {done or '.'} is not an object ({type(node).__name__})")
            where = f"{done}.{step}" if done else step
        if last:
            node[step] = _plain(value)
        else:
            if isinstance(step, str) and step not in node:
                node[step] = [] if isinstance(steps[i + 1], int) else {}
            node = node[step]
        done = where
    _one_stiffness_form(steps, scene)


def _overrides(overrides: Mapping[str, Any] | None, kwargs: Mapping[str, Any]) -> dict:
    """One dict of key paths: `overrides` as given, keyword arguments with
    `__` read as `.` (`mesh__parameters__size=0.5`)."""
    out = dict(overrides or {})
    for k, v in kwargs.items():
        out[k.replace("__", ".")] = v
    return out


def _scene_source(scene, base_dir, overrides: Mapping[str, Any]) -> tuple[str, str | None]:
    """The scene's path (as named in messages; its folder resolves
    `mesh.file`) and its JSON text (`None`: the binary reads the file)."""
    if isinstance(scene, Mapping):
        base = Path(base_dir) if base_dir is not None else Path.cwd()
        doc = copy.deepcopy(dict(scene))
        path = str(base / DICT_SCENE_NAME)
    else:
        path = os.fspath(scene)
        if base_dir is not None:
            raise InputError("base_dir is for a scene given as a dict; a scene file's mesh is found beside it")
        if not overrides:
            return path, None
        try:
            doc = json.loads(Path(path).read_text())
        except (OSError, ValueError, UnicodeDecodeError):
            # Unreadable or malformed: the binary says what is wrong.
            return path, None
        if not isinstance(doc, dict):
            return path, None
    for key, value in overrides.items():
        set_key(doc, key, value)
    return path, json.dumps(doc, indent=2)


def _override_note(message: str, path: str, overrides: Mapping[str, Any]) -> str | None:
    """For an error about the key path an override set (or one inside or
    around it): which override, since the file holds another value."""
    head = f"{path}: "
    if not overrides or not message.startswith(head):
        return None
    key = message[len(head):].split(": ", 1)[0]

    def within(a: str, b: str) -> bool:
        return a == b or a.startswith(b + ".") or a.startswith(b + "[")

    for k, v in overrides.items():
        if within(key, k) or within(k, key):
            return f" [from the override {k!r} = {v!r}]"
    return None


def _fmt_angle(theta: float) -> str:
    """The angle as the report names files (`cut_a-a_theta0.csv`)."""
    t = float(theta)
    s = str(int(t)) if t.is_integer() else repr(t)
    return s.replace("-", "m")


def _stations(member: dict):
    import pandas as pd

    rows = []
    for st in member["stations"]:
        f, m, u = st["force"], st["moment"], st["displacement"]
        phi = st.get("rotation") or [float("nan")] * 3
        rows.append(
            dict(
                z=st["z"], N=f[2], V_x=f[0], V_y=f[1], M_x=m[0], M_y=m[1], T=m[2],
                u_x=u[0], u_y=u[1], u_z=u[2], phi_x=phi[0], phi_y=phi[1], phi_z=phi[2],
            )
        )
    return pd.DataFrame(rows)


def _reaction(member: dict, lam: float | None):
    """Segments then the base, as reaction_<body>.csv (with the segments'
    mean motion, and `lambda` when given)."""
    import pandas as pd

    nan = float("nan")
    st = member["stations"]
    rows = []
    for k, seg in enumerate(member["segments"]):
        length = seg["z_top"] - seg["z_bottom"]
        a, b = st[k], st[k + 1]
        u = [(a["displacement"][c] + b["displacement"][c]) / 2 for c in range(3)]
        f, m = seg["force"], seg["moment"]
        rows.append(
            dict(
                part="shaft", z_top=seg["z_top"], z_bottom=seg["z_bottom"], u_x=u[0], u_y=u[1], u_z=u[2],
                p_x=f[0] / length, p_y=f[1] / length, t=f[2] / length,
                m_x=m[0] / length, m_y=m[1] / length, t_theta=m[2] / length,
                F_x=f[0], F_y=f[1], F_z=f[2], M_x=m[0], M_y=m[1], M_z=m[2],
            )
        )
    base, toe = member["base"], st[-1]
    f, m, u = base["force"], base["moment"], toe["displacement"]
    rows.append(
        dict(
            part="base", z_top=base["z"], z_bottom=base["z"], u_x=u[0], u_y=u[1], u_z=u[2],
            p_x=nan, p_y=nan, t=nan, m_x=nan, m_y=nan, t_theta=nan,
            F_x=f[0], F_y=f[1], F_z=f[2], M_x=m[0], M_y=m[1], M_z=m[2],
        )
    )
    frame = pd.DataFrame(rows)
    if lam is not None:
        frame.insert(0, "lambda", lam)
    return frame


class Result:
    """The solution folder of one run.

    `folder`: where it is (a temporary folder removed with this object when
    `run` was given no `output`). `summary`: summary.json as a dict (`None`
    for `report=False`). `solution`: solution.json (the header)."""

    def __init__(self, folder: Path, tmp: tempfile.TemporaryDirectory | None = None):
        self.folder = Path(folder)
        self._tmp = tmp
        self.solution = json.loads((self.folder / "solution.json").read_text())
        s = self.folder / "summary.json"
        self.summary = json.loads(s.read_text()) if s.is_file() else None

    def __repr__(self) -> str:
        return f"axijoint.Result({str(self.folder)!r})"

    @property
    def converged(self) -> bool:
        return self.solution.get("extra", {}).get("converged", True) is not False

    @property
    def complete(self) -> bool:
        """False when a stepped run stopped short of the whole load, or a one-shot run stopped."""
        return self.solution.get("extra", {}).get("complete", True) is not False

    @property
    def load_factor(self) -> float | None:
        return self.solution.get("extra", {}).get("load_factor")

    @property
    def limit_load_factor(self) -> float | None:
        """The limit load factor when the load exceeded the joints' capacity."""
        return self.solution.get("extra", {}).get("limit_load_factor")

    @property
    def exit_status(self) -> int:
        """The binary's exit status for this run: 0, or 3 (limit load
        factor below 1) or 6 (stopped short for another reason)."""
        if self.complete:
            return 0
        return 3 if self.limit_load_factor is not None else 6

    def cut(self, name: str, theta: float):
        """The cut `name` at `theta` degrees: `cut_<name>_theta<deg>.csv`."""
        import pandas as pd

        path = self.folder / f"cut_{name}_theta{_fmt_angle(theta)}.csv"
        if not path.is_file():
            have = sorted(p.name for p in self.folder.glob("cut_*.csv"))
            raise InputError(f"{path}: no such cut file (the folder has: {', '.join(have) or 'no cut CSV'})")
        return pd.read_csv(path)

    def joint(self, name: str):
        """The joint `name`: `joint_<name>.csv` (rows by section, then position)."""
        import pandas as pd

        path = self.folder / f"joint_{name}.csv"
        if not path.is_file():
            have = sorted(p.name for p in self.folder.glob("joint_*.csv"))
            raise InputError(f"{path}: no such joint file (the folder has: {', '.join(have) or 'no joint CSV'})")
        return pd.read_csv(path)

    @property
    def load_path(self):
        """load_path.csv of a stepped run, else `None`."""
        import pandas as pd

        path = self.folder / "load_path.csv"
        return pd.read_csv(path) if path.is_file() else None

    @property
    def stages(self):
        """stages.csv of a run with stages (one row per stage, per cycle of a
        cyclic stage: slip work, end displacement and load, displacement at
        zero load), else `None`."""
        import pandas as pd

        path = self.folder / "stages.csv"
        return pd.read_csv(path) if path.is_file() else None

    @property
    def members(self) -> dict:
        """The member forces of each body in `outputs.members`: body ->
        DataFrame, one row per station top to bottom (`z`, `N`, `V_x`,
        `V_y`, `M_x`, `M_y`, `T`, `u_x`, `u_y`, `u_z`, `phi_x`, `phi_y`,
        `phi_z`; conventions in docs/outputs.md)."""
        return {m["body"]: _stations(m) for m in self.solution.get("members", [])}

    def member_steps(self, body: str):
        """Member `body`'s stations (as `members`) at every converged load
        step, a `lambda` column first; `None` for a run without a load path."""
        import pandas as pd

        steps = ((self.solution.get("extra") or {}).get("load_path") or {}).get("steps") or []
        frames = []
        for s in steps:
            frame = _stations(self._member(body, s["observed"].get("members", [])))
            frame.insert(0, "lambda", s["lambda"])
            frames.append(frame)
        return pd.concat(frames, ignore_index=True) if frames else None

    def reaction(self, body: str):
        """The surroundings' reaction on member `body`: one row per shaft
        segment (`part` = "shaft", per unit length and totals), then the
        base (`part` = "base", totals)."""
        return _reaction(self._member(body, self.solution.get("members", [])), None)

    def reaction_curves(self, body: str):
        """The reaction curves of member `body` over the converged load
        steps (`lambda` column; as `reaction`, with each segment's mean
        motion), `None` for a run without a load path."""
        import pandas as pd

        steps = ((self.solution.get("extra") or {}).get("load_path") or {}).get("steps") or []
        frames = [
            _reaction(self._member(body, s["observed"].get("members", [])), s["lambda"])
            for s in steps
        ]
        return pd.concat(frames, ignore_index=True) if frames else None

    def capacity_split(self, body: str) -> dict:
        """Where member `body`'s load goes: `applied`, `weight`, `shaft`,
        `base` as (x, y, z) forces (the reactions on the member)."""
        return dict(self._member(body, self.solution.get("members", []))["split"])

    def _member(self, body: str, members: list) -> dict:
        for m in members:
            if m["body"] == body:
                return m
        have = ", ".join(m["body"] for m in members) or "none (set outputs.members)"
        raise InputError(f"{self.folder}: no member '{body}' (members: {have})")

    @property
    def displacement(self):
        """displacement.f64 as a numpy array `[M + 1, 2, nodes, 3]`:
        `[harmonic][family S, A][node][u_r, u_z, u_theta]` (docs/outputs.md)."""
        import numpy as np

        d = self.solution["displacement"]
        return np.fromfile(self.folder / d["file"], dtype="<f8").reshape(d["shape"])

    def close(self) -> None:
        """Removes the temporary folder now (no-op for a given `output`)."""
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None


class Cases:
    """The folder of a scene with `load_cases`: `index` (cases.json as a
    dict) and one `Result` per case, by name (`cases["uplift"]`), each
    solved from the same initial state on one set of factors."""

    def __init__(self, folder: Path, tmp: tempfile.TemporaryDirectory | None = None):
        self.folder = Path(folder)
        self._tmp = tmp
        self.index = json.loads((self.folder / "cases.json").read_text())

    def __repr__(self) -> str:
        return f"axijoint.Cases({str(self.folder)!r})"

    @property
    def names(self) -> list[str]:
        """The cases, in the scene's order."""
        return [c["name"] for c in self.index["cases"]]

    def __getitem__(self, name: str) -> Result:
        for c in self.index["cases"]:
            if c["name"] == name:
                if not c["converged"]:
                    raise InputError(f"load case {name}: {c.get('error')}")
                return Result(self.folder / c["folder"])
        raise InputError(f"no load case {name!r} (the scene has: {', '.join(self.names)})")

    def close(self) -> None:
        """Removes the temporary folder now (no-op for a given `output`)."""
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None


def run(
    scene,
    output=None,
    *,
    overrides: Mapping[str, Any] | None = None,
    base_dir=None,
    report: bool = True,
    without_joints: bool | None = None,
    force: bool = False,
    **kwargs,
) -> Result | Cases:
    """Meshes, solves and reports a scene, as `axijoint run SCENE -o OUTPUT`.

    `scene`: a scene file, or a dict in the scene format; a dict's relative
    `mesh.file` is resolved against `base_dir` (default: the current
    folder). `overrides`: key paths to values, applied to the scene first
    (`{"joints.pile_side.law.cohesion": 0.3, "loads[0].force[0]": 0.8}`);
    keyword arguments are more of them, `__` standing for `.`
    (`harmonics=2`, `mesh__parameters__size=0.5`). `output`: the solution
    folder (None: a temporary one, removed with the result). `report=False`
    skips the report (no summary.json, CSV or plots); `without_joints`:
    whether to solve the comparison run without joints (None: as the
    scene's `outputs.compare_without_joints`, default true). `force=True`
    goes on past the cost limits (more than 512 harmonics, factors beyond
    the memory a run may use), as the binary's `--force`.

    A failure raises `axijoint.Error` (a subclass per exit status of the
    binary, `exit_status` set) with the binary's message. A stepped run that
    stops at its limit load factor is no failure here: see
    `Result.complete`, `Result.limit_load_factor`, `Result.exit_status`.
    A scene with `load_cases` gives `Cases` (a `Result` per case).
    """
    ov = _overrides(overrides, kwargs)
    path, text = _scene_source(scene, base_dir, ov)
    tmp = None
    if output is None:
        tmp = tempfile.TemporaryDirectory(prefix="axijoint-")
        out = Path(tmp.name) / "run"
    else:
        out = Path(output)
    try:
        _native.run(path, text, os.fspath(out), report, without_joints, force)
    except Error as e:
        if tmp is not None:
            tmp.cleanup()
        note = _override_note(str(e), path, ov)
        if note is None:
            raise
        named = type(e)(f"{e}{note}")
        named.exit_status = e.exit_status
        raise named from None
    except BaseException:
        if tmp is not None:
            tmp.cleanup()
        raise
    if (out / "cases.json").is_file() and not (out / "solution.json").is_file():
        return Cases(out, tmp)
    return Result(out, tmp)

