"""The Python package against the axijoint binary (run by scripts/test after
`cargo test`, with target/venv from scripts/setup)."""

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import axijoint

ROOT = Path(__file__).resolve().parents[3]
BINARY = ROOT / "target" / "release" / "axijoint"
SCENE = "geo/pile_footing.json"
COARSE = 0.5  # mesh.parameters.size: Scene P in well under a second


@pytest.fixture(autouse=True)
def in_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def close(a, b, path="summary"):
    """Equal JSON values, numbers to 1e-9 relative."""
    if isinstance(a, float) or isinstance(b, float):
        assert isinstance(a, (int, float)) and isinstance(b, (int, float)), path
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-15), f"{path}: {a} != {b}"
    elif isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), f"{path}: keys {sorted(a)} != {sorted(b)}"
        for k in a:
            close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            close(x, y, f"{path}[{i}]")
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


def test_run_equals_the_binary(tmp_path):
    cli = tmp_path / "cli"
    subprocess.run(
        [BINARY, "run", SCENE, "--set", f"size={COARSE}", "-o", cli, "--quiet"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    expected = json.loads((cli / "summary.json").read_text())

    r = axijoint.run(SCENE, tmp_path / "py", overrides={"mesh.parameters.size": COARSE})
    close(r.summary, expected)
    assert r.summary["converged"] is True and r.exit_status == 0

    # The same files, read through the result.
    cut = r.cut("a-a", 0)
    assert list(cut.columns)[:5] == ["s [m]", "r [m]", "z [m]", "theta [deg]", "body"]
    np.testing.assert_array_equal(cut.to_numpy(), __import__("pandas").read_csv(cli / "cut_a-a_theta0.csv").to_numpy())
    joint = r.joint("pile_side")
    assert set(joint["state"]) <= {"stick", "slip", "open"}
    u = r.displacement
    h = r.solution
    assert list(u.shape) == h["displacement"]["shape"] == [len(h["harmonics"]), 2, h["mesh"]["nodes"], 3]
    np.testing.assert_array_equal(u, np.fromfile(cli / "displacement.f64", "<f8").reshape(u.shape))


def test_dict_scene_and_keyword_overrides(tmp_path):
    scene = json.loads((ROOT / SCENE).read_text())
    r = axijoint.run(scene, base_dir=ROOT / "geo", mesh__parameters__size=COARSE, harmonics=2, report=False)
    assert r.summary is None
    assert r.solution["harmonics"] == [0, 1, 2]
    assert r.solution["scene_file"].endswith(axijoint.DICT_SCENE_NAME)
    folder = r.folder
    assert folder.is_dir()
    r.close()
    assert not folder.exists()


def test_stages_in_a_dict_scene_give_the_load_path_by_stage():
    # A rod pulled in a rigid sleeve, unloaded and reloaded twice (a cyclic
    # stage): the load path by stage, the loop's slip work per cycle.
    pull = lambda f: [{"type": "resultant", "on": "pile_head", "force": [0, 0, f]}]
    law = {"type": "mohr_coulomb", "cohesion": 0.01, "friction_deg": 0, "tensile_strength": 0}
    scene = {
        "mesh": {"file": "pile_soil.geo", "parameters": {"a": 0.1, "size": 0.5, "coarsen": 8}},
        "materials": {"pile": {"E": 3.0e4, "nu": 0.0}, "soil": {"E": 3.0e7, "nu": 0.3}},
        "joints": {
            "pile_side": {"stiffness": "rigid", "law": law},
            "pile_base": {"stiffness": "rigid", "law": dict(law, cohesion=0)},
        },
        "supports": [{"on": "soil_outer", "fix": "all"}, {"on": "soil_bottom", "fix": "all"}],
        "stages": [
            {"name": "load", "loads": pull(0.04), "loading": {"steps": 2}},
            {"name": "cycles", "cyclic": {"loads": pull(0.04), "levels": [0, 1], "cycles": 2}, "loading": {"steps": 2}},
        ],
        "harmonics": 0,
        "outputs": {"csv": True, "plots": False, "vtu": False, "gmsh_views": False},
    }
    r = axijoint.run(scene, base_dir=ROOT / "geo", without_joints=False)
    path = r.load_path
    assert list(path["stage"].unique()) == ["load", "cycles"]
    assert len(path) == 2 + 2 * 2 * 2
    assert path["pile_head_applied [MN]"].iloc[-1] == pytest.approx(0.04, rel=1e-12)
    stages = r.stages
    loop = stages["dissipated [MN m]"].to_list()
    # P^3 / (12 EA q), the Masing loop of each cycle (coarse mesh: 3 %).
    ea, q = 3.0e4 * math.pi * 0.01, 0.01 * 2 * math.pi * 0.1
    assert loop[1] == pytest.approx(0.04**3 / (12 * ea * q), rel=0.03)
    assert loop[2] == pytest.approx(loop[1], rel=1e-3)
    # The residual displacement at zero load: Masing's w_max / 2 (the first
    # loading never returns to zero: empty).
    w_max = 0.04**2 / (2 * ea * q)
    residual = stages["pile_head_at_zero_load [m]"].to_list()
    assert math.isnan(residual[0])
    assert residual[1] == pytest.approx(w_max / 2, rel=0.03)
    r.close()


def test_bad_scene_raises_the_binarys_message(tmp_path):
    # A value out of range: the message names the key path.
    with pytest.raises(axijoint.InputError) as e:
        axijoint.run(SCENE, overrides={"mesh.parameters.size": COARSE, "joints.pile_side.law.cohesion": -1})
    assert e.value.exit_status == 1
    assert "joints.pile_side.law.cohesion" in str(e.value)
    assert isinstance(e.value, axijoint.Error)

    # A misspelt key, the same file given to the binary: the same message.
    scene = json.loads((ROOT / SCENE).read_text())
    scene["materials"]["pile"]["poisson"] = scene["materials"]["pile"].pop("nu")
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(scene, indent=2))
    cli = subprocess.run([BINARY, "run", bad, "-o", tmp_path / "cli"], capture_output=True, text=True)
    assert cli.returncode == 1
    with pytest.raises(axijoint.Error) as e:
        axijoint.run(bad, tmp_path / "py")
    assert "materials.pile.poisson" in str(e.value)
    assert cli.stderr.strip() == f"error: {e.value}"
    assert e.value.exit_status == cli.returncode

    # An override whose path does not exist in the scene's lists.
    with pytest.raises(axijoint.InputError, match=r"loads\[3\]"):
        axijoint.run(SCENE, overrides={"loads[3].force[0]": 1.0})

    # A missing scene file: the binary's message and status.
    with pytest.raises(axijoint.InputError, match="nope.json: cannot read"):
        axijoint.run("geo/nope.json")


def test_sweep_reports_a_failing_cell():
    law = "joints.pile_side.law"
    grid = {f"{law}.cohesion": [0.5, 0.05], f"{law}.tensile_strength": [0.0, 0.1]}
    table = axijoint.sweep(
        SCENE,
        grid,
        overrides={"mesh.parameters.size": COARSE, "outputs.members": ["pile"]},
        n_workers=2,
        progress=False,
    )
    assert len(table) == 4
    assert list(table.columns[:5]) == [f"{law}.cohesion", f"{law}.tensile_strength", "converged", "error", "exit_status"]
    # C = 0.05 with a tensile strength 0.1 lies beyond the apex C / tan(phi).
    failed = table[table["error"].notna()]
    assert len(failed) == 1
    bad = failed.iloc[0]
    assert (bad[f"{law}.cohesion"], bad[f"{law}.tensile_strength"]) == (0.05, 0.1)
    assert f"{law}.tensile_strength" in bad["error"] and bad["exit_status"] == 1
    ok = table[table["error"].isna()]
    assert ok["converged"].all()
    for column in ["max_displacement", "pile_end_ux", "pile_side_open_area", "pile_side_slip_area", "pile_side_stick_area", "pile_shaft_x", "pile_max_moment", "seconds"]:
        assert ok[column].notna().all(), column
    # The cell (C = 0.5, T = 0) is the run of the scene as it is.
    r = axijoint.run(SCENE, overrides={"mesh.parameters.size": COARSE}, report=True, without_joints=False)
    first = ok.iloc[0]
    assert math.isclose(first["max_displacement"], r.summary["max_displacement"], rel_tol=1e-9)
    assert math.isclose(first["pile_end_ux"], r.summary["loaded_faces"]["pile_end"][0], rel_tol=1e-9)
    # The member columns: the shaft and the base carry the applied 0.5 MN.
    assert (abs(ok["pile_shaft_x"] + ok["pile_base_x"] + 0.5) < 1e-9).all()
    # The whole tables per cell: the head station carries the applied 0.5 MN
    # (Scene P's load is on the pile's lower end: the last station).
    for stations, reaction in zip(ok["pile_stations"], ok["pile_reaction"]):
        assert abs(reaction["F_x"].sum() + 0.5) < 1e-9
        assert list(stations.columns[:3]) == ["z", "N", "V_x"]


def test_the_gil_is_released_while_solving():
    import threading
    import time

    done = []
    t = threading.Thread(target=lambda: done.append(axijoint.run(SCENE)))
    start = time.perf_counter()
    t.start()
    gaps, last = [], time.perf_counter()
    while t.is_alive():
        now = time.perf_counter()
        gaps.append(now - last)
        last = now
    elapsed = time.perf_counter() - start
    t.join()
    assert done and done[0].solution["mesh"]["nodes"] > 0
    # Held, the GIL would stop this loop for the whole solve.
    assert max(gaps) < 0.5 * elapsed, (max(gaps), elapsed)


def test_the_comparison_without_joints_follows_the_scene(tmp_path):
    """`without_joints=None` (the default) does what `axijoint run` does with
    the scene's `outputs.compare_without_joints`; True / False override it."""
    coarse = {"mesh.parameters.size": COARSE}
    off = {**coarse, "outputs.compare_without_joints": False}
    for name, overrides, flag, expected in [
        ("default", coarse, None, True),
        ("scene_off", off, None, False),
        ("forced_on", off, True, True),
        ("forced_off", coarse, False, False),
    ]:
        out = tmp_path / name
        axijoint.run(SCENE, out, overrides=overrides, report=False, without_joints=flag)
        assert (out / "without_joints" / "solution.json").is_file() == expected, name


def test_load_cases_equal_the_binary(tmp_path):
    """A scene with load cases runs through the binary's own path: one
    folder per case and cases.json, as `axijoint run`."""
    scene = json.loads((ROOT / SCENE).read_text())
    load = scene.pop("loads")[0]
    turned = {**load, "force": [0.0, load["force"][0], 0.0]}
    scene["load_cases"] = [{"name": "x", "loads": [load]}, {"name": "y", "loads": [turned]}]
    scene["mesh"]["parameters"]["size"] = COARSE
    scene.pop("sections")  # the paper's 5 over the half turn cannot carry the turned load
    path = ROOT / "geo" / "cases_py.json"
    cli = tmp_path / "cli"
    try:
        path.write_text(json.dumps(scene, indent=2))
        subprocess.run([BINARY, "run", path, "-o", cli, "--quiet"], check=True, stdout=subprocess.DEVNULL)
        cases = axijoint.run(path, tmp_path / "py")
    finally:
        path.unlink()
    assert isinstance(cases, axijoint.Cases) and cases.names == ["x", "y"]
    expected = json.loads((cli / "cases.json").read_text())
    close({k: v for k, v in cases.index.items() if k != "scene"}, {k: v for k, v in expected.items() if k != "scene"})
    for name in cases.names:
        r = cases[name]
        close(r.summary, json.loads((cli / name / "summary.json").read_text()))
    # The load turned by 90 degrees about the axis turns the answer (2e-16 measured).
    x, y = cases["x"].summary["loaded_faces"]["pile_end"], cases["y"].summary["loaded_faces"]["pile_end"]
    assert math.isclose(y[1], x[0], rel_tol=1e-9) and abs(y[0]) < 1e-12 * abs(x[0])


def test_the_namespace_holds_the_api_and_every_error_its_status():
    public = {n for n in dir(axijoint) if not n.startswith("_")}
    assert public == set(axijoint.__all__), public ^ set(axijoint.__all__)
    # An error raised in Python (an override path) carries a status too.
    with pytest.raises(axijoint.InputError) as e:
        axijoint.run(SCENE, overrides={"loads[3].force[0]": 1.0})
    assert e.value.exit_status == 1
    for cls, status in [
        (axijoint.BeyondCapacity, 3),
        (axijoint.GmshFailure, 4),
        (axijoint.IOFailure, 5),
        (axijoint.NumericalFailure, 6),
    ]:
        assert issubclass(cls, axijoint.Error) and cls.exit_status == status


def test_an_unguarded_sweep_script_says_why(tmp_path):
    """Without `if __name__ == "__main__":` the local cluster's workers import
    the script again and cannot start: the error says so."""
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import axijoint\n"
        f"axijoint.sweep({SCENE!r}, {{'joints.pile_side.law.cohesion': [0.5]}},\n"
        f"               overrides={{'mesh.parameters.size': {COARSE}}}, n_workers=1, progress=False)\n"
    )
    import sys

    p = subprocess.run([sys.executable, script], capture_output=True, text=True, timeout=300)
    assert p.returncode != 0
    assert 'if __name__ == "__main__":' in p.stderr, p.stderr[-2000:]


