"""massid.predict_log and Predictor.predict_log: massid predict's pipeline from Python.

Both doors run the one library pipeline (predict_log.hpp), so on the same log they
name the same contact rows with the same text, refuse a wrong wiring with the same
message, and write the same compensated wrench. The contact rows are the ones planted
here (an external force on a known block of rows), not read back from either door.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import AXES, REPO, massid_cli, write_csv

UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
UR_PLAN = REPO / "examples" / "ur_like" / "plan.csv"
FIRST, LAST = 80, 139  # data rows carrying the contact (0-based): file lines 82-141
FORCE = np.array([12.0, -8.0, 15.0])  # N, in the sensor frame
POINT = np.array([0.2, 0.1, 0.6])  # m, where it acts


def run(*args: Any) -> subprocess.CompletedProcess:
    return subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True)


@pytest.fixture(scope="module")
def logs(massid: Any, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The UR-like arm's plan simulated 4 times per pose with noise and an offset (clean),
    its params identified from it, the same log with a contact on rows FIRST..LAST, and
    the clean log with fz negated (a sign-flipped channel)."""
    d = tmp_path_factory.mktemp("predict_log")
    clean = massid.simulate(str(UR), str(UR_PLAN), noise_force=0.05, noise_moment=0.005,
                            sensor_offset=[1.0, -2.0, 3.5, 0.1, -0.2, 0.3], seed=5, repeat=4)
    out = {"clean": write_csv(d / "clean.csv", clean)}
    massid.identify(str(UR), str(out["clean"]), offset=True).save(d / "params.json")
    out["params"] = d / "params.json"
    contact = {k: np.array(v, dtype=float) for k, v in clean.items()}
    moment = np.cross(POINT, FORCE)
    for k in range(3):
        contact[AXES[k]][FIRST:LAST + 1] += FORCE[k]
        contact[AXES[3 + k]][FIRST:LAST + 1] += moment[k]
    out["contact"] = write_csv(d / "contact.csv", contact)
    flipped = dict(clean)
    flipped["fz"] = -np.asarray(clean["fz"])
    out["flipped"] = write_csv(d / "flipped.csv", flipped)
    return out


def place(text: str) -> list[tuple[int, int, int]]:
    """(first line, last line, rows) of every "lines A-B (n rows)" in text."""
    return [tuple(map(int, m)) for m in re.findall(r"lines (\d+)-(\d+) \((\d+) rows\)", text)]


def test_cli_and_python_name_the_same_contact_lines(massid: Any, logs: dict[str, Path],
                                                    tmp_path: Path) -> None:
    cli = run("predict", UR, logs["params"], logs["contact"], "-o", tmp_path / "pred.csv")
    assert cli.returncode == 0, cli.stderr
    notes = [line[len("massid: note: "):] for line in cli.stderr.splitlines()
             if line.startswith("massid: note: ")]
    py = massid.predict_log(str(UR), str(logs["params"]), str(logs["contact"]))
    # The planted rows, as file lines (header on line 1).
    planted = [(FIRST + 2, LAST + 2, LAST - FIRST + 1)]
    assert place("\n".join(notes)) == planted, cli.stderr
    assert place("\n".join(py.notes)) == planted, py.notes
    assert py.notes == notes  # the same text at both doors
    assert [(c["first_line"], c["last_line"], c["rows"]) for c in py.contact] == planted
    # The compensated wrench the CLI wrote, to the bit, and the planted wrench in it.
    written = massid.read_csv(tmp_path / "pred.csv")
    comp = np.column_stack([written[a + "_comp"] for a in AXES])
    assert py.compensated is not None
    np.testing.assert_array_equal(py.compensated, comp)
    np.testing.assert_array_equal(py.predicted, np.column_stack([written[a + "_pred"] for a in AXES]))
    assert py.lines == list(range(2, 2 + comp.shape[0]))
    inside = py.compensated[FIRST:LAST + 1, :3] - py.compensated[:FIRST, :3].mean(axis=0)
    assert np.abs(inside - FORCE).max() < 0.3
    # A Predictor gives the same; the clean log has no contact.
    pred = massid.Predictor(str(UR), str(logs["params"]))
    assert pred.predict_log(str(logs["contact"])).notes == py.notes
    assert pred.predict_log(str(logs["clean"])).notes == []


