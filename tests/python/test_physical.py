"""identify(..., physical=True) and predict(..., physical=True): physically consistent
parameters from Python, checked here with numpy (pseudo-inertia eigenvalues, K pi from the
params file's own terms), and the same file as the CLI's.

Run: PYTHONPATH=<build>/python /usr/bin/python3 -m pytest tests/python/test_physical.py
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import REPO, massid_cli, write_csv

UR = REPO / "examples" / "ur_like" / "ur_like.urdf"
KINDS = ["m", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"]


def pseudo_inertia(p: np.ndarray) -> np.ndarray:
    """J = [[tr(I)/2 1 - I, h], [h^T, m]] of ten parameters (m, h, I about the origin)."""
    inertia = np.array([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]])
    J = np.zeros((4, 4))
    J[:3, :3] = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    J[:3, 3] = J[3, :3] = p[1:4]
    J[3, 3] = p[0]
    return J


@pytest.fixture(scope="module")
def log(massid: Any, tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, np.ndarray], Path]:
    traj = massid.fourier_trajectory(UR, duration=10.0, rate=200.0, seed=2)
    data = massid.simulate(UR, traj, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=3,
                           sensor_offset=[1, 2, 3, 0.1, 0.2, 0.3])
    return data, write_csv(tmp_path_factory.mktemp("physical") / "log.csv", data)


def test_identify_physical_gives_consistent_bodies_within_std(massid: Any, log: Any) -> None:
    data, _ = log
    ident = massid.identify(UR, data, dynamic=True, offset=True, physical=True)
    p = ident.physical
    assert p is not None and p.consistent and not p.static_layout
    assert len(p.links) == ident.model.num_links and p.standard.shape == (10 * len(p.links),)
    for i, link in enumerate(p.links):
        ten = p.standard[10 * i : 10 * i + 10]
        if link.prior_body and ten[0] == 0:  # a massless frame stays massless
            assert not ten.any(), link.name
            continue
        J = pseudo_inertia(ten)
        assert ten[0] > 0 and np.linalg.eigvalsh(J)[0] >= -1e-12 * np.trace(J), link.name
        assert link.mass == pytest.approx(ten[0])
        np.testing.assert_allclose(link.com, ten[1:4] / ten[0], atol=1e-12)
    assert np.abs(p.mismatch).max() <= 1.0
    assert massid.identify(UR, data, dynamic=True, offset=True).physical is None


def test_params_file_and_predict_physical(massid: Any, log: Any, tmp_path: Path) -> None:
    data, path = log
    ident = massid.identify(UR, path, dynamic=True, offset=True, physical=True)
    # the same file as the CLI's
    out = tmp_path / "cli.json"
    subprocess.run([massid_cli(), "identify", str(UR), str(path), "--dynamic", "--offset", "--physical",
                    "-o", str(out)], check=True, capture_output=True)
    assert ident.to_json() == out.read_text()
    ident.save(tmp_path / "params.json")
    params = massid.load_params(tmp_path / "params.json")
    links = params.physical
    assert set(links) == {l.name for l in ident.physical.links}
    for i, l in enumerate(ident.physical.links):
        assert [links[l.name][k] for k in KINDS] == list(ident.physical.standard[10 * i : 10 * i + 10])
    # predict(physical=True) = predict of a file whose values are K pi_phys from its terms
    j = json.loads((tmp_path / "params.json").read_text())
    for e in j["base_parameters"]:
        e["value"] = sum(t["coef"] * links[t["link"]][t["param"]] for t in e["terms"])
    del j["physical"]
    (tmp_path / "direct.json").write_text(json.dumps(j))
    phys = massid.predict(UR, tmp_path / "params.json", data, physical=True)
    direct = massid.predict(UR, tmp_path / "direct.json", data)
    np.testing.assert_allclose(phys, direct, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(massid.predict(UR, ident, data, physical=True), direct, rtol=1e-9,
                               atol=1e-9)
    assert np.abs(phys - massid.predict(UR, ident, data)).max() > 0  # not the base values
    with pytest.raises(massid.InputError, match="no \"physical\" section"):
        massid.predict(UR, tmp_path / "direct.json", data, physical=True)
