#!/usr/bin/env python3
"""The numpy pipeline a user would write for dynamic identification, as an anchor.

    bench/numpy_identify_dynamic.py ROBOT.urdf DATA.csv [--sensor LINK] [--offset]
        [--cutoff HZ] [--span 2] [--decimate 1] [--params PARAMS.json] [--json]

The motion counterpart of bench/numpy_identify.py: np.loadtxt of a motion log
(t, one column per movable joint, JOINT_vel, JOINT_acc, gx,gy,gz,
fx,fy,fz,mx,my,mz); when the _vel or _acc columns are absent they are derived
from the positions by a zero-phase FIR low-pass (Blackman-windowed sinc, cutoff
--cutoff, half width --span/cutoff, default 2/cutoff) and its analytic
derivatives (np.convolve); the positions (and _vel when present, then
differentiated once for the acceleration) and the wrench are smoothed by the
same kernel, the regressor is built from the smoothed positions and
derivatives, gravity is only trimmed, the edges (one half width at each end)
are dropped and, with --decimate D, every D-th row is kept. (massid's filter,
src/identify/motion_filter.cpp, differs: half width 3/cutoff, a passband-flattening
taper, decimation floor(rate/(2 cutoff)) by default; --span 3 --decimate D
come close.)
Forward recursion of the link velocities and accelerations from the sensor
link (at rest: omega = alpha = 0, acceleration -g), vectorised over the rows;
the stacked 6N x 10L standard regressor (per link: m, mx, my, mz, ixx, ixy,
ixz, iyy, iyz, izz; inertia about the link-frame origin in the link frame);
np.linalg.lstsq on the column-normalised regressor with rcond 1e-9 (the
minimum-norm solution: identifiable combinations are determined, the rest
is not), weighted per axis like massid (sigma per axis re-estimated from the
residuals, 4 solves). The rank and the null space come from the SVD of the
column-normalised regressor on a random subset of the samples. Prints rows/s,
the total mass (when identifiable) and the residual RMS per axis.

Conventions (the project's contract):
  * measured bodies: the sensor link (--sensor, default the URDF root) and its
    subtree; sensor frame = sensor link frame, at rest;
  * child frame = parent * origin(xyz, rpy) * motion(q);
  * link L, link frame: f = m a + alpha x h + omega x (omega x h),
    n = I alpha + omega x (I omega) + h x a (a: origin acceleration minus
    gravity, h = m c, I about the origin); measured wrench (bodies on the
    sensor, moment about the sensor origin)
    w = -sum_L [R_L f_L; R_L n_L + p_L x R_L f_L];  at rest f = M g,
    m = sum m_i c_i x g.
  * --offset: w = Y pi + w0 with six constant offsets w0 as extra unknowns
    (then the total mass is no longer identifiable when g is constant: the
    sensor link's mass column [g; 0] is a force offset).

With --params (a params file of `massid identify` on the same data, with
base parameters as `terms` of {link, param, coef}, param one of m, mx, my, mz,
ixx, ixy, ixz, iyy, iyz, izz) it evaluates every base parameter on the numpy
solution and prints the largest difference relative to the parameter's std;
exit status 1 when one differs by more than 1e-3 std or the total mass by
more than 1e-9 relative (as bench/numpy_identify.py).

Needs numpy only (Debian python3-numpy: /usr/bin/python3); joint positions in
rad (m) or JOINT_deg, velocities and accelerations in rad/s, rad/s^2 (m/s...).
"""
import argparse
import json
import math
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