def test_an_override_never_makes_a_named_object():
    with pytest.raises(axijoint.InputError, match="no joint 'pile_sied'; did you mean 'pile_side'") as e:
        axijoint.run(SCENE, overrides={"joints.pile_sied.law.cohesion": 0.3})
    assert e.value.exit_status == 1
    with pytest.raises(axijoint.InputError, match=r"no material 'rock' \(it has: pile, footing\)"):
        axijoint.run(SCENE, overrides={"materials.rock.E": 100.0})


def test_an_error_in_an_overridden_scene_names_the_files_line_and_the_override():
    # The binary reads the scene serialized again; the line is the file's.
    lines = (ROOT / SCENE).read_text().splitlines()
    nu_line = next(i for i, l in enumerate(lines, 1) if '"pile": {"E"' in l)
    col = lines[nu_line - 1].index("0.17") + 1
    with pytest.raises(axijoint.InputError) as e:
        axijoint.run(SCENE, overrides={"materials.pile.nu": "abc"})
    assert f"materials.pile.nu: invalid type: string \"abc\", expected f64 (line {nu_line}, column {col})" in str(e.value)
    assert "[from the override 'materials.pile.nu' = 'abc']" in str(e.value)
    assert e.value.exit_status == 1
    # A key the file does not have: the override's, inside the law's line.
    law_line = next(i for i, l in enumerate(lines, 1) if '"law":' in l)
    with pytest.raises(axijoint.InputError) as e:
        axijoint.run(SCENE, overrides={"joints.pile_side.law.friction": 3})
    assert "unknown field `friction`" in str(e.value)
    assert f"(a value an override set, within the value at line {law_line}, column" in str(e.value)


