"""The Python module against independent computations and against the CLI.

Run: PYTHONPATH=<build>/python /usr/bin/python3 -m pytest tests/python
(ctest does this; MASSID_CLI names the massid executable).
"""

import ast
import json
import pathlib
import re
import subprocess
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import massid
from conftest import massid_cli, write_csv

REPO = pathlib.Path(__file__).resolve().parents[2]
PUMA = REPO / "examples" / "puma260" / "puma260.urdf"
PUMA_PLAN = REPO / "examples" / "puma260" / "plan.csv"
UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
UR_PLAN = REPO / "examples" / "ur_like" / "plan.csv"
BRANCHING = REPO / "examples" / "branching" / "branching.urdf"


def run_cli(*args, check=True):
    r = subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"massid {' '.join(map(str, args))}: {r.returncode}\n{r.stderr}")
    return r


# ---------------------------------------------------------------------------
# An independent forward kinematics straight from the URDF's XML, for the
# direct sum  f = sum m g,  m = sum m_l (p_l + R_l c_l) x g.


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def axis_rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def numbers(text, default):
    return np.array([float(v) for v in text.split()]) if text else np.array(default, float)


def direct_wrench(urdf, root, q_by_joint, g):
    """f, m at the root link's frame from the URDF's inertials, by recursion over the XML."""
    tree = ET.parse(urdf).getroot()
    inertials = {}
    for link in tree.findall("link"):
        i = link.find("inertial")
        if i is None:
            continue
        o = i.find("origin")
        com = numbers(o.get("xyz") if o is not None else None, [0, 0, 0])
        inertials[link.get("name")] = (float(i.find("mass").get("value")), com)
    children = {}
    for j in tree.findall("joint"):
        children.setdefault(j.find("parent").get("link"), []).append(j)
    f = np.zeros(3)
    m = np.zeros(3)

    def visit(link, R, p):
        nonlocal f, m
        if link in inertials:
            mass, com = inertials[link]
            f += mass * g
            m += mass * np.cross(p + R @ com, g)
        for j in children.get(link, []):
            o = j.find("origin")
            xyz = numbers(o.get("xyz") if o is not None else None, [0, 0, 0])
            rpy = numbers(o.get("rpy") if o is not None else None, [0, 0, 0])
            Rj = R @ rpy_matrix(*rpy)
            pj = p + R @ xyz
            axis = numbers(j.find("axis").get("xyz") if j.find("axis") is not None else None, [1, 0, 0])
            qv = q_by_joint.get(j.get("name"), 0.0)
            if j.get("type") in ("revolute", "continuous"):
                Rj = Rj @ axis_rotation(axis, qv)
            elif j.get("type") == "prismatic":
                pj = pj + Rj @ (axis / np.linalg.norm(axis) * qv)
            visit(j.find("child").get("link"), Rj, pj)

    visit(root, np.eye(3), np.zeros(3))
    return np.concatenate([f, m])


def random_poses(model, n, rng):
    q = np.column_stack(
        [rng.uniform(j.lower, j.upper, n) if j.limited else rng.uniform(-np.pi, np.pi, n) for j in model.joints]
    )
    g = rng.normal(size=(n, 3))
    g *= 9.81 / np.linalg.norm(g, axis=1, keepdims=True)
    return q, g


@pytest.fixture(scope="module")
def puma_data(tmp_path_factory):
    """The demo's data: the paper's plan simulated with noise by the CLI."""
    d = tmp_path_factory.mktemp("puma")
    data = d / "data.csv"
    run_cli("simulate", PUMA, PUMA_PLAN, "-o", data, "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", "1")
    params = d / "params.json"
    run_cli("identify", PUMA, data, "-o", params)
    return d, data, params


# ---------------------------------------------------------------------------


def test_version_matches_the_cli():
    out = run_cli("--version").stdout.strip()
    assert out == f"massid {massid.__version__}"


@pytest.mark.parametrize("urdf", [PUMA, UR, BRANCHING])
def test_model_lists_the_urdf_joints_and_masses(urdf):
    model = massid.load_model(urdf)
    tree = ET.parse(urdf).getroot()
    movable = [j.get("name") for j in tree.findall("joint") if j.get("type") in ("revolute", "continuous", "prismatic")]
    assert sorted(model.joint_names) == sorted(movable)
    masses = sum(float(l.find("inertial/mass").get("value")) for l in tree.findall("link") if l.find("inertial") is not None)
    assert model.nominal_total_mass == pytest.approx(masses, rel=1e-12)
    assert model.links[0].name == model.sensor_link and model.links[0].parent == -1