PARAMS = ("m", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz")
RCOND = 1e-9  # singular values below RCOND x the largest (columns normalised): undetermined


def rpy_matrix(r, p, y):
    # URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def floats(text, default):
    return [float(v) for v in text.split()] if text else default


def origin_of(element):
    o = element.find("origin") if element is not None else None
    xyz = floats(o.get("xyz") if o is not None else None, [0.0, 0.0, 0.0])
    rpy = floats(o.get("rpy") if o is not None else None, [0.0, 0.0, 0.0])
    return np.array(xyz), rpy_matrix(*rpy)


def load_urdf(path, sensor=None):
    """Measured links in tree order (sensor link first, parents before children),
    per non-sensor link its joint, per link its ten standard parameters (URDF)."""
    robot = ET.parse(path).getroot()
    links = [l.get("name") for l in robot.findall("link")]
    joints = {}
    for j in robot.findall("joint"):
        xyz, R = origin_of(j)
        axis = j.find("axis")
        limit = j.find("limit")
        a = np.array(floats(axis.get("xyz") if axis is not None else None, [1.0, 0.0, 0.0]))
        if j.get("type") not in ("revolute", "continuous", "prismatic", "fixed"):
            sys.exit(f"{path}: joint {j.get('name')}: type {j.get('type')} not supported")
        joints[j.find("child").get("link")] = {
            "name": j.get("name"),
            "type": j.get("type"),
            "parent": j.find("parent").get("link"),
            "xyz": xyz,
            "R": R,
            "axis": a / np.linalg.norm(a),
            "lower": float(limit.get("lower", "nan")) if limit is not None else math.nan,
            "upper": float(limit.get("upper", "nan")) if limit is not None else math.nan,
        }
    roots = [l for l in links if l not in joints]
    if sensor is None:
        if len(roots) != 1:
            sys.exit(f"{path}: expected one root link, found {roots}")
        sensor = roots[0]
    elif sensor not in links:
        sys.exit(f"{path}: no link {sensor}")
    order, todo = [sensor], [sensor]
    while todo:
        parent = todo.pop(0)
        for child, j in joints.items():
            if j["parent"] == parent:
                order.append(child)
                todo.append(child)
    theta = {}
    for l in robot.findall("link"):
        theta[l.get("name")] = standard_parameters(l.find("inertial"))
    return order, {c: joints[c] for c in order[1:]}, theta


def standard_parameters(inertial):
    """[m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz] of a URDF <inertial> (zeros when absent)."""
    if inertial is None:
        return np.zeros(10)
    c, Rc = origin_of(inertial)
    mass = inertial.find("mass")
    m = float(mass.get("value")) if mass is not None else 0.0
    i = inertial.find("inertia")
    get = (lambda k: float(i.get(k, "0"))) if i is not None else (lambda k: 0.0)
    Ic = np.array([[get("ixx"), get("ixy"), get("ixz")],
                   [get("ixy"), get("iyy"), get("iyz")],
                   [get("ixz"), get("iyz"), get("izz")]])
    Io = Rc @ Ic @ Rc.T + m * (c @ c * np.eye(3) - np.outer(c, c))  # about the link origin
    return np.array([m, *(m * c), Io[0, 0], Io[0, 1], Io[0, 2], Io[1, 1], Io[1, 2], Io[2, 2]])


def movable(joints):
    return [j for j in joints.values() if j["type"] != "fixed"]


def read_data(path, joints):
    """np.loadtxt of the CSV: a dict of the columns (N each)."""
    with open(path, encoding="utf-8-sig") as f:
        skip = 0
        for line in f:
            skip += 1
            if line.strip() and not line.lstrip().startswith("#"):
                header = [c.strip() for c in line.split(",")]
                break
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=skip, ndmin=2,
                      encoding="utf-8-sig")
    col = {name: data[:, i] for i, name in enumerate(header)}
    for j in movable(joints):
        if j["name"] not in col and j["name"] + "_deg" in col:
            col[j["name"]] = np.radians(col[j["name"] + "_deg"])
        if j["name"] not in col:
            sys.exit(f"{path}: no column {j['name']} (or {j['name']}_deg)")
    for k in ("gx", "gy", "gz", "fx", "fy", "fz", "mx", "my", "mz"):
        if k not in col:
            sys.exit(f"{path}: no column {k}")
    return col, data.shape[0]


# --- zero-phase FIR low-pass and its derivatives ------------------------------