def test_cli_and_python_refuse_a_flipped_channel_with_the_same_message(
        massid: Any, logs: dict[str, Path], tmp_path: Path) -> None:
    cli = run("predict", UR, logs["params"], logs["flipped"], "-o", tmp_path / "p.csv")
    assert cli.returncode == 2, cli.stderr
    assert not (tmp_path / "p.csv").exists()
    with pytest.raises(massid.InputError) as e:
        massid.predict_log(str(UR), str(logs["params"]), str(logs["flipped"]))
    # The library's message (the hints spelled by each door: --no-checks, checks=False).
    assert "'fz' is negated" in e.value.message
    errors = [line for line in cli.stderr.splitlines() if line.startswith("massid: error: ")]
    assert len(errors) == 1, cli.stderr
    assert errors[0].startswith("massid: error: " + e.value.message + " ("), (errors, e.value.message)
    assert "--no-checks" in errors[0] and "checks=False" in str(e.value)
    with pytest.raises(massid.InputError) as again:
        massid.Predictor(str(UR), str(logs["params"])).predict_log(str(logs["flipped"]))
    assert again.value.message == e.value.message
    # Without the checks, as predict --no-checks: predicted as it is.
    nochecks = run("predict", UR, logs["params"], logs["flipped"], "--no-checks", "-o",
                   tmp_path / "n.csv")
    assert nochecks.returncode == 0, nochecks.stderr
    p = massid.predict_log(str(UR), str(logs["params"]), str(logs["flipped"]), checks=False)
    written = massid.read_csv(tmp_path / "n.csv")
    np.testing.assert_array_equal(p.compensated,
                                  np.column_stack([written[a + "_comp"] for a in AXES]))


def test_columns_by_name_give_the_file_s_prediction(massid: Any, logs: dict[str, Path]) -> None:
    columns = massid.read_csv(str(logs["contact"]))
    by_name = massid.predict_log(str(UR), str(logs["params"]), columns)
    from_file = massid.predict_log(str(UR), str(logs["params"]), str(logs["contact"]))
    np.testing.assert_array_equal(by_name.predicted, from_file.predicted)
    # Rows are numbered from 0 for columns by name: the file's lines minus 2.
    assert [(c["first_line"], c["last_line"]) for c in by_name.contact] == [(FIRST, LAST)]
    assert by_name.notes[0].startswith("data: lines ")


def test_every_door_applies_the_params_clock_delay(massid: Any, logs: dict[str, Path],
                                                   tmp_path: Path) -> None:
    """A params file with "delay": massid.predict, massid.predict_log and massid predict
    predict each row for the joint state delay seconds earlier, the same figures at each
    door, and not the ones the file without the delay gives."""
    import json
    params = json.loads(Path(logs["params"]).read_text())
    params["delay"] = {"value": 0.004, "std": 0.0}
    delayed = tmp_path / "delayed.json"
    delayed.write_text(json.dumps(params))
    columns = {k: np.asarray(v, dtype=float) for k, v in massid.read_csv(str(logs["clean"])).items()}
    columns["t"] = 0.01 * np.arange(len(columns["fx"]))
    log = write_csv(tmp_path / "timed.csv", columns)
    with pytest.warns(massid.MassidWarning, match="clock delay of 4 ms"):
        by_predict = massid.predict(str(UR), str(delayed), str(log))
    by_log = massid.predict_log(str(UR), str(delayed), str(log), checks=False)
    np.testing.assert_array_equal(by_predict, by_log.predicted)
    assert any("clock delay of 4 ms" in n for n in by_log.notes)
    cli = run("predict", UR, delayed, log, "--no-checks", "-o", tmp_path / "p.csv")
    assert cli.returncode == 0, cli.stderr
    assert "clock delay of 4 ms" in cli.stderr
    written = massid.read_csv(tmp_path / "p.csv")
    np.testing.assert_array_equal(by_log.predicted,
                                  np.column_stack([written[a + "_pred"] for a in AXES]))
    undelayed = massid.predict(str(UR), str(logs["params"]), str(log))
    assert np.abs(by_predict - undelayed).max() > 1e-3