@pytest.mark.parametrize("urdf", [PUMA, UR, BRANCHING])
def test_standard_regressor_times_urdf_parameters_is_the_direct_sum(urdf):
    model = massid.load_model(urdf)
    q, g = random_poses(model, 25, np.random.default_rng(4))
    Y = massid.standard_regressor(model, q, g)
    assert Y.shape == (25, 6, 4 * model.num_links)
    w = Y @ model.nominal_parameters()
    for i in range(len(q)):
        direct = direct_wrench(urdf, model.sensor_link, dict(zip(model.joint_names, q[i])), g[i])
        np.testing.assert_allclose(w[i], direct, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("urdf", [PUMA, UR, BRANCHING])
def test_base_regressor_reproduces_every_standard_parameter_vector(urdf):
    """Eq. 28: Y pi = Y_b K pi for any pi (the base parameters lose nothing)."""
    model = massid.load_model(urdf)
    base = massid.base_parameters(model)
    q, g = random_poses(model, 30, np.random.default_rng(5))
    Y = massid.standard_regressor(model, q, g)
    Yb = massid.regressor(model, q, g)
    assert Yb.shape == (30, 6, base.num_unknowns)
    pi = np.random.default_rng(6).normal(size=4 * model.num_links)
    np.testing.assert_allclose(Y @ pi, Yb @ (base.K @ pi), rtol=1e-9, atol=1e-9)
    Yo = massid.regressor(model, q, g, offset=True)
    np.testing.assert_array_equal(Yo[:, :, -6:], np.broadcast_to(np.eye(6), (30, 6, 6)))


def test_identify_a_csv_gives_the_clis_params_file_byte_for_byte(puma_data):
    d, data, params = puma_data
    ident = massid.identify(PUMA, data)
    assert ident.to_json() == params.read_text()
    saved = d / "saved.json"
    ident.save(saved)
    assert saved.read_text() == params.read_text()
    p = json.loads(params.read_text())
    assert ident.total_mass == p["total_mass"]
    assert [b.name for b in ident.base_parameters] == [b["name"] for b in p["base_parameters"]]
    assert [b.value for b in ident.base_parameters] == [b["value"] for b in p["base_parameters"]]
    assert [b.std for b in ident.base_parameters] == [b["std"] for b in p["base_parameters"]]
    assert ident.condition_number == p["condition_number"]
    np.testing.assert_array_equal(ident.covariance, np.array(p["covariance"]["matrix"]))
    assert ident.report() in run_cli("identify", PUMA, data, "-o", d / "again.json").stdout


def test_identify_columns_equals_identify_the_csv(puma_data):
    _, data, _ = puma_data
    columns = massid.read_csv(data)
    from_csv = massid.identify(PUMA, data)
    from_dict = massid.identify(PUMA, columns)
    np.testing.assert_allclose(from_dict.values, from_csv.values, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(from_dict.std, from_csv.std, rtol=1e-9)
    assert from_dict.source == "data"


def test_residuals_are_measured_minus_fitted_and_match_the_summary(puma_data):
    _, data, _ = puma_data
    ident = massid.identify(PUMA, data)
    cols = massid.read_csv(data)
    W = np.column_stack([cols[k] for k in ("fx", "fy", "fz", "mx", "my", "mz")])
    np.testing.assert_array_equal(ident.wrench, W)
    np.testing.assert_allclose(ident.residuals, W - ident.fitted, atol=1e-12)
    # fitted = Y_b x, from the regressor
    Yb = massid.regressor(ident.model, ident.q, ident.gravity)
    np.testing.assert_allclose(ident.fitted, Yb @ ident.values, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(np.sqrt((ident.residuals**2).mean(axis=0)), ident.residual_rms, rtol=1e-9)
    np.testing.assert_allclose(np.abs(ident.residuals).max(axis=0), ident.residual_max, rtol=1e-9)
    # correlation is the normalised covariance, unit diagonal
    np.testing.assert_allclose(np.diag(ident.correlation), 1.0, rtol=1e-12)
    rows = [i + 1 for i, l in enumerate(open(data)) if l.strip() and not l.startswith("#")]
    np.testing.assert_array_equal(ident.lines, rows[1:])  # file lines, after the header


def test_predict_is_vectorised_and_equals_the_cli(puma_data, tmp_path):
    d, data, params = puma_data
    holdout = REPO / "examples" / "puma260" / "holdout.csv"
    out = tmp_path / "pred.csv"
    run_cli("predict", PUMA, params, holdout, "-o", out)
    cols = massid.read_csv(out)
    expected = np.column_stack([cols[k + "_pred"] for k in ("fx", "fy", "fz", "mx", "my", "mz")])
    P = massid.predict(PUMA, params, holdout)
    np.testing.assert_array_equal(P, expected)  # CLI writes shortest round-trip numbers
    predictor = massid.Predictor(PUMA, massid.load_params(params))
    q = np.column_stack([cols[n] if n in cols else np.radians(cols[n + "_deg"]) for n in predictor.joint_names])
    g = np.column_stack([cols["gx"], cols["gy"], cols["gz"]])
    np.testing.assert_array_equal(predictor(q, g), P)
    np.testing.assert_array_equal(predictor.predict(q[3], g[3]), P[3])
    assert predictor(q[3], g[3]).shape == (6,)
    ident_predictor = massid.identify(PUMA, data).predictor()
    np.testing.assert_allclose(ident_predictor(q, g), P, rtol=1e-12, atol=1e-12)


def test_simulate_without_noise_is_the_direct_sum_and_the_cli(tmp_path):
    model = massid.load_model(UR)
    sim = massid.simulate(UR, UR_PLAN)
    out = tmp_path / "sim.csv"
    run_cli("simulate", UR, UR_PLAN, "-o", out)
    cli_cols = massid.read_csv(out)
    for k in ("fx", "fy", "fz", "mx", "my", "mz"):
        np.testing.assert_array_equal(sim[k], cli_cols[k])
    for i in (0, 7, 31):
        q = {n: sim[n][i] for n in model.joint_names}
        direct = direct_wrench(UR, model.sensor_link, q, np.array([sim["gx"][i], sim["gy"][i], sim["gz"][i]]))
        np.testing.assert_allclose([sim[k][i] for k in ("fx", "fy", "fz", "mx", "my", "mz")], direct, atol=1e-9)
    rep = massid.simulate(UR, UR_PLAN, repeat=3, noise_force=0.1, seed=2)
    assert len(rep["fx"]) == 3 * len(sim["fx"])
    assert np.std(rep["fx"] - np.repeat(sim["fx"], 3)) == pytest.approx(0.1, rel=0.2)


def test_design_saves_the_clis_plan(tmp_path):
    plan = massid.design(PUMA, 12, tilt_max_deg=20, seed=5)
    assert len(plan) == 12 and plan.identifiable
    mine = tmp_path / "mine.csv"
    plan.save(mine)
    theirs = tmp_path / "cli.csv"
    run_cli("design", PUMA, "--poses", "12", "--tilt-max", "20", "--seed", "5", "-o", theirs)
    assert mine.read_text() == theirs.read_text()
    cols = plan.columns()
    np.testing.assert_allclose(np.column_stack([cols["gx"], cols["gy"], cols["gz"]]), plan.gravity)
    np.testing.assert_allclose(np.linalg.norm(plan.gravity, axis=1), 9.80665, rtol=1e-12)
    assert "condition number" in plan.report()
    # The report's prose names settings as keywords where the CLI's names options.
    report = plan.report()
    assert "level_poses=0 lets the optimiser tilt every pose" in report, report
    assert "min_height=H requires a height" in report, report  # the PUMA's sensor link is low
    assert not re.search(r"--[A-Za-z]", report), report
    cli = run_cli("design", PUMA, "--poses", "12", "--tilt-max", "20", "--seed", "5", "-o", theirs)
    assert "--level-poses 0 lets the optimiser tilt every pose" in cli.stdout, cli.stdout
    assert "--min-height H requires a height" in cli.stdout, cli.stdout
    # level_poses as the CLI's --level-poses.
    flat = massid.design(PUMA, 12, tilt_max_deg=20, seed=5, level_poses=0)
    flat.save(mine)
    run_cli("design", PUMA, "--poses", "12", "--tilt-max", "20", "--seed", "5", "--level-poses", "0",
            "-o", theirs)
    assert mine.read_text() == theirs.read_text()
    assert "level poses:" not in flat.report()


def test_design_simulate_identify_recovers_the_urdf():
    model = massid.load_model(UR)
    plan = massid.design(model, 40, tilt_max_deg=25, seed=2)
    data = massid.simulate(model, plan, noise_force=0.02, noise_moment=0.002, seed=3)
    ident = massid.identify(model, data)
    truth = massid.base_parameters(model).K @ model.nominal_parameters()
    err = (ident.values - truth) / ident.std
    assert np.all(np.abs(err) < 5), err
    assert ident.total_mass == pytest.approx(model.nominal_total_mass, abs=5 * ident.total_mass_std)


def test_errors_carry_the_clis_messages(tmp_path, puma_data):
    missing = tmp_path / "nope.csv"
    r = run_cli("identify", PUMA, missing, "-o", tmp_path / "p.json", check=False)
    assert r.returncode == 2
    with pytest.raises(massid.InputError) as e:
        massid.identify(PUMA, missing)
    assert r.stderr.strip() == f"massid: error: {e.value}"
    assert str(missing) in str(e.value)
    # a joint that never moves: not identifiable (exit 3)
    _, data, _ = puma_data
    cols = massid.read_csv(data)
    cols["joint3"] = np.zeros_like(cols["joint3"])
    stuck = write_csv(tmp_path / "stuck.csv", cols)
    r = run_cli("identify", PUMA, stuck, "-o", tmp_path / "p.json", check=False)
    assert r.returncode == 3
    with pytest.raises(massid.IdentifiabilityError) as e:
        massid.identify(PUMA, stuck)
    # One message from the library; its hint spelled by each front end: the
    # CLI's option, Python's keyword (the text itself names neither).
    assert e.value.hints == [("fixed", "joint3=0")]
    assert "--" not in e.value.message and "fixed=" not in e.value.message
    assert str(e.value) == e.value.message + " (fixed={'joint3': 0})"
    assert r.stderr.strip() == f"massid: error: {e.value.message} (--fixed joint3=0)"
    with pytest.raises(massid.IdentifiabilityError):
        massid.identify(PUMA, cols)


def test_array_errors_name_the_argument_and_shape():
    model = massid.load_model(PUMA)
    with pytest.raises(massid.InputError, match=r"q \(joints joint1, joint2, joint3\): expected shape \(N, 3\)"):
        massid.standard_regressor(model, np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(massid.InputError, match="one of each per sample"):
        massid.regressor(model, np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(massid.InputError, match=r"element \[1, 2\] is nan"):
        massid.regressor(model, np.array([[0, 0, 0], [0, 0, np.nan]]), np.zeros((2, 3)))
    with pytest.raises(massid.InputError, match=r"data\['fz'\]\[2\]: nan is not a finite number"):
        cols = massid.simulate(model, massid.design(model, 5, seed=1))
        cols["fz"][2] = np.nan
        massid.identify(model, cols)
    # A joint below the sensor without a column is held (with a note); the
    # wrench is what such a dict lacks.
    with pytest.raises(massid.InputError, match="no measured wrench"):
        massid.identify(model, {"joint1": [0.0], "gx": [0.0], "gy": [0.0], "gz": [9.8]})
    with pytest.raises(massid.InputError, match="column 'fx' has 2 rows"):
        massid.identify(model, {"joint1": [0.0], "fx": [0.0, 1.0], "fy": [0.0], "fz": [0.0],
                                "mx": [0.0], "my": [0.0], "mz": [0.0]})
    assert issubclass(massid.InputError, ValueError) and issubclass(massid.IdentifiabilityError, ValueError)


def test_a_spoiled_sample_is_warned_about_and_rejected_by_robust():
    model = massid.load_model(UR)
    plan = massid.design(model, 30, tilt_max_deg=25, seed=4)
    cols = massid.simulate(model, plan, noise_force=0.05, noise_moment=0.005, seed=8, repeat=4)
    cols["fz"][7] += 3.0  # a bump of 60 sigma
    with pytest.warns(massid.MassidWarning, match="implausible") as caught:
        plain = massid.identify(model, cols)
    assert [o.sample for o in plain.outliers] == [7]
    assert plain.used.all()
    # The hint in this module's keywords, not the CLI's options.
    implausible = [w for w in plain.warnings if "implausible" in w]
    assert len(implausible) == 1 and implausible[0].endswith("(robust=True)"), plain.warnings
    assert any(str(w.message) == implausible[0] for w in caught)
    assert not any(re.search(r"--[A-Za-z]", w) for w in plain.warnings), plain.warnings
    with pytest.warns(massid.MassidWarning, match="rejected 1 of 120"):
        robust = massid.identify(model, cols, robust=True)
    assert robust.robust and not robust.used[7] and robust.used.sum() == 119
    assert abs(robust.residuals[7, 2]) > 2.5  # the bump stays in its residual


def test_drift_is_part_of_the_fitted_wrench():
    model = massid.load_model(UR)
    plan = massid.design(model, 30, tilt_max_deg=25, seed=4)
    data = massid.simulate(model, plan, noise_force=0.02, noise_moment=0.002, seed=5, repeat=4)
    n = len(data["fx"])
    t = np.linspace(0.0, 300.0, n)
    data["t"] = t
    data["fx"] = data["fx"] + 4.0 * t / 300.0  # 4 N over five minutes
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", massid.MassidWarning)
        ident = massid.identify(model, data, drift="linear")
    assert ident.drift == "linear" and len(ident.drift_names) == 6
    assert ident.drift_values[0] == pytest.approx(4.0 / 300.0, abs=5 * ident.drift_std[0])
    assert ident.residual_rms[0] < 0.03  # drift taken out of the residuals
    np.testing.assert_allclose(np.sqrt((ident.residuals**2).mean(axis=0)), ident.residual_rms, rtol=1e-6)


def test_fixed_joints_and_sensor_pass_through():
    full = massid.load_model(UR)
    name = full.joint_names[-1]
    held = massid.load_model(UR, fixed={name: 0.3})
    assert held.held == {name: 0.3} and held.num_joints == full.num_joints - 1
    with pytest.raises(massid.InputError, match="sensor= goes with a URDF path"):
        massid.identify(full, {}, sensor="x")
    with pytest.raises(massid.InputError):
        massid.load_model(UR, sensor="no_such_link")


def test_the_stub_lists_every_public_name_and_attribute():
    stub = ast.parse((pathlib.Path(massid.__file__).parent / "_massid.pyi").read_text())
    declared = {}
    for node in stub.body:
        if isinstance(node, ast.ClassDef):
            declared[node.name] = {
                n.target.id if isinstance(n, ast.AnnAssign) else n.name
                for n in node.body
                if isinstance(n, (ast.AnnAssign, ast.FunctionDef))
            }
        elif isinstance(node, ast.FunctionDef):
            declared[node.name] = set()
    from massid import _massid

    public = {n for n in dir(_massid) if not n.startswith("_")}
    assert public == set(declared), (public ^ set(declared))
    for cls, members in declared.items():
        obj = getattr(_massid, cls)
        if not isinstance(obj, type) or issubclass(obj, Exception):
            continue
        actual = {n for n in dir(obj) if not n.startswith("_")}
        assert members - {"__init__", "__call__"} == actual, (cls, members ^ actual)
    for name in public:
        assert getattr(_massid, name).__doc__, name


# ---------------------------------------------------------------------------
# A continuous static log: the robot moves from pose to pose while logging


def continuous_columns(massid, poses=30, rate=250.0, rest=1.5, move=1.0):
    """The PUMA's plan poses in order, resting `rest` s at each and moving `move` s
    between them (quintic), with the wrench of the motion (simulate dynamic=True)."""
    plan = massid.read_csv(str(PUMA_PLAN))
    names = [j.name for j in massid.load_model(str(PUMA)).joints]
    q_plan = np.column_stack([plan[n] for n in names])[:poses]
    g = np.column_stack([plan[c] for c in ("gx", "gy", "gz")])[:poses]
    q, qd, qdd, grav = [], [], [], []
    for p in range(poses):
        n_rest = int(rest * rate)
        q.append(np.repeat(q_plan[p:p + 1], n_rest, axis=0))
        qd.append(np.zeros((n_rest, len(names))))
        qdd.append(np.zeros((n_rest, len(names))))
        grav.append(np.repeat(g[p:p + 1], n_rest, axis=0))
        if p + 1 == poses:
            break
        u = (np.arange(int(move * rate)) + 1.0) / int(move * rate)
        s = u**3 * (10 - 15 * u + 6 * u**2)
        v = 30 * u**2 * (1 - u)**2 / move
        a = 60 * u * (1 - u) * (1 - 2 * u) / move**2
        dq = q_plan[p + 1] - q_plan[p]
        q.append(q_plan[p] + s[:, None] * dq)
        qd.append(v[:, None] * dq)
        qdd.append(a[:, None] * dq)
        grav.append(np.repeat(g[p:p + 1], u.size, axis=0))  # a level platform
    q, qd, qdd, grav = (np.vstack(x) for x in (q, qd, qdd, grav))
    cols = {"t": np.arange(q.shape[0]) / rate}
    for j, n in enumerate(names):
        cols[n], cols[n + "_vel"], cols[n + "_acc"] = q[:, j], qd[:, j], qdd[:, j]
    cols.update(gx=grav[:, 0], gy=grav[:, 1], gz=grav[:, 2])
    data = massid.simulate(str(PUMA), cols, dynamic=True, noise_force=0.05, noise_moment=0.005, seed=5)
    # the log has no velocities: a static log recorded while moving
    return {k: v for k, v in data.items() if not k.endswith(("_vel", "_acc"))}


def test_continuous_static_log_uses_its_rest_windows(massid, tmp_path):
    data = continuous_columns(massid)
    csv = write_csv(tmp_path / "continuous.csv", data)
    r = run_cli("identify", PUMA, csv, "-o", tmp_path / "p.json")
    assert "rest windows of a continuous log: 30 windows" in r.stdout
    params = json.loads((tmp_path / "p.json").read_text())
    rw = params["rest_windows"]
    assert rw["windows"] == 30 and rw["rows"] == len(data["t"]) and rw["samples"] == params["samples"]
    assert rw["samples"] < rw["rows"] and "joints" in rw["criterion"]
    # the same from Python, file or columns
    for source in (csv, data):
        ident = massid.identify(str(PUMA), source)
        assert ident.rest_windows["samples"] == rw["samples"] and len(ident.rest_windows["windows"]) == 30
        assert [p.value for p in ident.base_parameters] == pytest.approx(
            [p["value"] for p in params["base_parameters"]], rel=1e-9, abs=1e-12)
    # against the truth (the URDF the data came from): within 4 std; every row is far off
    model = massid.load_model(str(PUMA))
    truth = massid.base_parameters(model).K @ model.nominal_parameters()
    ident = massid.identify(str(PUMA), csv)
    with pytest.warns(massid.MassidWarning, match="implausible"):  # the moves' rows
        every = massid.identify(str(PUMA), csv, rest="off", checks=False)
    assert every.rest_windows is None and every.samples == len(data["t"])

    def worst(fit):
        return max(abs(p.value - t) / p.std for p, t in zip(fit.base_parameters, truth))
    assert worst(ident) < 4.0
    assert worst(every) > 20.0
    r = run_cli("identify", PUMA, csv, "-o", tmp_path / "off.json", "--rest", "off", "--no-checks")
    assert "rest windows" not in r.stdout
    assert "rest_windows" not in json.loads((tmp_path / "off.json").read_text())


def test_static_wrist_log_takes_gravity_from_the_arm_and_root_gravity(massid, tmp_path):
    """A tool on a wrist sensor at rest, the arm on a tilted wall, no gx,gy,gz:
    the CSV path (streamed, as the CLI), the CLI and the arrays take gravity
    from the arm's joints and root_gravity, and find the URDF's tool."""
    arm = massid.load_model(str(UR))
    wrist = massid.load_model(str(UR), sensor="wrist_3_link")
    rng = np.random.default_rng(3)
    plan = {name: rng.uniform(-3.0, 3.0, 200) for name in arm.joint_names}
    root_gravity = [-9.0, 0.0, -3.9]
    data = massid.simulate(wrist, plan, noise_force=0.05, noise_moment=0.005, seed=2, root_gravity=root_gravity)
    assert not {"gx", "gy", "gz"} & set(data)
    log = write_csv(tmp_path / "wall.csv", data)
    run_cli("identify", UR, log, "--sensor", "wrist_3_link", "--root-gravity", "-9,0,-3.9", "-o", tmp_path / "w.json")
    ident = massid.identify(str(UR), log, sensor="wrist_3_link", root_gravity=root_gravity)
    assert ident.to_json() == (tmp_path / "w.json").read_text()
    assert json.loads(ident.to_json())["gravity_from"] == "upstream joints"
    arrays = massid.identify(wrist, data, root_gravity=root_gravity)
    np.testing.assert_allclose(arrays.values, ident.values, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(arrays.std, ident.std, rtol=1e-6)
    truth = massid.base_parameters(wrist).K @ wrist.nominal_parameters()
    assert max(abs(p.value - t) / p.std for p, t in zip(ident.base_parameters, truth)) < 5.0
    # the default root gravity is another gravity: the fit misses the tool
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", massid.MassidWarning)  # implausible residuals
        wrong = massid.identify(wrist, data, checks=False)
    assert max(abs(p.value - t) / p.std for p, t in zip(wrong.base_parameters, truth)) > 10.0