def lowpass_kernels(fc, dt, span=2.0):
    """Blackman-windowed sinc of cutoff fc (Hz), half width T = span/fc, sampled at dt:
    the smoothing kernel and its first and second time derivatives, as weights
    (h(tau_k) dt) for tau_k = -K dt .. K dt. The derivative kernels are the
    analytic derivatives of the same continuous kernel (not np.gradient of the
    filtered positions), with their discrete moments corrected (below)."""
    T = span / fc  # span an integer: T is a zero of the sinc, h and h' vanish there
    K = int(math.floor(T / dt + 1e-9))
    tau = np.arange(-K, K + 1) * dt
    u = 2.0 * math.pi * fc * tau  # sinc argument: s(tau) = 2 fc sin(u)/u
    du = 2.0 * math.pi * fc
    small = np.abs(u) < 1e-2
    us = np.where(small, 1.0, u)
    f0 = np.where(small, 1 - u**2 / 6 + u**4 / 120, np.sin(us) / us)
    f1 = np.where(small, -u / 3 + u**3 / 30, (us * np.cos(us) - np.sin(us)) / us**2)
    f2 = np.where(small, -1 / 3 + u**2 / 10, ((2 - us**2) * np.sin(us) - 2 * us * np.cos(us)) / us**3)
    s0, s1, s2 = 2 * fc * f0, 2 * fc * du * f1, 2 * fc * du**2 * f2
    b1, b2 = math.pi / T, 2 * math.pi / T
    w0 = 0.42 + 0.5 * np.cos(b1 * tau) + 0.08 * np.cos(b2 * tau)
    w1 = -0.5 * b1 * np.sin(b1 * tau) - 0.08 * b2 * np.sin(b2 * tau)
    w2 = -0.5 * b1**2 * np.cos(b1 * tau) - 0.08 * b2**2 * np.cos(b2 * tau)
    h0 = s0 * w0
    h1 = s1 * w0 + s0 * w1
    h2 = s2 * w0 + 2 * s1 * w1 + s0 * w2
    h0, h1, h2 = h0 * dt, h1 * dt, h2 * dt  # weights
    # Discrete moment conditions, so that the sampled kernels are exact on a
    # constant, a ramp and a parabola like the continuous ones: the window's
    # second derivative does not vanish at +-T, and the sampled h'' leaks
    # ~dt^2 h'''(T)/6 of the DC level into the acceleration (2e-3 rad/s^2 per
    # rad of position at 10 Hz, 1 kHz; 3.6e-2 at 20 Hz). Unit DC gain of h0;
    # h1, h2 are the analytic derivatives up to these corrections.
    h0 /= h0.sum()
    h1 *= -1.0 / (tau * h1).sum()
    h2 -= h2.sum() * h0
    h2 *= 2.0 / (tau * tau * h2).sum()
    return h0, h1, h2, K


def smooth(x, kernel):
    """Zero-phase FIR (kernel indexed by tau = -K..K): y(t) = sum_k kernel_k x(t - tau_k),
    valid part only (K samples dropped at each end)."""
    return np.convolve(x, kernel, mode="valid")


def joint_motion(col, joints, fc, span=2.0, decimate=1):
    """q, qd, qdd per movable joint ([N] each), gravity [N x 3], wrench [N x 6] and a
    note; filtered (edges dropped, every decimate-th row kept) when a derivative
    column is absent."""
    mov = movable(joints)
    g = np.stack([col[k] for k in ("gx", "gy", "gz")], axis=1)
    w = np.stack([col[k] for k in ("fx", "fy", "fz", "mx", "my", "mz")], axis=1)
    has_vel = all(j["name"] + "_vel" in col for j in mov)
    has_acc = all(j["name"] + "_acc" in col for j in mov)
    q = {j["name"]: col[j["name"]] for j in mov}
    if has_vel and has_acc:
        return q, {n: col[n + "_vel"] for n in q}, {n: col[n + "_acc"] for n in q}, g, w, None
    if "t" not in col:
        sys.exit("derivatives to derive from the positions but no column t")
    t = col["t"]
    dt = (t[-1] - t[0]) / (len(t) - 1)
    if np.max(np.abs(np.diff(t) - dt)) > 1e-3 * dt:
        print(f"warning: t not uniformly sampled (dt {dt:.6g} s used)", file=sys.stderr)
    h0, h1, h2, K = lowpass_kernels(fc, dt, span)
    if len(t) <= 2 * K:
        sys.exit(f"{len(t)} rows: fewer than the filter length {2 * K + 1}")
    qf, qdf, qddf = {}, {}, {}
    for n, x in q.items():
        qf[n] = smooth(x, h0)
        if has_vel:  # smooth the measured velocity, differentiate it once
            qdf[n] = smooth(col[n + "_vel"], h0)
            qddf[n] = smooth(col[n + "_vel"], h1)
        else:
            qdf[n] = smooth(x, h1)
            qddf[n] = smooth(x, h2)
    wf = np.stack([smooth(w[:, k], h0) for k in range(6)], axis=1)
    note = (f"filtered: Blackman sinc {fc:g} Hz, {2 * K + 1} taps at {1 / dt:.6g} Hz, "
            f"{K} rows dropped at each end")
    g = g[K:len(t) - K]  # gravity is not smoothed (constant on a sensor at rest), only trimmed
    if decimate > 1:
        d = slice(None, None, decimate)
        qf, qdf, qddf = ({n: v[d] for n, v in x.items()} for x in (qf, qdf, qddf))
        g, wf = g[d], wf[d]
        note += f", every {decimate}th row kept"
    return qf, qdf, qddf, g, wf, note