def test_an_override_chooses_the_joints_stiffness_form():
    from axijoint._api import set_key

    scene = json.loads((ROOT / SCENE).read_text())
    joint = scene["joints"]["pile_side"]
    assert (joint["k_xi"], joint["k_eta"], joint["k_theta"]) == (1.0e4, 2.0e4, 1.0e4)
    set_key(scene, "joints.pile_side.stiffness", "rigid")
    assert joint["stiffness"] == "rigid" and not any(k in joint for k in ("k_xi", "k_eta", "k_theta"))
    set_key(scene, "joints.pile_side.stiffness", {"thickness": 0.05})
    assert joint["stiffness"] == {"thickness": 0.05}
    set_key(scene, "joints.pile_side.k_eta", 3.0e4)
    assert "stiffness" not in joint and joint["k_eta"] == 3.0e4
    with pytest.raises(axijoint.InputError, match="no joint 'pile_sied'; did you mean 'pile_side'"):
        set_key(scene, "joints.pile_sied.stiffness", "rigid")


def test_a_rigid_joint_by_override_runs_and_reports_its_springs(tmp_path):
    r = axijoint.run(
        SCENE,
        tmp_path / "rigid",
        overrides={
            "mesh.parameters.size": COARSE,
            "joints.pile_side.stiffness": "rigid",
            # Scene P runs the paper's method and sections, which a rigid
            # nonlinear joint refuses.
            "solver.method": "newton",
            "sections": None,
        },
        report=False,
        without_joints=False,
    )
    springs = r.solution["extra"]["joint_springs"]["pile_side"]
    assert springs["source"] == "rigid"
    # 1000 E / h_min: E = 2e4 MPa (pile and footing), h_min at most the
    # element size along the pile side, size / refine = 0.25 m.
    assert springs["k_xi"] == springs["k_eta"] == springs["k_theta"], springs
    assert 0 < 1000 * 2.0e4 / springs["k_eta"] <= 0.25 * (1 + 1e-9), springs
    with pytest.raises(axijoint.InputError, match=r"needs `solver.method` \"newton\""):
        axijoint.run(SCENE, overrides={"joints.pile_side.stiffness": "rigid"})
    with pytest.raises(axijoint.InputError, match=r"joints\.pile_side\.stiffness: 'stiff' is not a stiffness"):
        axijoint.run(SCENE, overrides={"joints.pile_side.stiffness": "stiff"})


