"""massid.Tracker against massid compensate --track, to the bit.

The tracked logs of tests/tracker_support.hpp (written by massid_tracker_fixture:
the UR-like arm with a tool, an object grasped and put down, drifting offsets and
a contact), on a wrist sensor and on a base sensor, go through the CLI on stdin,
the reference; the same rows then go through Tracker.update one at a time and
Tracker.track at once, and every column must be the same double (the CLI writes
shortest round-trip numbers, which float() reads back exactly). Then the errors:
a wrong payload link, wrong shapes, time going back.

MASSID_TRACKER_FIXTURE names the fixture program (ctest sets it), else the one of
the build tree holding the imported package.
"""

from __future__ import annotations

import csv
import os
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import AXES, REPO, massid_cli

UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
ARM = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
       "wrist_2_joint", "wrist_3_joint")
TRACKED = ("payload_m", "payload_cx", "payload_cy", "payload_cz", "payload_m_std",
           "payload_c_std", "payload_ixx", "payload_ixy", "payload_ixz", "payload_iyy",
           "payload_iyz", "payload_izz", "offset_fx", "offset_fy", "offset_fz", "offset_mx",
           "offset_my", "offset_mz")


def fixture_program(massid: Any) -> str:
    exe = os.environ.get("MASSID_TRACKER_FIXTURE")
    if exe:
        return exe
    return str(Path(massid.__file__).resolve().parents[2] / "tests" / "massid_tracker_fixture")


def read_columns(path: Path) -> dict[str, list[str]]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    return {name: [r[k] for r in rows[1:]] for k, name in enumerate(rows[0])}


def numbers(cells: list[str]) -> np.ndarray:
    """The CLI's cells as doubles, empty ones NaN."""
    return np.array([float(c) if c else np.nan for c in cells])


def same_bits(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return (a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))


