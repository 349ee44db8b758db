"""Identification in motion from Python (identify(dynamic=True), Predictor, simulate,
fourier_trajectory, base_parameters(dynamic=True)) against the CLI and against an
independent numpy computation of the wrench in motion (bench/numpy_identify_dynamic.py,
written from the URDF's XML alone).

Run: PYTHONPATH=<build>/python /usr/bin/python3 -m pytest tests/python/test_dynamic.py
"""

from __future__ import annotations

import importlib.util
import json
import math
import re
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import AXES, MOTION_OFFSET, REPO, massid_cli, write_csv

PUMA = REPO / "examples" / "puma260" / "puma260.urdf"
UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
BRANCHING = REPO / "examples" / "branching" / "branching.urdf"


def run_cli(*args: Any, check: bool = True) -> subprocess.CompletedProcess:
    r = subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"massid {' '.join(map(str, args))}: {r.returncode}\n{r.stderr}")
    return r


def numpy_dynamic() -> Any:
    """bench/numpy_identify_dynamic.py as a module (numpy only, no massid)."""
    path = REPO / "bench" / "numpy_identify_dynamic.py"
    spec = importlib.util.spec_from_file_location("numpy_identify_dynamic", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def wrench_of(cols: dict[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([cols[a] for a in AXES])


def joint_matrix(cols: dict[str, np.ndarray], names: list[str], suffix: str = "") -> np.ndarray:
    return np.column_stack([cols[n + suffix] for n in names])


def gravity_of(cols: dict[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([cols["gx"], cols["gy"], cols["gz"]])


def assert_same_fit(a: Any, b: Any) -> None:
    """Two identifications of the same samples, one in memory and one streamed
    from the file: the same base, values and std to round-off."""
    assert [p.name for p in a.base_parameters] == [p.name for p in b.base_parameters]
    np.testing.assert_allclose(a.values, b.values, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(a.std, b.std, rtol=1e-9)
    np.testing.assert_allclose(a.residual_rms, b.residual_rms, rtol=1e-9)
    assert a.samples == b.samples


def random_motion(model: Any, n: int, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    q = np.column_stack([rng.uniform(j.lower, j.upper, n) if j.limited else rng.uniform(-np.pi, np.pi, n)
                         for j in model.joints]).reshape(n, model.num_joints)
    qd = rng.normal(scale=1.5, size=(n, model.num_joints))
    qdd = rng.normal(scale=4.0, size=(n, model.num_joints))
    g = rng.normal(size=(n, 3))
    g *= 9.81 / np.linalg.norm(g, axis=1, keepdims=True)
    return q, qd, qdd, g


@pytest.fixture(scope="module")
def cli_fits(tmp_path_factory: pytest.TempPathFactory, ur_motion_csv: Path, ur_positions_csv: Path) -> dict[str, Any]:
    """massid identify --dynamic on both logs: the params files and the printed text."""
    d = tmp_path_factory.mktemp("cli")
    given = run_cli("identify", UR, ur_motion_csv, "--dynamic", "-o", d / "given.json")
    derived = run_cli("identify", UR, ur_positions_csv, "--dynamic", "--offset", "--cutoff", "8",
                      "-o", d / "derived.json")
    return {"dir": d, "given": d / "given.json", "given_out": given.stdout,
            "derived": d / "derived.json", "derived_out": derived.stdout}


# ---------------------------------------------------------------------------
# The wrench in motion against numpy


@pytest.mark.parametrize("urdf", [UR, PUMA, BRANCHING])
def test_motion_regressor_is_the_numpy_newton_euler(massid: Any, urdf: Path) -> None:
    """Y(q, qd, qdd, g) column by column (per link m, mx, my, mz, ixx ... izz) equals the
    numpy regressor of bench/numpy_identify_dynamic.py, and Y @ the URDF's parameters
    equals the numpy wrench and simulate(dynamic=True)."""
    npd = numpy_dynamic()
    model = massid.load_model(urdf)
    order, joints, theta = npd.load_urdf(str(urdf))
    assert sorted(order) == sorted(l.name for l in model.links)
    n = 40
    q, qd, qdd, g = random_motion(model, n, np.random.default_rng(7))
    by_name = lambda m: {name: m[:, j] for j, name in enumerate(model.joint_names)}  # noqa: E731
    kin = npd.link_motion(order, joints, by_name(q), by_name(qd), by_name(qdd), g)
    A = npd.regressor(order, kin)  # [6N x 10 L], link order `order`
    Y = massid.standard_regressor(model, q, g, qd=qd, qdd=qdd)
    assert Y.shape == (n, 6, 10 * model.num_links)
    # columns by (link, parameter) name
    names = model.parameter_names(dynamic=True)
    numpy_names = [f"{p}({link})" for link in order for p in npd.PARAMS]
    perm = [numpy_names.index(nm) for nm in names]
    scale = max(1.0, float(np.abs(A).max()))
    np.testing.assert_allclose(Y.reshape(6 * n, -1), A[:, perm], rtol=1e-10, atol=1e-10 * scale)
    # the URDF's inertials: same standard parameters, same wrench
    pi = model.nominal_parameters(dynamic=True)
    theta_np = np.concatenate([theta[link] for link in order])
    np.testing.assert_allclose(pi, theta_np[perm], rtol=1e-12, atol=1e-15)
    w_numpy = (A @ theta_np).reshape(n, 6)
    np.testing.assert_allclose(Y @ pi, w_numpy, rtol=1e-10, atol=1e-9)
    cols = {name: q[:, j] for j, name in enumerate(model.joint_names)}
    cols.update({name + "_vel": qd[:, j] for j, name in enumerate(model.joint_names)})
    cols.update({name + "_acc": qdd[:, j] for j, name in enumerate(model.joint_names)})
    cols.update(gx=g[:, 0], gy=g[:, 1], gz=g[:, 2])
    sim = massid.simulate(model, cols, dynamic=True)
    np.testing.assert_allclose(wrench_of(sim), w_numpy, rtol=1e-10, atol=1e-9)
    # at rest the motion regressor is the static one (first moments, rest zero)
    Y0 = massid.standard_regressor(model, q, g, qd=np.zeros_like(q), qdd=np.zeros_like(q))
    Ys = massid.standard_regressor(model, q, g)
    static_cols = [names.index(nm) for nm in model.parameter_names()]
    np.testing.assert_allclose(Y0[:, :, static_cols], Ys, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("gravity", ["varying", "level"])
def test_dynamic_base_regressor_loses_nothing(massid: Any, gravity: str) -> None:
    """Y pi = Y_b K pi for any pi (at the reduction's gravity when it is level)."""
    model = massid.load_model(UR)
    base = massid.base_parameters(model, dynamic=True, gravity_model=gravity)
    assert base.dynamic and base.gravity == gravity and base.K.shape == (len(base.names), 10 * model.num_links)
    assert base.standard_parameter_names == model.parameter_names(dynamic=True)
    q, qd, qdd, g = random_motion(model, 30, np.random.default_rng(11))
    if gravity == "level":
        g = np.tile([0.0, 0.0, -9.80665], (30, 1))
    Y = massid.standard_regressor(model, q, g, qd=qd, qdd=qdd)
    Yb = massid.regressor(model, q, g, qd=qd, qdd=qdd, base=base)
    pi = np.random.default_rng(12).normal(size=10 * model.num_links)
    np.testing.assert_allclose(Y @ pi, Yb @ (base.K @ pi), rtol=1e-9, atol=1e-9)
    if gravity == "varying":  # the default dynamic base
        np.testing.assert_array_equal(massid.regressor(model, q, g, qd=qd, qdd=qdd), Yb)


@pytest.mark.parametrize("args", [["--dynamic"], ["--dynamic", "--gravity-model", "level", "--offset"],
                                  ["--dynamic", "--moving-sensor"]])
def test_base_parameters_are_the_clis_model_output(massid: Any, args: list[str]) -> None:
    kw = {"dynamic": True, "offset": "--offset" in args, "moving_sensor": "--moving-sensor" in args,
          "gravity_model": "level" if "level" in args else "varying"}
    base = massid.base_parameters(str(UR), **kw)
    assert base.to_json() == run_cli("model", UR, *args, "--json").stdout
    assert base.report() == run_cli("model", UR, *args).stdout
    assert base.total_mass_identifiable == (kw["gravity_model"] == "varying" or not kw["offset"])
    assert base.moving_sensor == kw["moving_sensor"]
    static = massid.base_parameters(str(UR))
    assert not static.dynamic and static.gravity is None
    assert static.to_json() == run_cli("model", UR, "--json").stdout


# ---------------------------------------------------------------------------
# identify(dynamic=True) against the CLI


def test_identify_dynamic_gives_the_clis_params_file(massid: Any, cli_fits: dict[str, Any],
                                                     ur_motion_csv: Path, tmp_path: Path) -> None:
    ident = massid.identify(UR, ur_motion_csv, dynamic=True)
    text = cli_fits["given"].read_text()
    assert ident.to_json() == text
    ident.save(tmp_path / "saved.json")
    assert (tmp_path / "saved.json").read_text() == text
    assert ident.report() in cli_fits["given_out"]
    p = json.loads(text)
    assert p["model"] == "dynamic" and ident.dynamic
    assert ident.total_mass == p["total_mass"]
    assert [b.value for b in ident.base_parameters] == [b["value"] for b in p["base_parameters"]]
    assert [b.std for b in ident.base_parameters] == [b["std"] for b in p["base_parameters"]]
    assert {b.unit for b in ident.base_parameters} == {"kg", "kg m", "kg m^2"}
    assert ident.filter is None  # JOINT_vel, JOINT_acc given
    cols = massid.read_csv(ur_motion_csv)
    names = ident.model.joint_names
    np.testing.assert_array_equal(ident.q, joint_matrix(cols, names))
    np.testing.assert_array_equal(ident.qd, joint_matrix(cols, names, "_vel"))
    np.testing.assert_array_equal(ident.qdd, joint_matrix(cols, names, "_acc"))
    np.testing.assert_array_equal(ident.time, cols["t"])
    np.testing.assert_array_equal(ident.wrench, wrench_of(cols))
    assert ident.sensor_motion is None
    # fitted = Y_b(q, qd, qdd, g) x; residuals = measured - fitted
    base = massid.base_parameters(ident.model, dynamic=True, gravity_model="level")
    assert base.names == [b.name for b in ident.base_parameters]
    Yb = massid.regressor(ident.model, ident.q, ident.gravity, qd=ident.qd, qdd=ident.qdd, base=base)
    np.testing.assert_allclose(ident.fitted, Yb @ ident.values, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(ident.residuals, ident.wrench - ident.fitted, atol=1e-12)
    np.testing.assert_allclose(np.sqrt((ident.residuals ** 2).mean(axis=0)), ident.residual_rms, rtol=1e-9)
    # columns in memory: the same fit (in memory; the file was streamed: equal to round-off)
    from_dict = massid.identify(UR, cols, dynamic=True)
    assert from_dict.source == "data"
    assert_same_fit(from_dict, ident)


def test_identify_dynamic_recovers_the_urdf(massid: Any, ur_motion: dict[str, np.ndarray]) -> None:
    model = massid.load_model(UR)
    ident = massid.identify(model, ur_motion, dynamic=True)
    base = massid.base_parameters(model, dynamic=True, gravity_model="level")
    truth = base.K @ model.nominal_parameters(dynamic=True)
    err = (ident.values - truth) / ident.std
    assert np.all(np.abs(err) < 5), err
    assert ident.total_mass == pytest.approx(model.nominal_total_mass, abs=5 * ident.total_mass_std)
    assert np.all(ident.residual_rms[:3] < 0.12) and np.all(ident.residual_rms[3:] < 0.012)


def test_identify_from_positions_derives_like_the_cli(massid: Any, cli_fits: dict[str, Any],
                                                      ur_positions_csv: Path,
                                                      ur_positions: dict[str, np.ndarray]) -> None:
    ident = massid.identify(UR, ur_positions_csv, dynamic=True, offset=True, cutoff=8.0)
    text = cli_fits["derived"].read_text()
    assert ident.to_json() == text
    assert ident.report() in cli_fits["derived_out"]
    f = ident.filter
    assert f["cutoff"] == 8.0 and f["rate"] == pytest.approx(200.0) and f["rows"] == len(ur_positions["t"])
    assert f["decimation"] == math.floor(200.0 / (2 * 8.0))
    line = (f"zero-phase low-pass at 8 Hz (--cutoff), {f['half_width']} samples at each end dropped, "
            f"every {f['decimation']} filtered sample kept: {ident.samples} of {f['rows']} rows")
    assert line in cli_fits["derived_out"]
    # a level platform with offsets: the weight joins offset_fz
    assert math.isnan(ident.total_mass) and math.isnan(ident.total_mass_std)
    assert "total_mass" not in json.loads(text)
    assert "not identifiable" in repr(ident)
    # (fx, fy, mz: gravity along -z puts the weight into fz and constant moments into mx, my)
    np.testing.assert_allclose(ident.offset[[0, 1, 5]], np.array(MOTION_OFFSET)[[0, 1, 5]], atol=0.05)
    # columns in memory (the file was streamed: equal to round-off), and the
    # samples prepare_motion makes: the same
    assert_same_fit(massid.identify(UR, ur_positions, dynamic=True, offset=True, cutoff=8.0), ident)
    prep = massid.prepare_motion(UR, ur_positions_csv, cutoff=8.0)
    names = ident.model.joint_names
    np.testing.assert_array_equal(joint_matrix(prep, names), ident.q)
    np.testing.assert_array_equal(joint_matrix(prep, names, "_vel"), ident.qd)
    np.testing.assert_array_equal(joint_matrix(prep, names, "_acc"), ident.qdd)
    np.testing.assert_array_equal(wrench_of(prep), ident.wrench)
    np.testing.assert_array_equal(prep["t"], ident.time)
    np.testing.assert_array_equal(prep["row"], ident.lines - 2)  # header on line 1
    # the derived velocities are the trajectory's (a slow motion, well inside the band)
    traj = massid.fourier_trajectory(UR, harmonics=5, period=10.0, duration=20.0, rate=200.0, seed=3)
    np.testing.assert_allclose(ident.qd, joint_matrix(traj, names, "_vel")[prep["row"]], atol=2e-3)


def test_moving_sensor_below_joints_with_root_gravity(massid: Any, tmp_path: Path) -> None:
    """A wrist sensor: gravity and the sensor's motion from the joints above it."""
    full = massid.load_model(UR)
    wrist = massid.load_model(UR, sensor="wrist_3_link")
    assert wrist.num_joints == 0
    traj = massid.fourier_trajectory(full, duration=12.0, rate=100.0, period=6.0, seed=4)
    for k in ("gx", "gy", "gz"):
        del traj[k]
    root_gravity = [0.5, -1.0, -9.7]
    data = massid.simulate(wrist, traj, dynamic=True, noise_force=0.05, noise_moment=0.005, seed=2,
                           root_gravity=root_gravity)
    log = write_csv(tmp_path / "wrist.csv", data)
    run_cli("identify", UR, log, "--dynamic", "--sensor", "wrist_3_link", "--root-gravity", "0.5,-1,-9.7",
            "-o", tmp_path / "wrist.json")
    ident = massid.identify(UR, log, dynamic=True, sensor="wrist_3_link", root_gravity=root_gravity)
    assert ident.to_json() == (tmp_path / "wrist.json").read_text()
    assert ident.sensor_motion.shape == (len(data["t"]), 9) and np.abs(ident.sensor_motion).max() > 0.1
    assert json.loads(ident.to_json())["motion"]["sensor_moving"] is True
    assert_same_fit(massid.identify(wrist, data, dynamic=True, root_gravity=root_gravity), ident)
    assert massid.identify(wrist, data, dynamic=True).to_json() != ident.to_json()  # another gravity
    assert ident.total_mass == pytest.approx(wrist.nominal_total_mass, abs=5 * ident.total_mass_std)
    # prediction with the sensor's motion: the fit, and massid predict
    pr = ident.predictor()
    none = np.zeros((ident.samples, 0))
    np.testing.assert_allclose(pr(none, ident.gravity, none, none, sensor_motion=ident.sensor_motion),
                               ident.fitted, rtol=1e-10, atol=1e-9)
    run_cli("predict", UR, tmp_path / "wrist.json", log, "--root-gravity", "0.5,-1,-9.7", "-o", tmp_path / "p.csv")
    P = massid.predict(UR, tmp_path / "wrist.json", log, root_gravity=root_gravity)
    np.testing.assert_allclose(P, cli_prediction(tmp_path / "p.csv"), rtol=1e-12, atol=1e-10)


# ---------------------------------------------------------------------------
# Prediction


def cli_prediction(path: Path) -> np.ndarray:
    import massid

    cols = massid.read_csv(path)
    return np.column_stack([cols[a + "_pred"] for a in AXES])


def test_predict_dynamic_equals_the_cli(massid: Any, cli_fits: dict[str, Any], tmp_path: Path) -> None:
    params = cli_fits["derived"]  # with offsets, level platform
    traj = massid.fourier_trajectory(UR, duration=8.0, rate=200.0, period=4.0, seed=9)
    data = massid.simulate(UR, traj, dynamic=True, seed=4)
    given = write_csv(tmp_path / "given.csv", data)
    positions = {k: v for k, v in data.items() if not k.endswith(("_vel", "_acc"))}
    derived = write_csv(tmp_path / "derived.csv", positions)
    n = len(data["t"])

    run_cli("predict", UR, params, given, "-o", tmp_path / "pred_given.csv")
    P = massid.predict(UR, params, given)
    assert P.shape == (n, 6) and np.isfinite(P).all()
    np.testing.assert_allclose(P, cli_prediction(tmp_path / "pred_given.csv"), rtol=1e-12, atol=1e-10)
    np.testing.assert_array_equal(massid.predict(UR, params, data), P)

    out = run_cli("predict", UR, params, derived, "-o", tmp_path / "pred_derived.csv").stdout
    Pd = massid.predict(UR, params, derived)
    kept = np.isfinite(Pd).all(axis=1)
    h = int(re.search(r"the (\d+) rows at each end dropped", out).group(1))
    assert kept.sum() == n - 2 * h and not kept[:h].any() and not kept[-h:].any() and kept[h:-h].all()
    np.testing.assert_allclose(Pd[kept], cli_prediction(tmp_path / "pred_derived.csv"), rtol=1e-12, atol=1e-10)
    np.testing.assert_array_equal(np.isnan(Pd), np.isnan(massid.predict(UR, params, positions)))

    # the Predictor: arrays, derivatives given or derived, single samples
    pr = massid.Predictor(UR, params)
    assert pr.dynamic and pr.offset is not None and pr.offset.shape == (6,)
    names = pr.joint_names
    q, qd, qdd, g = (joint_matrix(data, names), joint_matrix(data, names, "_vel"),
                     joint_matrix(data, names, "_acc"), gravity_of(data))
    # massid.predict (fx_pred) and a Predictor both give the mechanism's wrench;
    # sensor_reading adds the identified offsets (what the sensor reads)
    np.testing.assert_allclose(pr(q, g, qd, qdd), P, rtol=1e-12, atol=1e-10)
    np.testing.assert_array_equal(pr.sensor_reading(pr(q, g, qd, qdd)), pr(q, g, qd, qdd) + pr.offset)
    # level: gravity defaults to the fit's (here its smoothed -9.80665, to rounding)
    np.testing.assert_allclose(pr.predict(q, None, qd, qdd), P, rtol=1e-12, atol=1e-10)
    np.testing.assert_array_equal(pr(q[5], g[5], qd[5], qdd[5]), pr(q, g, qd, qdd)[5])
    assert pr(q[5], g[5], qd[5], qdd[5]).shape == (6,)
    np.testing.assert_allclose(pr(q, g, t=data["t"]), Pd, rtol=1e-12, atol=1e-10)
    # On a level platform the offsets took the weight and some constant moments; the
    # fit's data had MOTION_OFFSET, the holdout none.
    W = wrench_of(data)
    np.testing.assert_allclose(P + pr.offset, W + np.array(MOTION_OFFSET), atol=0.02)


def test_identification_predictor_reproduces_the_fit(massid: Any, ur_motion_csv: Path) -> None:
    ident = massid.identify(UR, ur_motion_csv, dynamic=True)
    pr = ident.predictor()
    assert pr.dynamic and pr.offset is None
    np.testing.assert_allclose(pr(ident.q, ident.gravity, ident.qd, ident.qdd), ident.fitted,
                               rtol=1e-10, atol=1e-9)
    np.testing.assert_array_equal(pr(ident.q, None, ident.qd, ident.qdd),
                                  pr(ident.q, ident.gravity, ident.qd, ident.qdd))  # level


def test_varying_gravity_in_motion(massid: Any) -> None:
    """A platform tilting while the arm moves: gravity varies, the prediction needs it."""
    traj = massid.fourier_trajectory(UR, duration=12.0, rate=100.0, period=6.0, seed=8)
    a = 0.4 * np.sin(2 * np.pi * traj["t"] / 7.0)
    traj["gx"], traj["gz"] = 9.80665 * np.sin(a), -9.80665 * np.cos(a)
    data = massid.simulate(UR, traj, dynamic=True, noise_force=0.05, noise_moment=0.005, seed=3)
    ident = massid.identify(UR, data, dynamic=True, offset=True)
    assert json.loads(ident.to_json())["motion"]["gravity"] == "varying"
    assert ident.total_mass == pytest.approx(massid.load_model(UR).nominal_total_mass,
                                             abs=5 * ident.total_mass_std)
    pr = ident.predictor()
    with pytest.raises(massid.InputError, match=r"gravity \(gx, gy, gz\) is needed"):
        pr(ident.q, None, ident.qd, ident.qdd)
    base = massid.base_parameters(ident.model, offset=True, dynamic=True)
    assert base.names == [b.name for b in ident.base_parameters]


def test_prediction_errors_say_what_is_missing(massid: Any, cli_fits: dict[str, Any]) -> None:
    pr = massid.Predictor(UR, cli_fits["given"])
    q = np.zeros((4, 6))
    g = np.tile([0.0, 0.0, -9.81], (4, 1))
    with pytest.raises(massid.InputError, match="give qd and qdd .* or t"):
        pr(q, g)
    with pytest.raises(massid.InputError, match="qd and qdd: give both"):
        pr(q, g, qd=q)
    with pytest.raises(massid.InputError, match=r"qdd \(joints .*\): expected shape \(N, 6\)"):
        pr(q, g, q, np.zeros((4, 5)))
    with pytest.raises(massid.InputError, match="t and cutoff go with positions alone"):
        pr(q, g, q, q, t=np.arange(4.0))
    static = massid.identify(PUMA, massid.simulate(PUMA, REPO / "examples" / "puma260" / "plan.csv",
                                                   noise_force=0.05, noise_moment=0.005))
    with pytest.raises(massid.InputError, match="static .* qd, qdd"):
        static.predictor()(np.zeros(3), [0, 0, -9.81], np.zeros(3), np.zeros(3))
    with pytest.raises(massid.InputError, match="cutoff goes with dynamic parameters"):
        massid.predict(PUMA, static, REPO / "examples" / "puma260" / "holdout.csv", cutoff=5.0)


def test_identify_errors_carry_the_clis_messages(massid: Any, tmp_path: Path,
                                                 ur_positions: dict[str, np.ndarray]) -> None:
    no_time = {k: v for k, v in ur_positions.items() if k != "t"}
    log = write_csv(tmp_path / "no_time.csv", no_time)
    r = run_cli("identify", UR, log, "--dynamic", "-o", tmp_path / "p.json", check=False)
    assert r.returncode == 2
    with pytest.raises(massid.InputError) as e:
        massid.identify(UR, log, dynamic=True)
    assert r.stderr.strip() == f"massid: error: {e.value}"
    assert "JOINT_vel" in str(e.value)
    with pytest.raises(massid.InputError, match="cutoff goes with dynamic=True"):
        massid.identify(UR, log, cutoff=5.0)
    with pytest.raises(massid.InputError, match="cutoff: -1 is not a positive number"):
        massid.identify(UR, ur_positions, dynamic=True, cutoff=-1.0)
    with pytest.raises(massid.InputError, match="root_gravity: three numbers"):
        massid.identify(UR, ur_positions, dynamic=True, root_gravity=[0, 9.8])


# ---------------------------------------------------------------------------
# simulate(dynamic=True) and fourier_trajectory


def test_simulate_dynamic_equals_the_cli(massid: Any, tmp_path: Path, ur_trajectory: dict[str, np.ndarray]) -> None:
    traj_csv = write_csv(tmp_path / "traj.csv", ur_trajectory)
    args = ["--noise-force", "0.1", "--noise-moment", "0.01", "--seed", "7", "--sensor-offset", "1,2,3,0.1,0.2,0.3"]
    run_cli("simulate", UR, traj_csv, "-o", tmp_path / "sim.csv", "--dynamic", *args)
    cli = massid.read_csv(tmp_path / "sim.csv")
    for data in (ur_trajectory, traj_csv):
        sim = massid.simulate(UR, data, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=7,
                              sensor_offset=[1, 2, 3, 0.1, 0.2, 0.3])
        for a in AXES:
            np.testing.assert_array_equal(sim[a], cli[a])
        assert set(ur_trajectory) <= set(sim)
    with pytest.raises(massid.InputError, match="needs the trajectory's velocities and accelerations"):
        massid.simulate(UR, {k: v for k, v in ur_trajectory.items() if not k.endswith("_vel")
                             and not k.endswith("_acc")}, dynamic=True)


def test_fourier_trajectory_is_smooth_periodic_and_within_limits(massid: Any) -> None:
    model = massid.load_model(UR)
    rate, period = 500.0, 5.0
    tr = massid.fourier_trajectory(model, harmonics=4, period=period, duration=10.0, rate=rate, seed=2,
                                   velocity_limit={"elbow_joint": 0.5}, acceleration_limit=3.0)
    names = model.joint_names
    assert list(tr) == ["t", *names, *(n + "_vel" for n in names), *(n + "_acc" for n in names), "gx", "gy", "gz"]
    t = tr["t"]
    assert len(t) == 5001 and t[0] == 0.0 and t[-1] == pytest.approx(10.0)
    np.testing.assert_array_equal(gravity_of(tr), np.tile([0.0, 0.0, -9.80665], (len(t), 1)))
    q, qd, qdd = (joint_matrix(tr, names, s) for s in ("", "_vel", "_acc"))
    np.testing.assert_allclose(qd[0], 0.0, atol=1e-12)  # at rest at t = 0
    np.testing.assert_allclose(qdd[0], 0.0, atol=1e-9)
    p = int(period * rate)
    np.testing.assert_allclose(q[p:2 * p], q[:p], atol=1e-9)  # periodic
    # qd and qdd are the derivatives of q (central differences)
    np.testing.assert_allclose(np.gradient(q, t, axis=0)[1:-1], qd[1:-1], atol=2e-4 * np.abs(qd).max())
    np.testing.assert_allclose(np.gradient(qd, t, axis=0)[1:-1], qdd[1:-1], atol=2e-4 * np.abs(qdd).max())
    for j, joint in enumerate(model.joints):
        if joint.limited:
            margin = 0.1 * (joint.upper - joint.lower)
            assert q[:, j].min() >= joint.lower + margin - 1e-9 and q[:, j].max() <= joint.upper - margin + 1e-9
    # (the limits are judged on a grid of 400 points per harmonic and period)
    assert np.abs(qd[:, names.index("elbow_joint")]).max() <= 0.5 * (1 + 1e-4)
    assert np.abs(qdd).max() <= 3.0 * (1 + 1e-4)
    again = massid.fourier_trajectory(model, harmonics=4, period=period, duration=10.0, rate=rate, seed=2,
                                      velocity_limit={"elbow_joint": 0.5}, acceleration_limit=3.0)
    assert all(np.array_equal(again[k], tr[k]) for k in tr)
    other = massid.fourier_trajectory(model, harmonics=4, period=period, duration=10.0, rate=rate, seed=3)
    assert not np.array_equal(other[names[0]], tr[names[0]])
    with pytest.raises(massid.InputError, match="velocity_limit: no movable joint 'nope'"):
        massid.fourier_trajectory(model, velocity_limit={"nope": 1.0})
    with pytest.raises(massid.InputError, match="harmonics must be in"):
        massid.fourier_trajectory(model, harmonics=0)


def test_params_file_of_a_dynamic_fit_reads_back(massid: Any, cli_fits: dict[str, Any]) -> None:
    p = massid.load_params(cli_fits["derived"])
    assert p.dynamic and p.gravity == "level" and not p.moving_sensor
    np.testing.assert_allclose(p.gravity_vector, [0.0, 0.0, -9.80665])
    assert math.isnan(p.total_mass) and p.offset is not None
    assert any(b.unit == "kg m^2" for b in p.base_parameters)
    given = massid.load_params(cli_fits["given"])
    assert given.dynamic and given.total_mass > 0 and given.offset is None


def test_wrench_delay_is_estimated_and_applied(massid: Any, tmp_path: Path) -> None:
    """A log whose wrench arrives 2 ms late (2 rows at 1 kHz): identify --dynamic --delay
    auto finds it within 0.2 ms, prints and records it; Python agrees; a given delay is
    recorded with std 0; --delay goes with --dynamic only."""
    traj = massid.fourier_trajectory(str(UR), duration=4.0, rate=1000.0, period=4.0, seed=3)
    data = massid.simulate(str(UR), traj, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=8)
    lag = 2
    for a in AXES:
        data[a] = np.concatenate([np.repeat(data[a][:1], lag), data[a][:-lag]])  # late by 2 rows
    csv = write_csv(tmp_path / "late.csv", data)
    r = run_cli("identify", UR, csv, "--dynamic", "--delay", "auto", "-o", tmp_path / "p.json")
    assert "wrench delay behind the joints:" in r.stdout and "(estimated" in r.stdout
    delay = json.loads((tmp_path / "p.json").read_text())["delay"]
    assert delay["value"] == pytest.approx(0.002, abs=2e-4)
    assert 0 < delay["std"] < 2e-4
    ident = massid.identify(str(UR), data, dynamic=True, delay="auto")
    assert ident.delay["value"] == pytest.approx(delay["value"], abs=1e-12)
    assert ident.delay["estimated"] and len(ident.delay["scan"]) >= 17
    run_cli("identify", UR, csv, "--dynamic", "--delay", "0.002", "-o", tmp_path / "g.json")
    assert json.loads((tmp_path / "g.json").read_text())["delay"] == {"value": 0.002, "std": 0.0}
    r = run_cli("identify", UR, csv, "--delay", "auto", "-o", tmp_path / "s.json", check=False)
    assert r.returncode == 2 and "--delay goes with --dynamic" in r.stderr


@pytest.mark.parametrize("cli_args, keywords", [
    (["--delay", "auto"], {"delay": "auto"}),
    (["--dynamic", "--rest", "off"], {"dynamic": True, "rest": "off"}),
    (["--cutoff", "5"], {"cutoff": 5.0}),
    (["--drift", "quadratic"], {"drift": "quadratic"}),
    (["--dynamic", "--delay", "2ms"], {"dynamic": True, "delay": "2ms"}),
])
def test_cli_and_python_give_one_message_per_rule(massid: Any, tmp_path: Path,
                                                  cli_args: list[str],
                                                  keywords: dict[str, Any]) -> None:
    """The request's rules (identify_request.hpp): the same message from either door, each
    spelling the settings its own way (--delay / delay, --dynamic / dynamic=True)."""
    log = tmp_path / "never_read.csv"
    r = run_cli("identify", UR, log, "-o", tmp_path / "p.json", *cli_args, check=False)
    assert r.returncode == 2
    with pytest.raises(massid.InputError) as e:
        massid.identify(str(UR), str(log), **keywords)
    # The setting at fault leads the message; the one it needs is spelled as turned on.
    spelled = re.sub(r"^(delay|rest|cutoff|drift)\b", r"--\1", str(e.value))
    spelled = spelled.replace("dynamic=True", "--dynamic")
    assert r.stderr == f"massid: error: {spelled}\n"


def test_old_spellings_still_work_and_warn(massid: Any) -> None:
    """simulate(offset=...) is sensor_offset='s old spelling and base_parameters(gravity=...)
    gravity_model='s: the same results, with a DeprecationWarning."""
    traj = massid.fourier_trajectory(str(UR), duration=1.0, rate=200.0, period=1.0, seed=3)
    offset = [1, 2, 3, 0.1, 0.2, 0.3]
    new = massid.simulate(str(UR), traj, dynamic=True, sensor_offset=offset)
    with pytest.warns(DeprecationWarning, match="use sensor_offset="):
        old = massid.simulate(str(UR), traj, dynamic=True, offset=offset)
    for a in AXES:
        np.testing.assert_array_equal(old[a], new[a])
    plain = massid.simulate(str(UR), traj, dynamic=True)
    np.testing.assert_allclose(new["fy"] - plain["fy"], 2.0, atol=1e-12)
    level = massid.base_parameters(str(UR), dynamic=True, gravity_model="level")
    with pytest.warns(DeprecationWarning, match="use gravity_model="):
        old_level = massid.base_parameters(str(UR), dynamic=True, gravity="level")
    assert old_level.names == level.names and len(level.names) == 43