def test_members_come_as_dataframes_that_balance_the_load(tmp_path):
    r = axijoint.run(
        SCENE,
        tmp_path / "m",
        overrides={
            "mesh.parameters.size": COARSE,
            "outputs.members": ["pile"],
            "solver.method": "newton",
            "solver.loading": {"steps": 2},
        },
        without_joints=False,
    )
    stations = r.members["pile"]
    assert list(stations.columns[:7]) == ["z", "N", "V_x", "V_y", "M_x", "M_y", "T"]
    assert stations["z"].is_monotonic_decreasing
    # The same numbers as the binary's CSV.
    csv = __import__("pandas").read_csv(tmp_path / "m" / "member_pile.csv")
    assert np.allclose(csv["N [MN]"], stations["N"], rtol=1e-9, atol=1e-15)
    assert np.allclose(csv["M_y [MN m]"], stations["M_y"], rtol=1e-9, atol=1e-15)
    # Shaft and base balance the applied 0.5 MN (statics, to round-off).
    reaction = r.reaction("pile")
    assert list(reaction["part"].unique()) == ["shaft", "base"]
    assert abs(reaction["F_x"].sum() + 0.5) < 1e-9
    split = r.capacity_split("pile")
    assert abs(split["applied"][0] - 0.5) < 1e-12
    assert abs(split["shaft"][0] + split["base"][0] + 0.5) < 1e-9
    # One block of rows per converged step, the last one the final state.
    curves = r.reaction_curves("pile")
    assert sorted(curves["lambda"].unique()) == [0.5, 1.0]
    last = curves[curves["lambda"] == 1.0].reset_index(drop=True)
    assert np.allclose(last["F_x"], reaction["F_x"], rtol=1e-9, atol=1e-15)
    assert r.summary["members"]["pile"]["split"] == split
    # The stations at every step: the last step's are the final ones.
    path = r.member_steps("pile")
    final = path[path["lambda"] == 1.0].drop(columns="lambda").reset_index(drop=True)
    assert np.allclose(final["M_y"], stations["M_y"], rtol=1e-9, atol=1e-15)
    assert len(path) == 2 * len(stations)
    # At half the load, shaft and base balance half of it.
    assert abs(curves[curves["lambda"] == 0.5]["F_x"].sum() + 0.25) < 1e-9
    with pytest.raises(axijoint.InputError, match="no member 'footing'"):
        r.reaction("footing")


def test_the_cost_limits_and_force(tmp_path, monkeypatch):
    # More than 512 harmonics: refused before any work, as the binary.
    with pytest.raises(axijoint.InputError, match="--force") as e:
        axijoint.run(SCENE, harmonics=600)
    assert e.value.exit_status == 1
    # Factors beyond the memory a run may use: refused, unless forced.
    monkeypatch.setenv("AXIJOINT_MEMORY", "1M")
    with pytest.raises(axijoint.InputError, match="GiB"):
        axijoint.run(SCENE, overrides={"mesh.parameters.size": COARSE}, report=False)
    r = axijoint.run(SCENE, overrides={"mesh.parameters.size": COARSE}, report=False, force=True)
    assert r.converged