# --- kinematics and regressor --------------------------------------------------

def axis_rotation(axis, angle):
    """Rodrigues, vectorised: [N x 3 x 3] rotations by angle[i] about the unit axis."""
    K = skew(axis)
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def skew(v):
    """[... x 3 x 3] cross-product matrices of [... x 3] vectors."""
    v = np.asarray(v)
    S = np.zeros(v.shape + (3,))
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    S[..., 1, 0], S[..., 2, 0], S[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return S


def rt_times(R, v):
    """R^T v for [N x 3 x 3] (or [3 x 3]) R and [N x 3] v."""
    return np.einsum("...ji,...j->...i", R, v)


def link_motion(order, joints, q, qd, qdd, g):
    """Per link: R, p (link frame in the sensor frame, [N x 3 x 3], [N x 3]) and
    omega, alpha, a (link frame, [N x 3]; a: origin acceleration minus gravity)."""
    n = g.shape[0]
    zero = np.zeros((n, 3))
    kin = {order[0]: {"R": np.broadcast_to(np.eye(3), (n, 3, 3)), "p": zero,
                      "w": zero, "dw": zero, "a": -g}}
    for link in order[1:]:
        j = joints[link]
        P = kin[j["parent"]]
        s = j["axis"]
        Rpc, t = np.broadcast_to(j["R"], (n, 3, 3)), np.broadcast_to(j["xyz"], (n, 3))
        if j["type"] in ("revolute", "continuous"):
            Rpc = j["R"] @ axis_rotation(s, q[j["name"]])
        elif j["type"] == "prismatic":
            t = t + (j["R"] @ s) * q[j["name"]][:, None]
        w = rt_times(Rpc, P["w"])
        dw = rt_times(Rpc, P["dw"])
        a = rt_times(Rpc, P["a"] + np.cross(P["dw"], t) + np.cross(P["w"], np.cross(P["w"], t)))
        if j["type"] in ("revolute", "continuous"):
            sqd = s * qd[j["name"]][:, None]
            w = w + sqd
            dw = dw + s * qdd[j["name"]][:, None] + np.cross(w, sqd)
        elif j["type"] == "prismatic":
            sqd = s * qd[j["name"]][:, None]
            a = a + s * qdd[j["name"]][:, None] + 2 * np.cross(w, sqd)
        kin[link] = {"R": P["R"] @ Rpc, "p": P["p"] + np.einsum("nij,nj->ni", P["R"], t),
                     "w": w, "dw": dw, "a": a}
    return kin


def regressor(order, kin, offset=False):
    """A [6N x (10 L [+ 6])], rows fx..mz of sample 0, then sample 1, ...; columns
    the ten standard parameters per link (PARAMS order) [, then the six offsets].

    Body regressor (link frame): f = m a + alpha x h + omega x (omega x h),
    n = I alpha + omega x (I omega) + h x a; measured w = -[R f; R n + p x R f].
    Each column is evaluated in the sensor frame (R (u x v) = R u x R v), as
    [N x 3] vectors over the samples, and stored column-major (Fortran order:
    the layout lstsq copies to), one contiguous column at a time."""
    n = kin[order[0]]["a"].shape[0]
    L = len(order)
    P = 10 * L + (6 if offset else 0)
    At = np.empty((P, n, 6))  # At[c] = column c as [N x 6]
    for i, link in enumerate(order):
        k = kin[link]
        R, p = k["R"], k["p"]
        r = [np.ascontiguousarray(R[:, :, j]) for j in range(3)]  # link axes in the sensor frame
        a_s, al_s, om_s = (np.einsum("nij,nj->ni", R, k[v]) for v in ("a", "dw", "w"))
        al, om = k["dw"], k["w"]  # link-frame components
        cols = At[10 * i:10 * i + 10]

        def put(c, F, M):  # F = R f, M = R n (None: 0), bodies' wrench in the sensor frame
            if F is None:
                cols[c, :, 0:3] = 0.0
                cols[c, :, 3:6] = -M
                return
            cols[c, :, 0:3] = -F
            cols[c, :, 3:6] = -np.cross(p, F) if M is None else -(M + np.cross(p, F))

        put(0, a_s, None)  # m: f = a
        for j in range(3):  # h_j: f = alpha x e_j + omega x (omega x e_j), n = e_j x a
            put(1 + j, np.cross(al_s, r[j]) + np.cross(om_s, np.cross(om_s, r[j])), np.cross(r[j], a_s))
        for c, (j1, j2) in enumerate(((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
            # I = E (unit entries ixx, ixy, ...): n = E alpha + omega x (E omega)
            if j1 == j2:
                Ea, Ew = r[j1] * al[:, j1, None], r[j1] * om[:, j1, None]
            else:
                Ea = r[j1] * al[:, j2, None] + r[j2] * al[:, j1, None]
                Ew = r[j1] * om[:, j2, None] + r[j2] * om[:, j1, None]
            put(4 + c, None, Ea + np.cross(om_s, Ew))
    if offset:
        At[10 * L:] = 0.0
        for c in range(6):
            At[10 * L + c, :, c] = 1.0  # w = Y pi + w0
    return At.reshape(P, 6 * n).T


# --- identification ------------------------------------------------------------

def null_space(As, rows, rng):
    """Rank and null-space basis of the column-normalised regressor, from the SVD
    of a random subset of the samples ([6N x P] with N samples)."""
    n = As.shape[0] // 6
    pick = np.sort(rng.choice(n, size=min(n, rows), replace=False))
    sub = As[(6 * pick[:, None] + np.arange(6)).reshape(-1)]
    _, s, Vt = np.linalg.svd(sub, full_matrices=False)
    if sub.shape[0] < sub.shape[1]:
        sys.exit(f"{n} samples: fewer rows than unknowns")
    rank = int((s > RCOND * s[0]).sum())
    return rank, Vt[rank:].T, s


def identify(As, y, iterations=4):
    """Per-axis weighted least squares on the column-normalised regressor, sigma
    re-estimated like massid's identify(); minimum-norm solution (rcond RCOND).

    Returns x (scaled coordinates), sigma, lstsq's rank and the seconds of the first solve."""
    n = As.shape[0] // 6
    sigma = np.ones(6)
    first, rank = None, None
    for it in range(iterations):
        t0 = time.perf_counter()
        wts = np.tile(1.0 / sigma, n)
        # rows weighted in place and restored (1 ulp) rather than copied: A is
        # 4.8 GB at 10^6 rows of a 10-link tree, and lstsq copies it once more
        As *= wts[:, None]
        x, _, rank, _ = np.linalg.lstsq(As, y * wts, rcond=RCOND)
        As /= wts[:, None]
        first = first or time.perf_counter() - t0
        r = (y - As @ x).reshape(n, 6)
        sigma = np.sqrt((r * r).sum(axis=0) / max(1.0, n - rank / 6.0))
        sigma = np.maximum(sigma, 1e-300)  # noise-free data
    return x, sigma, rank, first


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("urdf")
    ap.add_argument("data")
    ap.add_argument("--sensor", help="sensor link (default: the URDF root)")
    ap.add_argument("--offset", action="store_true", help="six constant wrench offsets as unknowns")
    ap.add_argument("--cutoff", type=float, default=10.0,
                    help="low-pass cutoff (Hz) when _vel/_acc columns are absent (default 10)")
    ap.add_argument("--span", type=float, default=2.0,
                    help="filter half width in cutoff periods, T = span/cutoff (default 2; massid: 3)")
    ap.add_argument("--decimate", type=int, default=1,
                    help="keep every D-th filtered row (default 1; massid: floor(rate/(2 cutoff)))")
    ap.add_argument("--iterations", type=int, default=4, help="weighted solves (default 4)")
    ap.add_argument("--subset", type=int, default=5000,
                    help="random samples in the SVD for rank and null space (default 5000)")
    ap.add_argument("--params", help="massid identify's params file on the same data")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()

    t0 = time.perf_counter()
    order, joints, urdf_theta = load_urdf(a.urdf, a.sensor)
    col, rows = read_data(a.data, joints)
    t_read = time.perf_counter()
    q, qd, qdd, g, w, filtered = joint_motion(col, joints, a.cutoff, a.span, a.decimate)
    del col
    t_filter = time.perf_counter()
    kin = link_motion(order, joints, q, qd, qdd, g)
    A = regressor(order, kin, a.offset)  # [6N x P], Fortran order
    del kin
    scale = np.sqrt(np.einsum("ij,ij->j", A, A))
    scale[scale == 0] = 1.0
    A /= scale  # column-normalised, in place
    y = w.reshape(-1)
    t_reg = time.perf_counter()
    rank_svd, N, _ = null_space(A, a.subset, np.random.default_rng(1))
    t_svd = time.perf_counter()
    xs, sigma, rank, first_solve = identify(A, y, a.iterations)
    t1 = time.perf_counter()
    r = (y - A @ xs).reshape(-1, 6)
    x = xs / scale
    used = g.shape[0]
    L = len(order)
    std = {(link, name): x[10 * i + k] for i, link in enumerate(order) for k, name in enumerate(PARAMS)}

    def identifiable(e):  # e . x determined: e (unscaled coordinates) normal to the null space
        es = e / scale
        return N.shape[1] == 0 or np.linalg.norm(N.T @ es) <= 1e-6 * np.linalg.norm(es)

    e_mass = np.zeros(A.shape[1])
    e_mass[0:10 * L:10] = 1.0
    total_mass = float(e_mass @ x) if identifiable(e_mass) else None
    rms = np.sqrt((r * r).mean(axis=0))
    rms_y = np.sqrt((w * w).mean(axis=0))
    out = {"rows": rows, "rows_used": used, "seconds": t1 - t0, "rows_per_s": rows / (t1 - t0),
           "rows_per_s_one_solve": rows / (t_svd - t0 + first_solve),
           "loadtxt_s": t_read - t0, "filter_s": t_filter - t_read, "regressor_s": t_reg - t_filter,
           "svd_s": t_svd - t_reg, "lstsq_s": t1 - t_svd, "filtered": filtered,
           "links": order, "standard_parameters": 10 * L, "unknowns": A.shape[1],
           "rank": int(rank), "rank_svd_subset": rank_svd,
           "total_mass": total_mass,
           "urdf_total_mass": float(sum(urdf_theta[l][0] for l in order)),
           "sigma": sigma.tolist(), "residual_rms": rms.tolist(),
           "residual_rms_relative": (rms / np.maximum(rms_y, 1e-300)).tolist()}
    if a.offset:
        out["offset"] = x[10 * L:].tolist()
    ok = True
    if a.params:
        with open(a.params) as f:
            params = json.load(f)
        worst = (abs(total_mass - params["total_mass"]) / max(1e-300, abs(params["total_mass"]))
                 if total_mass is not None and params.get("total_mass") is not None else 0.0)
        worst_std = 0.0
        for bp in params["base_parameters"]:
            value = sum(t["coef"] * std[(t["link"], t["param"])] for t in bp["terms"])
            worst_std = max(worst_std, abs(value - bp["value"]) / bp["std"])
        out["total_mass_rel_diff"] = worst
        out["base_parameters_max_diff_in_std"] = worst_std
        ok = worst_std < 1e-3 and worst < 1e-9
    if a.json:
        print(json.dumps(out, indent=2))
    else:
        mass = f"{total_mass:.6g} kg" if total_mass is not None else "not identifiable"
        print(f"numpy pipeline (dynamic): {rows} rows in {out['seconds']:.3g} s, "
              f"{out['rows_per_s']:.3g} rows/s (loadtxt {out['loadtxt_s']:.3g} s, "
              f"filter {out['filter_s']:.3g} s, regressor {out['regressor_s']:.3g} s, "
              f"rank SVD {out['svd_s']:.3g} s, lstsq x{a.iterations} {out['lstsq_s']:.3g} s; with one lstsq "
              f"{out['rows_per_s_one_solve']:.3g} rows/s); total mass {mass} "
              f"(URDF {out['urdf_total_mass']:.6g} kg)")
        print(f"{used} rows used{'; ' + filtered if filtered else ''}; {A.shape[1]} unknowns, "
              f"rank {rank} (SVD of {min(used, a.subset)} samples: {rank_svd})")
        print("residual RMS per axis (fx fy fz N, mx my mz N m): "
              + " ".join(f"{v:.3g}" for v in rms)
              + "; relative to the measured RMS: " + " ".join(f"{v:.3g}" for v in out["residual_rms_relative"]))
        if a.params:
            print(f"against {a.params}: total mass differs by {out['total_mass_rel_diff']:.2g} "
                  f"relative, base parameters by at most {out['base_parameters_max_diff_in_std']:.2g} std")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
