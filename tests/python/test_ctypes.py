"""The C interface (include/massid.h) called directly through ctypes, as a user's
foreign-function binding would: libmassid_c against the massid Python module
(the same library through pybind11) and against the wrench simulated from the
URDF's own inertials, for static and dynamic params files, with mimic joints,
a moving sensor frame, and the error paths.

The library is MASSID_C_LIBRARY (ctest sets it to the build's libmassid_c.so).
"""

from __future__ import annotations

import ctypes
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import AXES, PUMA, REPO

OK, INVALID_ARGUMENT, FILE_ERROR, MODEL_MISMATCH, STATIC_PARAMS, NOT_FINITE = 0, -1, -2, -3, -4, -5
OFFSET = [1.0, -2.0, 3.0, 0.1, -0.2, 0.3]
UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
ROBOTIQ = REPO / "tests" / "data" / "robots" / "robotiq_2f_85.urdf"

c_double_p = ctypes.POINTER(ctypes.c_double)


class Predictor(ctypes.Structure):
    """The opaque massid_predictor."""


Handle = ctypes.POINTER(Predictor)


@pytest.fixture(scope="module")
def lib() -> ctypes.CDLL:
    path = os.environ.get("MASSID_C_LIBRARY")
    if not path:  # a clear failure, not a skip: CI must run this test
        pytest.fail("MASSID_C_LIBRARY is not set: the path of libmassid_c.so (ctest sets it)",
                    pytrace=False)
    lib = ctypes.CDLL(path)
    lib.massid_version.restype = ctypes.c_char_p
    lib.massid_version.argtypes = []
    lib.massid_error_string.restype = ctypes.c_char_p
    lib.massid_error_string.argtypes = [ctypes.c_int]
    lib.massid_predictor_load.restype = Handle
    lib.massid_predictor_load.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p,
                                          ctypes.c_size_t]
    lib.massid_predictor_open.restype = ctypes.c_int
    lib.massid_predictor_open.argtypes = [ctypes.c_char_p, ctypes.c_char_p,
                                          ctypes.POINTER(Handle), ctypes.c_char_p, ctypes.c_size_t]
    lib.massid_predictor_free.restype = None
    lib.massid_predictor_free.argtypes = [Handle]
    for name in ("num_joints", "is_dynamic", "has_offset"):
        f = getattr(lib, f"massid_predictor_{name}")
        f.restype = ctypes.c_int
        f.argtypes = [Handle]
    lib.massid_predictor_joint_name.restype = ctypes.c_char_p
    lib.massid_predictor_joint_name.argtypes = [Handle, ctypes.c_int]
    lib.massid_predictor_sensor_link.restype = ctypes.c_char_p
    lib.massid_predictor_sensor_link.argtypes = [Handle]
    lib.massid_predictor_offset.restype = ctypes.c_int
    lib.massid_predictor_offset.argtypes = [Handle, c_double_p]
    lib.massid_predict.restype = ctypes.c_int
    lib.massid_predict.argtypes = [Handle, c_double_p, c_double_p, c_double_p]
    lib.massid_predict_motion.restype = ctypes.c_int
    lib.massid_predict_motion.argtypes = [Handle, c_double_p, c_double_p, c_double_p, c_double_p,
                                          c_double_p]
    lib.massid_predictor_num_upstream_joints.restype = ctypes.c_int
    lib.massid_predictor_num_upstream_joints.argtypes = [Handle]
    lib.massid_predictor_upstream_joint_name.restype = ctypes.c_char_p
    lib.massid_predictor_upstream_joint_name.argtypes = [Handle, ctypes.c_int]
    lib.massid_predict_motion_upstream.restype = ctypes.c_int
    lib.massid_predict_motion_upstream.argtypes = [Handle] + [c_double_p] * 8
    lib.massid_predict_motion_sensor.restype = ctypes.c_int
    lib.massid_predict_motion_sensor.argtypes = [Handle, c_double_p, c_double_p, c_double_p,
                                                 c_double_p, c_double_p, c_double_p]
    return lib


def ptr(a: np.ndarray | None) -> Any:
    """A double* to a C-contiguous float64 array (kept alive by the caller), or NULL."""
    if a is None:
        return None
    assert a.dtype == np.float64 and a.flags["C_CONTIGUOUS"]
    return a.ctypes.data_as(c_double_p)