@pytest.fixture(scope="module")
def logs(massid: Any, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The fixture's logs, their params (identify --dynamic on the free logs) and
    compensate --track's output, NAME_out.csv, for NAME wrist and base."""
    d = tmp_path_factory.mktemp("tracker")
    subprocess.run([fixture_program(massid), str(d)], check=True)
    for name, sensor in (("wrist", ["--sensor", "wrist_3_link"]), ("base", [])):
        subprocess.run([massid_cli(), "identify", str(UR), str(d / f"{name}_free.csv"), "--dynamic",
                        *sensor, "-o", str(d / f"{name}.json")], check=True,
                       capture_output=True)
        with open(d / f"{name}_tracked.csv", "rb") as fin, \
                open(d / f"{name}_out.csv", "wb") as fout:
            subprocess.run([massid_cli(), "compensate", str(UR), str(d / f"{name}.json"),
                            "--track"], stdin=fin, stdout=fout, check=True, capture_output=False,
                           stderr=subprocess.DEVNULL)
    return d


def samples(logs: Path, name: str) -> dict[str, Any]:
    """The tracked log's rows as Tracker's arguments."""
    c = {k: numbers(v) for k, v in read_columns(logs / f"{name}_tracked.csv").items()}
    joints = {
        "q": np.column_stack([c[j] for j in ARM]),
        "qd": np.column_stack([c[j + "_vel"] for j in ARM]),
        "qdd": np.column_stack([c[j + "_acc"] for j in ARM]),
    }
    args: dict[str, Any] = {"t": c["t"], "wrench": np.column_stack([c[a] for a in AXES])}
    if name == "wrist":  # the arm's joints are above the sensor
        args.update(q=None, q_upstream=joints["q"], qd_upstream=joints["qd"],
                    qdd_upstream=joints["qdd"])
    else:
        args.update(joints, gravity=np.column_stack([c["gx"], c["gy"], c["gz"]]))
    return args


@pytest.mark.parametrize("name", ["wrist", "base"])
def test_track_and_update_are_compensate_track_to_the_bit(massid: Any, logs: Path,
                                                          name: str) -> None:
    cli = read_columns(logs / f"{name}_out.csv")
    args = samples(logs, name)
    n = len(args["t"])
    assert len(cli["event"]) == n == 20000

    # track(): every column, by the spec's names, from a Predictor.
    tracker = massid.Tracker(massid.Predictor(str(UR), str(logs / f"{name}.json")))
    assert tracker.payload_link == "tool"
    out = tracker.track(**args)
    names = [a + "_comp" for a in AXES] + list(TRACKED) + ["event"]
    assert list(out) == names
    for col in names[:-1]:
        assert out[col].shape == (n,)
        differ = np.flatnonzero(~same_bits(out[col], numbers(cli[col])))
        assert differ.size == 0, f"{col}: {differ.size} rows differ, first {differ[:5]}"
    assert list(out["event"]) == cli["event"]
    # The log exercises what the tracker decides: grasp and release, a contact.
    assert (out["event"] == "change").sum() == 2
    assert (out["event"] == "contact").sum() > 900
    assert np.isnan(out["payload_ixx"]).any() and not np.isnan(out["payload_ixx"]).all()

    # update(): one row at a time, from the URDF and params; the estimate's names.
    tracker = massid.Tracker(str(UR), str(logs / f"{name}.json"))
    per_row = {k: v for k, v in args.items() if v is not None and k not in ("t", "q", "wrench")}
    got = {col: np.empty(n) for col in names[:-1]}
    events = []
    for i in range(n):
        q = None if args["q"] is None else args["q"][i]
        e = tracker.update(args["t"][i], q, args["wrench"][i],
                           **{k: v[i] for k, v in per_row.items()})
        got["payload_m"][i] = e.payload_m
        got["payload_m_std"][i] = e.payload_m_std
        got["payload_c_std"][i] = e.payload_c_std
        for k, axis in enumerate("xyz"):
            got[f"payload_c{axis}"][i] = e.payload_c[k]
        inertia = e.payload_inertia
        for k, (a, b) in enumerate(((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
            got[TRACKED[6 + k]][i] = np.nan if inertia is None else inertia[a, b]
        for k, axis in enumerate(AXES):
            got[f"offset_{axis}"][i] = e.offset[k]
            got[f"{axis}_comp"][i] = e.comp[k]
        events.append(e.event)
        assert e.offset_std.shape == (6,) and (e.offset_std > 0).all()
    for col in names[:-1]:
        differ = np.flatnonzero(~same_bits(got[col], numbers(cli[col])))
        assert differ.size == 0, f"update: {col}: {differ.size} rows differ, first {differ[:5]}"
    assert events == cli["event"]
    assert tracker.estimate.payload_m == got["payload_m"][-1]


def test_exact_d2_changes_only_d2_below_the_gate(massid: Any, logs: Path) -> None:
    # exact_d2=True forms S on every sample; the default skips it where the
    # noise-only bound e^T R^-1 e (>= d2) is within the gate: the same events
    # and compensated wrench, the same d2 beyond the gate, at least it below.
    args = samples(logs, "wrist")
    per_row = {k: v for k, v in args.items() if v is not None and k not in ("t", "q", "wrench")}
    fast = massid.Tracker(str(UR), str(logs / "wrist.json"))
    exact = massid.Tracker(str(UR), str(logs / "wrist.json"), exact_d2=True)
    below = beyond = 0
    for i in range(0, 20000, 2):  # every other row: a 250 Hz log
        q = None if args["q"] is None else args["q"][i]
        kw = {k: v[i] for k, v in per_row.items()}
        a = fast.update(args["t"][i], q, args["wrench"][i], **kw)
        b = exact.update(args["t"][i], q, args["wrench"][i], **kw)
        assert a.event == b.event and (a.comp == b.comp).all() and a.payload_m == b.payload_m
        if a.d2 > 25.0:
            beyond += 1
            assert a.d2 == b.d2
        else:
            below += 1
            assert a.d2 >= b.d2 * (1 - 1e-12)
    assert beyond > 200 and below > 8000


def test_a_wrong_payload_link_names_the_measured_links(massid: Any, logs: Path) -> None:
    with pytest.raises(massid.InputError, match=r"payload link 'gripper'.*measured links.*tool"):
        massid.Tracker(str(UR), str(logs / "wrist.json"), payload_link="gripper")
    with pytest.raises(massid.InputError, match=r"sigma_force = -1"):
        massid.Tracker(str(UR), str(logs / "wrist.json"), sigma_force=-1.0)
    with pytest.raises(massid.InputError, match=r"params is needed"):
        massid.Tracker(str(UR))
    # The link given by name is the default's; a noise given is used.
    t = massid.Tracker(str(UR), str(logs / "wrist.json"), payload_link="tool", sigma_force=0.1,
                       sigma_moment=0.01)
    assert t.payload_link == "tool"


def test_wrong_shapes_and_time_give_clear_errors(massid: Any, logs: Path) -> None:
    base = massid.Tracker(str(UR), str(logs / "base.json"))
    q = np.zeros(6)
    g = np.array([0.0, 0.0, -9.80665])
    w = np.zeros(6)
    with pytest.raises(massid.InputError, match=r"wrench \(fx, fy, fz, mx, my, mz\): expected "
                       r"shape \(N, 6\) or \(6,\), got \(5\)"):
        base.update(0.0, q, np.zeros(5), q, q, g)
    with pytest.raises(massid.InputError, match=r"q \(joints shoulder_pan_joint, .*wrist_3_joint\)"
                       r": expected shape \(N, 6\) or \(6,\), got \(5\)"):
        base.update(0.0, np.zeros(5), w, q, q, g)
    with pytest.raises(massid.InputError, match=r"gravity \(gx, gy, gz\): expected shape"):
        base.update(0.0, q, w, q, q, np.zeros(2))
    with pytest.raises(massid.InputError, match=r"qd and qdd: give both"):
        base.update(0.0, q, w, q, None, g)
    # Parameters identified at one gravity (the base's, level) take it when none is given.
    level = massid.Tracker(str(UR), str(logs / "base.json"))
    assert (level.update(0.0, q, w, q, q).comp == base.update(0.0, q, w, q, q, g).comp).all()
    with pytest.raises(massid.InputError, match=r"t: element \[0\] is nan"):
        base.update(np.nan, q, w, q, q, g)
    with pytest.raises(massid.InputError, match=r"t: one time"):
        base.update(np.zeros(2), q, w, q, q, g)
    with pytest.raises(massid.InputError, match=r"wrench \(fx, fy, fz, mx, my, mz\) has 3 rows "
                       r"and t 4"):
        base.track(np.arange(4.0), np.zeros((4, 6)), np.zeros((3, 6)), gravity=np.tile(g, (4, 1)))
    with pytest.raises(massid.InputError, match=r"element \[1, 2\] is nan"):
        base.track(np.arange(2.0), np.zeros((2, 6)), np.array([w, [0, 0, np.nan, 0, 0, 0]]),
                   gravity=np.tile(g, (2, 1)))
    # Time must increase: named by its row in track().
    base.update(1.0, q, w, q, q, g)
    with pytest.raises(massid.InputError, match=r"t = 1 does not increase \(the previous "
                       r"sample's is 1\)"):
        base.update(1.0, q, w, q, q, g)
    with pytest.raises(massid.InputError, match=r"t\[1\]: .*t = 1.5 does not increase"):
        base.track(np.array([2.0, 1.5]), np.zeros((2, 6)), np.zeros((2, 6)),
                   gravity=np.tile(g, (2, 1)))
    # A wrist sensor: q_upstream for the joints above it (named), q None.
    wrist = massid.Tracker(str(UR), str(logs / "wrist.json"))
    with pytest.raises(massid.InputError, match=r"q_upstream \(joints shoulder_pan_joint, .*\): "
                       r"expected shape \(N, 6\) or \(6,\), got \(3\)"):
        wrist.update(0.0, None, w, q_upstream=np.zeros(3))
    with pytest.raises(massid.InputError, match=r"gravity \(gx, gy, gz, sensor frame\) is needed, "
                       r"or q_upstream"):
        wrist.update(0.0, None, w)