# ---------------------------------------------------------------------------
# The level gravity that tilt columns turn: level_gravity=, as the CLI's --gravity

FLIPPED_URDF = """<robot name="flipped"><link name="base"/>
  <joint name="mount" type="fixed"><parent link="base"/><child link="ft"/>
    <origin xyz="0 0 0.3" rpy="3.141592653589793 0 0"/></joint>
  <link name="ft"/>
  <joint name="j1" type="revolute"><parent link="ft"/><child link="link1"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/>
    <limit lower="-3.2" upper="3.2" effort="10" velocity="1"/></joint>
  <link name="link1"><inertial><origin xyz="0.10 0.02 0.04"/><mass value="2.0"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1.6" upper="1.6" effort="10" velocity="1"/></joint>
  <link name="link2"><inertial><origin xyz="0.15 0 0.03"/><mass value="1.0"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"""


def test_level_gravity_of_tilt_columns_is_the_clis(massid: Any, tmp_path: Path) -> None:
    """A sensor mounted upside down (180 degrees about x under the root): its level gravity
    is 0,0,+g. A tilt-only log simulated at that level gravity is identified in memory and
    from the file with default keywords (the root gravity through the mount; the old
    readers took 0,0,-g and refused the log) to the URDF's 3 kg, and Python's predict
    equals massid predict's *_pred, by default and with level_gravity given; given for a
    log with gx,gy,gz it is an error naming the keyword."""
    urdf = tmp_path / "flipped.urdf"
    urdf.write_text(FLIPPED_URDF)
    model = massid.load_model(str(urdf), sensor="ft")
    rng = np.random.default_rng(7)
    n = 60
    plan = {"j1": rng.uniform(-3, 3, n), "j2": rng.uniform(-1.5, 1.5, n),
            "tilt_x_deg": rng.uniform(-25, 25, n), "tilt_y_deg": rng.uniform(-25, 25, n)}
    up = [0.0, 0.0, 9.80665]
    data = massid.simulate(model, plan, noise_force=0.01, noise_moment=0.001, level_gravity=up)
    # The force is the weight, 3 kg times (Rx(tilt_x) Ry(tilt_y))^T (0, 0, +g).
    tx, ty = np.radians(plan["tilt_x_deg"]), np.radians(plan["tilt_y_deg"])
    g = 9.80665 * np.column_stack([-np.cos(tx) * np.sin(ty), np.sin(tx),
                                   np.cos(tx) * np.cos(ty)])
    np.testing.assert_allclose(np.column_stack([data["fx"], data["fy"], data["fz"]]), 3 * g,
                               atol=0.05)
    path = write_csv(tmp_path / "log.csv", data)
    for source in (data, str(path)):
        ident = massid.identify(model, source)
        assert ident.total_mass == pytest.approx(3.0, abs=0.01)
    params = tmp_path / "params.json"
    r = run("identify", urdf, path, "--sensor", "ft", "-o", params)
    assert r.returncode == 0, r.stderr
    r = run("predict", urdf, params, path, "-o", tmp_path / "pred.csv")
    assert r.returncode == 0, r.stderr
    cli = massid.read_csv(str(tmp_path / "pred.csv"))
    for keywords in ({}, {"level_gravity": up}):
        predicted = massid.predict(str(urdf), str(params), str(path), **keywords)
        for k, axis in enumerate(AXES):
            np.testing.assert_allclose(predicted[:, k], cli[axis + "_pred"], atol=1e-9)
        lp = massid.predict_log(str(urdf), str(params), str(path), **keywords)
        np.testing.assert_allclose(lp.compensated, np.column_stack(
            [cli[a + "_comp"] for a in AXES]), atol=1e-9)
    with_g = dict(plan, gx=np.zeros(n), gy=np.zeros(n), gz=np.full(n, 9.80665))
    with pytest.raises(massid.InputError, match=r"no tilt columns .*\(level_gravity\)"):
        massid.identify(model, dict(with_g, **{a: data[a] for a in AXES}), level_gravity=up)