class CPredictor:
    """A handle and the calls of massid.h on numpy rows."""

    def __init__(self, lib: ctypes.CDLL, urdf: Path, params: Path) -> None:
        self.lib = lib
        error = ctypes.create_string_buffer(1024)
        self.handle = lib.massid_predictor_load(str(urdf).encode(), str(params).encode(), error,
                                                len(error))
        assert self.handle, error.value.decode()
        self.n = lib.massid_predictor_num_joints(self.handle)

    def close(self) -> None:
        self.lib.massid_predictor_free(self.handle)

    def joint_names(self) -> list[str]:
        return [self.lib.massid_predictor_joint_name(self.handle, i).decode() for i in range(self.n)]

    def offset(self) -> np.ndarray:
        out = np.full(6, np.nan)
        assert self.lib.massid_predictor_offset(self.handle, ptr(out)) == OK
        return out

    def predict(self, Q: np.ndarray, G: np.ndarray) -> np.ndarray:
        W = np.empty((len(G), 6))
        for i in range(len(G)):
            q, g, w = np.ascontiguousarray(Q[i]), np.ascontiguousarray(G[i]), np.empty(6)
            assert self.lib.massid_predict(self.handle, ptr(q), ptr(g), ptr(w)) == OK
            W[i] = w
        return W

    def predict_motion(self, Q: np.ndarray, QD: np.ndarray, QDD: np.ndarray, G: np.ndarray,
                       S: np.ndarray | None = None) -> np.ndarray:
        W = np.empty((len(G), 6))
        for i in range(len(G)):
            q, qd, qdd = (np.ascontiguousarray(X[i]) for X in (Q, QD, QDD))
            g, w = np.ascontiguousarray(G[i]), np.empty(6)
            if S is None:
                code = self.lib.massid_predict_motion(self.handle, ptr(q), ptr(qd), ptr(qdd), ptr(g),
                                                      ptr(w))
            else:
                s = np.ascontiguousarray(S[i])
                code = self.lib.massid_predict_motion_sensor(self.handle, ptr(q), ptr(qd), ptr(qdd),
                                                             ptr(g), ptr(s), ptr(w))
            assert code == OK, self.lib.massid_error_string(code).decode()
            W[i] = w
        return W


def columns(data: dict[str, np.ndarray], names: list[str], suffix: str = "") -> np.ndarray:
    """[N x len(names)] the columns NAME+suffix (float64, C order)."""
    n = len(next(iter(data.values())))
    return np.ascontiguousarray(np.column_stack([data[k + suffix] for k in names])
                                if names else np.zeros((n, 0)), dtype=np.float64)


