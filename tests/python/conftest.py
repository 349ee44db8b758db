"""Shared fixtures of the Python tests: the package, the PUMA 260 example, its data.

The compiled package is found on MASSID_PYTHONPATH or PYTHONPATH (the build's
python directory, e.g. ``PYTHONPATH=build/py/python /usr/bin/python3 -m pytest
tests/python``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import pytest

for _p in reversed([p for p in os.environ.get("MASSID_PYTHONPATH", "").split(os.pathsep) if p]):
    if _p not in sys.path:
        sys.path.insert(0, _p)

REPO = Path(__file__).resolve().parents[2]
PUMA = REPO / "examples" / "puma260"
CHROMIUM = "/usr/bin/chromium"
AXES = ("fx", "fy", "fz", "mx", "my", "mz")


def _import_massid() -> Any:
    try:
        import massid
    except ImportError as e:  # a clear failure, not a skip: CI must run these tests
        pytest.fail(f"cannot import massid ({e}); set PYTHONPATH or MASSID_PYTHONPATH to the "
                    "build's python directory (e.g. build/py/python)", pytrace=False)
    return massid


def massid_cli() -> str:
    """The massid executable: MASSID_CLI (ctest sets it), else the one of the build tree
    whose python directory holds the imported package (<build>/python/massid)."""
    exe = os.environ.get("MASSID_CLI")
    if exe:
        return exe
    return str(Path(_import_massid().__file__).resolve().parents[2] / "massid")


def write_csv(path: Path, columns: Mapping[str, Any], comment: str = "") -> Path:
    """Write columns as a CSV (header on line 1 unless a comment line precedes it)."""
    names = list(columns)
    arrays = [np.asarray(columns[n], dtype=float).reshape(-1) for n in names]
    with open(path, "w", encoding="utf-8") as f:
        if comment:
            f.write(f"# {comment}\n")
        f.write(",".join(names) + "\n")
        for row in zip(*arrays):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    return path


@pytest.fixture(scope="session")
def massid() -> Any:
    """The massid package under test."""
    return _import_massid()


@pytest.fixture(scope="session")
def package_env(massid: Any) -> dict[str, str]:
    """Environment for a subprocess that must import the same massid package."""
    env = dict(os.environ)
    root = str(Path(os.path.abspath(massid.__file__)).parent.parent)
    env["PYTHONPATH"] = os.pathsep.join([root] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env.pop("MASSID_PYTHONPATH", None)
    return env


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO


@pytest.fixture(scope="session")
def puma_urdf() -> Path:
    return PUMA / "puma260.urdf"


@pytest.fixture(scope="session")
def puma_plan() -> Path:
    """The paper's plan: 30 poses, 15 level and 15 tilted 25 deg about y."""
    return PUMA / "plan.csv"


@pytest.fixture(scope="session")
def puma_holdout() -> Path:
    """200 poses tilted up to 25 deg in any direction (joint and gravity columns only)."""
    return PUMA / "holdout.csv"


@pytest.fixture(scope="session")
def puma_data(massid: Any, puma_urdf: Path, puma_holdout: Path) -> dict[str, np.ndarray]:
    """200 simulated samples with sensor noise and a sensor offset (three+ gravity directions)."""
    return massid.simulate(str(puma_urdf), str(puma_holdout), noise_force=0.05,
                           noise_moment=0.005, sensor_offset=[1.0, -2.0, 3.0, 0.1, -0.2, 0.3], seed=3)


@pytest.fixture(scope="session")
def puma_data_csv(tmp_path_factory: pytest.TempPathFactory, puma_data: Mapping[str, Any]) -> Path:
    """puma_data as a CSV file (header on line 1, sample i on line i + 2)."""
    return write_csv(tmp_path_factory.mktemp("puma") / "data.csv", puma_data)


@pytest.fixture(scope="session")
def puma_ident(massid: Any, puma_urdf: Path, puma_data_csv: Path) -> Any:
    """The identification of puma_data (with offsets)."""
    return massid.identify(str(puma_urdf), str(puma_data_csv), offset=True)


@pytest.fixture(scope="session")
def identify_report(massid: Any, tmp_path_factory: pytest.TempPathFactory, puma_ident: Any) -> Path:
    """The HTML identification report of puma_ident."""
    from massid import report

    path = tmp_path_factory.mktemp("report") / "identify.html"
    report.write_identify_report(path, puma_ident)
    return path


@pytest.fixture(scope="session")
def chromium() -> str:
    """Debian's Chromium; the browser tests skip only when it is not installed."""
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        pytest.skip(f"{CHROMIUM} is not installed (Debian: apt-get install chromium; "
                    "scripts/test.sh installs it)")
    return CHROMIUM


# --------------------------------------------------------------------------
# Identification in motion: the UR-like arm on a level platform.

UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
MOTION_OFFSET = [1.0, -2.0, 3.0, 0.1, -0.2, 0.3]


@pytest.fixture(scope="session")
def ur_urdf() -> Path:
    return UR


@pytest.fixture(scope="session")
def ur_trajectory(massid: Any) -> dict[str, np.ndarray]:
    """An exciting trajectory of the UR-like arm: 20 s at 200 Hz, two periods of 10 s."""
    return massid.fourier_trajectory(str(UR), harmonics=5, period=10.0, duration=20.0, rate=200.0, seed=3)


@pytest.fixture(scope="session")
def ur_motion(massid: Any, ur_trajectory: Mapping[str, Any]) -> dict[str, np.ndarray]:
    """The wrench along ur_trajectory (JOINT_vel, JOINT_acc given), with noise and no offset."""
    return massid.simulate(str(UR), ur_trajectory, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=5)


@pytest.fixture(scope="session")
def ur_motion_csv(tmp_path_factory: pytest.TempPathFactory, ur_motion: Mapping[str, Any]) -> Path:
    return write_csv(tmp_path_factory.mktemp("motion") / "motion.csv", ur_motion)


@pytest.fixture(scope="session")
def ur_positions(massid: Any, ur_trajectory: Mapping[str, Any]) -> dict[str, np.ndarray]:
    """A log of positions, t, gravity and the wrench only (with a sensor offset): the
    derivatives are to be derived by the filter."""
    data = massid.simulate(str(UR), ur_trajectory, dynamic=True, noise_force=0.1, noise_moment=0.01,
                           sensor_offset=MOTION_OFFSET, seed=6)
    return {k: v for k, v in data.items() if not k.endswith(("_vel", "_acc"))}


@pytest.fixture(scope="session")
def ur_positions_csv(tmp_path_factory: pytest.TempPathFactory, ur_positions: Mapping[str, Any]) -> Path:
    return write_csv(tmp_path_factory.mktemp("motion") / "positions.csv", ur_positions)