def wrench(data: dict[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([data[a] for a in AXES])


# --------------------------------------------------------------------------
# Static parameters: the PUMA 260 with its wrist held, with sensor offsets.


@pytest.fixture(scope="module")
def puma_static(massid: Any, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Noise-free data with an offset at the first 100 of the 200 held-out poses (tilted up to
    25 degrees in any direction), identified with offsets; the other 100 to check."""
    urdf = PUMA / "puma260.urdf"
    data = massid.simulate(str(urdf), str(PUMA / "holdout.csv"), sensor_offset=OFFSET)
    params = tmp_path_factory.mktemp("ctypes") / "static.json"
    massid.identify(str(urdf), {k: v[:100] for k, v in data.items()}, offset=True).save(str(params))
    # the URDF's wrench at the other 100 poses, without the offset
    holdout = massid.simulate(str(urdf), {k: v[100:] for k, v in data.items()})
    return {"urdf": urdf, "params": params, "holdout": holdout}


def test_static_params_predict_the_urdfs_wrench(lib: ctypes.CDLL, massid: Any,
                                                puma_static: dict[str, Any]) -> None:
    urdf, params, holdout = puma_static["urdf"], puma_static["params"], puma_static["holdout"]
    p = CPredictor(lib, urdf, params)
    try:
        py = massid.Predictor(str(urdf), str(params))
        names = p.joint_names()
        assert names == py.joint_names and p.n == len(names) > 0
        assert lib.massid_predictor_joint_name(p.handle, p.n) is None
        assert lib.massid_predictor_sensor_link(p.handle).decode() == py.model.sensor_link
        assert lib.massid_predictor_is_dynamic(p.handle) == 0
        assert lib.massid_predictor_has_offset(p.handle) == 1
        np.testing.assert_allclose(p.offset(), OFFSET, atol=1e-9)
        np.testing.assert_allclose(p.offset(), py.offset, rtol=0, atol=0)

        Q, G = columns(holdout, names), columns(holdout, ["gx", "gy", "gz"])
        W = p.predict(Q, G)
        # the URDF's inertials (simulate, another code path) at 100 poses the fit never had
        np.testing.assert_allclose(W, wrench(holdout), rtol=0, atol=1e-9)
        # the Python module: neither its Predictor nor massid.predict adds the offset
        np.testing.assert_allclose(W, py.predict(Q, G), rtol=0, atol=1e-12)
        np.testing.assert_allclose(W, massid.predict(str(urdf), str(params), holdout),
                                   rtol=0, atol=1e-12)

        # static parameters hold no inertia: an error code, the wrench NaN
        q, g, w = np.ascontiguousarray(Q[0]), np.ascontiguousarray(G[0]), np.zeros(6)
        z = np.zeros(p.n)
        code = lib.massid_predict_motion(p.handle, ptr(q), ptr(z), ptr(z), ptr(g), ptr(w))
        assert code == STATIC_PARAMS and np.isnan(w).all()
        assert b"--dynamic" in lib.massid_error_string(code)
    finally:
        p.close()


def test_mimic_joints_are_not_inputs(lib: ctypes.CDLL, massid: Any, tmp_path: Path) -> None:
    """The Robotiq 2F-85's five mimic joints follow its one independent joint."""
    model = massid.load_model(str(ROBOTIQ))
    plan = massid.design(str(ROBOTIQ), poses=30, tilt_max_deg=40.0, seed=2).columns()
    data = massid.simulate(str(ROBOTIQ), plan)
    params = tmp_path / "robotiq.json"
    # checks=False: noise-free moments of 1e-9 N m fool the set-up check for a negated axis
    massid.identify(str(ROBOTIQ), data, checks=False).save(str(params))
    p = CPredictor(lib, ROBOTIQ, params)
    try:
        assert p.joint_names() == model.joint_names
        assert p.n == model.num_joints < ROBOTIQ.read_text().count("<joint ")
        W = p.predict(columns(data, model.joint_names), columns(data, ["gx", "gy", "gz"]))
        np.testing.assert_allclose(W, wrench(data), rtol=0, atol=1e-9)
    finally:
        p.close()


# --------------------------------------------------------------------------
# Dynamic parameters: the UR-like arm along an exciting trajectory, tilted.


@pytest.fixture(scope="module")
def ur_dynamic(massid: Any, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Noise-free wrench along a trajectory on a tilting, turning and shaking platform (the
    wx .. az columns); dynamic params with offsets, which see the platform's motion."""
    traj = massid.fourier_trajectory(str(UR), harmonics=5, period=5.0, duration=10.0, rate=100.0,
                                     seed=3)
    t = traj["t"]
    tilt = 0.4 * np.sin(0.6 * t)  # about x, up to 23 degrees
    g0 = 9.80665
    traj["gx"], traj["gy"], traj["gz"] = (np.zeros_like(t), g0 * np.sin(tilt), -g0 * np.cos(tilt))
    for k, name in enumerate(("wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az")):
        traj[name] = (0.3 + 0.1 * k) * np.sin((0.5 + 0.23 * k) * t + k)
    data = massid.simulate(str(UR), traj, dynamic=True, sensor_offset=OFFSET)
    params = tmp_path_factory.mktemp("ctypes") / "dynamic.json"
    massid.identify(str(UR), data, dynamic=True, offset=True).save(str(params))
    return {"params": params, "data": data}


def test_dynamic_params_predict_the_urdfs_wrench_in_motion(lib: ctypes.CDLL, massid: Any,
                                                           ur_dynamic: dict[str, Any]) -> None:
    params, data = ur_dynamic["params"], ur_dynamic["data"]
    p = CPredictor(lib, UR, params)
    try:
        py = massid.Predictor(str(UR), str(params))
        names = p.joint_names()
        assert names == py.joint_names
        assert lib.massid_predictor_is_dynamic(p.handle) == 1
        assert lib.massid_predictor_has_offset(p.handle) == 1
        np.testing.assert_allclose(p.offset(), OFFSET, atol=1e-7)

        rows = slice(0, None, 7)  # 143 samples
        Q, QD, QDD = (columns(data, names, s)[rows] for s in ("", "_vel", "_acc"))
        G = columns(data, ["gx", "gy", "gz"])[rows]
        S = columns(data, ["wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"])[rows]
        W = p.predict_motion(Q, QD, QDD, G, S)
        # the URDF's inertials through simulate (forward kinematics and the regressor)
        np.testing.assert_allclose(W, wrench(data)[rows] - OFFSET, rtol=0, atol=1e-7)
        # the Python module's motion predictor (the offset not included there either)
        np.testing.assert_allclose(W, py.predict(Q, G, QD, QDD, sensor_motion=S),
                                   rtol=0, atol=1e-12)

        # the sensor frame at rest
        Wr = p.predict_motion(Q, QD, QDD, G)
        np.testing.assert_allclose(Wr, py.predict(Q, G, QD, QDD), rtol=0, atol=1e-12)
        assert np.abs(Wr - W).max() > 0.1  # the platform's motion shows

        # at rest: massid_predict is the motion predictor at zero rates
        Z = np.zeros_like(Q)
        np.testing.assert_allclose(p.predict(Q, G), py.predict(Q, G, Z, Z), rtol=0,
                                   atol=1e-12)
    finally:
        p.close()


def test_wrist_sensor_below_moving_joints(lib: ctypes.CDLL, massid: Any, tmp_path: Path) -> None:
    """The UR-like arm's wrist_3_link as the sensor: the six joints above it give gravity (from
    the root's) and the sensor's motion, as massid predict computes them from their columns."""
    wrist = massid.load_model(str(UR), sensor="wrist_3_link")
    traj = massid.fourier_trajectory(massid.load_model(str(UR)), duration=6.0, rate=100.0,
                                     period=6.0, seed=4)
    for k in ("gx", "gy", "gz"):
        del traj[k]
    root_gravity = np.array([0.5, -1.0, -9.7])
    data = massid.simulate(wrist, traj, dynamic=True, root_gravity=root_gravity)
    params = tmp_path / "wrist.json"
    massid.identify(wrist, data, dynamic=True, root_gravity=root_gravity).save(str(params))
    p = CPredictor(lib, UR, params)
    try:
        assert p.n == 0
        nu = lib.massid_predictor_num_upstream_joints(p.handle)
        names = [lib.massid_predictor_upstream_joint_name(p.handle, i).decode() for i in range(nu)]
        assert nu == 6 and names == massid.load_model(str(UR)).joint_names
        rows = range(0, len(traj["t"]), 11)
        Q, QD, QDD = (columns(data, names, s) for s in ("", "_vel", "_acc"))
        none = np.zeros(1)
        W = np.empty((len(rows), 6))
        for r, i in enumerate(rows):
            qu, qdu, qddu = (np.ascontiguousarray(X[i]) for X in (Q, QD, QDD))
            w = np.empty(6)
            code = lib.massid_predict_motion_upstream(p.handle, ptr(qu), ptr(qdu), ptr(qddu),
                                                      ptr(root_gravity), ptr(none), ptr(none),
                                                      ptr(none), ptr(w))
            assert code == OK, lib.massid_error_string(code).decode()
            W[r] = w
        # the URDF's inertials, and massid.predict with the joints' columns and the root gravity
        np.testing.assert_allclose(W, wrench(data)[list(rows)], rtol=0, atol=1e-7)
        P = massid.predict(str(UR), str(params), data, root_gravity=list(root_gravity))
        np.testing.assert_allclose(W, P[list(rows)], rtol=0, atol=1e-12)
    finally:
        p.close()


# --------------------------------------------------------------------------
# Errors


def test_errors(lib: ctypes.CDLL, puma_static: dict[str, Any], tmp_path: Path) -> None:
    urdf, params = puma_static["urdf"], puma_static["params"]
    missing = tmp_path / "missing.json"
    error = ctypes.create_string_buffer(512)
    assert not lib.massid_predictor_load(str(urdf).encode(), str(missing).encode(), error, 512)
    assert str(missing) in error.value.decode()

    handle = Handle()
    code = lib.massid_predictor_open(str(urdf).encode(), str(missing).encode(),
                                     ctypes.byref(handle), error, 512)
    assert code == FILE_ERROR and not handle
    assert lib.massid_error_string(code).decode().startswith("a URDF or params file")

    # the params of the PUMA for the UR-like arm: another robot
    code = lib.massid_predictor_open(str(UR).encode(), str(params).encode(), ctypes.byref(handle),
                                     error, 512)
    assert code == MODEL_MISMATCH and not handle, error.value.decode()

    # a truncated message is NUL-terminated within the buffer
    small = ctypes.create_string_buffer(b"x" * 16, 16)
    assert not lib.massid_predictor_load(str(urdf).encode(), str(missing).encode(), small, 10)
    assert small.raw[:10] == str(missing).encode()[:9] + b"\0" and small.raw[10:] == b"x" * 6

    p = CPredictor(lib, urdf, params)
    try:
        q, g, w = np.zeros(p.n), np.array([0.0, 0.0, -9.80665]), np.zeros(6)
        assert lib.massid_predict(p.handle, None, ptr(g), ptr(w)) == INVALID_ARGUMENT
        assert np.isnan(w).all()
        assert lib.massid_predict(None, ptr(q), ptr(g), ptr(w)) == INVALID_ARGUMENT
        bad = np.array([0.0, math.nan, -9.8])
        assert lib.massid_predict(p.handle, ptr(q), ptr(bad), ptr(w)) == NOT_FINITE
        assert lib.massid_predictor_joint_name(p.handle, -1) is None
        assert lib.massid_predictor_num_joints(None) == INVALID_ARGUMENT
        assert lib.massid_predict(p.handle, ptr(q), ptr(g), ptr(w)) == OK and np.isfinite(w).all()
    finally:
        p.close()
    lib.massid_predictor_free(None)
    assert lib.massid_version().decode() == __import__("massid").__version__


# --------------------------------------------------------------------------
# Every door: one log with an identified offset through massid predict -o,
# massid compensate (stdin), the Python Predictor and the C interface.


def _doors_log(massid: Any, data: dict[str, np.ndarray], names: list[str], path: Path) -> Path:
    """data with noise on the wrench and every joint in radians, as a CSV all four doors read."""
    from conftest import write_csv

    rng = np.random.default_rng(11)
    cols = {}
    for k, v in data.items():
        if k.endswith("_deg") and k[:-4] in names:
            cols[k[:-4]] = np.radians(v)
        else:
            cols[k] = np.asarray(v, dtype=float)
    for k, sigma in zip(AXES, (0.05,) * 3 + (0.005,) * 3):
        cols[k] = cols[k] + sigma * rng.standard_normal(len(cols[k]))
    return write_csv(path, cols)


def _comp_of(table: dict[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([table[a + "_comp"] for a in AXES])


@pytest.mark.parametrize("kind", ["static", "dynamic"])
def test_every_door_gives_the_same_compensated_wrench_to_the_bit(
        kind: str, lib: ctypes.CDLL, massid: Any, puma_static: dict[str, Any],
        ur_dynamic: dict[str, Any], tmp_path: Path) -> None:
    import subprocess

    from conftest import massid_cli

    if kind == "static":
        urdf, params = puma_static["urdf"], puma_static["params"]
        data = massid.simulate(str(urdf), str(PUMA / "holdout.csv"), offset=OFFSET)
    else:
        urdf, params, data = UR, ur_dynamic["params"], ur_dynamic["data"]
    py = massid.Predictor(str(urdf), str(params))
    assert py.dynamic == (kind == "dynamic") and py.offset is not None
    log = _doors_log(massid, data, py.joint_names, tmp_path / "log.csv")
    cols = massid.read_csv(str(log))
    names = py.joint_names
    Q, G = columns(cols, names), columns(cols, ["gx", "gy", "gz"])
    M = np.ascontiguousarray(wrench(cols))

    # 1. massid predict -o
    cli = massid_cli()
    subprocess.run([cli, "predict", str(urdf), str(params), str(log), "-o",
                    str(tmp_path / "pred.csv")], check=True, capture_output=True)
    by_predict = _comp_of(massid.read_csv(str(tmp_path / "pred.csv")))
    # 2. massid compensate, the log on stdin
    with open(log, "rb") as f:
        out = subprocess.run([cli, "compensate", str(urdf), str(params)], stdin=f, check=True,
                             capture_output=True).stdout
    (tmp_path / "comp.csv").write_bytes(out)
    by_compensate = _comp_of(massid.read_csv(str(tmp_path / "comp.csv")))
    # 3. the Python Predictor: the mechanism's wrench, then compensate
    c = ctypes_predictor = CPredictor(lib, urdf, params)
    try:
        if kind == "static":
            P = py(Q, G)
            W = c.predict(Q, G)
        else:
            QD, QDD = columns(cols, names, "_vel"), columns(cols, names, "_acc")
            S = columns(cols, ["wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"])
            P = py(Q, G, QD, QDD, sensor_motion=S)
            W = c.predict_motion(Q, QD, QDD, G, S)
        by_python = py.compensate(M, P)
        # 4. the C interface: measured - wrench - offset, as massid.h documents it
        by_c = (M - W) - c.offset()
    finally:
        ctypes_predictor.close()

    assert by_predict.shape == by_compensate.shape == by_python.shape == by_c.shape == M.shape
    np.testing.assert_array_equal(by_predict, by_python)
    np.testing.assert_array_equal(by_compensate, by_python)
    np.testing.assert_array_equal(by_c, by_python)
    np.testing.assert_array_equal(W, P)  # the C and Python predictions themselves
    # the offset is in play: without it the force would be off by OFFSET
    assert np.abs(by_python[:, :3]).max() < 0.5
    assert np.abs((M - P)[:, 0] - OFFSET[0]).max() < 0.5
