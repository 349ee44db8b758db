"""The HTML report of an identification in motion and of a dynamic prediction: the
pages along time, the residual spectrum, the residuals against joint velocity, the
parameters in kg m^2, and the command lines (python -m massid.report, massid --report)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import AXES, UR, massid_cli, write_csv
from test_report import Page, check_self_contained, expected_flags, parameter_scales, read_page

# along time, fitted against measured, residuals along time, spectrum, residuals
# against positions (6 joints: 2 figures) and velocities (2), correlation,
# position, velocity and acceleration coverage, gravity directions
DYNAMIC_IMAGES_UR = 13


def run_cli(*args: Any) -> subprocess.CompletedProcess:
    return subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True)


def alts(page: Page) -> list[str]:
    return [im.get("alt") or "" for im in page.images]


@pytest.fixture(scope="module")
def dynamic_ident(massid: Any, ur_positions_csv: Path) -> Any:
    """Positions only (derivatives derived at 8 Hz), offsets on a level platform."""
    return massid.identify(str(UR), ur_positions_csv, dynamic=True, offset=True, cutoff=8.0)


@pytest.fixture(scope="module")
def dynamic_report(massid: Any, tmp_path_factory: pytest.TempPathFactory, dynamic_ident: Any) -> Path:
    path = tmp_path_factory.mktemp("dynamic") / "identify.html"
    massid.report.write_identify_report(path, dynamic_ident)
    return path


def test_dynamic_identify_report_content(massid: Any, dynamic_report: Path, dynamic_ident: Any) -> None:
    text, page = read_page(dynamic_report)
    check_self_contained(text, page, DYNAMIC_IMAGES_UR)
    ident = dynamic_ident
    body = page.text
    assert "model: dynamic (in motion)" in body
    for anchor in ('id="summary"', 'id="fit"', 'id="residuals"', 'id="spectrum"', 'id="parameters"',
                   'id="correlation"', 'id="coverage"'):
        assert anchor in text
    names = alts(page)
    for alt in ("fitted and measured wrench along time", "residuals (measured − fitted) along time",
                "amplitude spectrum of the residuals", "residuals (measured − fitted) against joint velocities",
                "joint velocity histograms", "joint acceleration histograms"):
        assert alt in names, (alt, names)
    assert "delay scan" not in names and 'id="delay"' not in text  # no --delay, no section
    assert names.count("residuals (measured − fitted) against joint velocities") == 2  # 6 joints, 4 a figure
    # the weight joined offset_fz (level platform, offsets)
    assert "not identifiable" in body and "offset_fz" in body
    # the filter that derived the derivatives
    f = ident.filter
    assert "derivatives from positions" in body and f"{f['cutoff']:.3g} Hz" in body
    assert f"{f['half_width']} rows dropped at each end" in body
    assert f"({ident.samples} of {f['rows']} rows)" in body
    assert "condition number (columns scaled)" in body and f"{ident.condition_number:.4g}" in body
    # every base parameter: value, std, unit (kg m^2 for inertias), expression, flag
    units = set()
    scales = parameter_scales(ident)
    for p in ident.base_parameters:
        cls, cells = page.row(p.name)
        assert cells[1] == f"{p.value:.6g}" and cells[2] == f"{p.std:.2g}"
        assert cells[4] == p.unit and cells[5] == p.expression
        assert ("poor" in cls) == expected_flags(p.std, scales[p.name])
        units.add(cells[4])
    assert units == {"kg m", "kg m^2"} or units == {"kg", "kg m", "kg m^2"}
    assert "inertias (kg m², about each link's origin" in body


def test_dynamic_report_of_derivatives_given(massid: Any, tmp_path: Path, ur_motion_csv: Path) -> None:
    ident = massid.identify(str(UR), ur_motion_csv, dynamic=True)
    out = tmp_path / "given.html"
    massid.report.write_identify_report(out, ident)
    text, page = read_page(out)
    check_self_contained(text, page, DYNAMIC_IMAGES_UR)
    assert f"{ident.total_mass:.6g} kg" in page.text
    assert "Joint velocities and accelerations were given" in page.text
    assert "derivatives from positions" not in page.text


def test_amplitude_spectrum_reads_sine_amplitudes_and_the_noise_floor(massid: Any) -> None:
    from massid.report import amplitude_spectrum, white_noise_level

    dt, n = 0.01, 4000
    t = np.arange(n) * dt
    rng = np.random.default_rng(1)
    sine = 0.7 * np.sin(2 * np.pi * 5.0 * t)  # 5 Hz: an exact bin (200 cycles)
    noise = rng.normal(scale=0.05, size=(n, 2))
    freq, amp = amplitude_spectrum(np.column_stack([sine + noise[:, 0], noise[:, 1]]), dt)
    assert freq[-1] == pytest.approx(50.0) and amp.shape == (n // 2 + 1, 2)
    k = int(np.argmax(amp[:, 0]))
    assert freq[k] == pytest.approx(5.0) and amp[k, 0] == pytest.approx(0.7, rel=0.02)
    floor = white_noise_level(np.array([0.05]), n)[0]
    assert float(amp[1:, 1].mean()) == pytest.approx(floor, rel=0.1)


def test_report_command_line_in_motion(massid: Any, package_env: dict[str, str], tmp_path: Path,
                                       ur_positions_csv: Path, ur_trajectory: dict[str, np.ndarray]) -> None:
    def report(*args: Any) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "massid.report", *map(str, args)],
                              capture_output=True, text=True, env=package_env)

    out = tmp_path / "id.html"
    r = report("identify", UR, ur_positions_csv, "-o", out, "--dynamic", "--offset", "--cutoff", "8")
    assert r.returncode == 0, r.stderr
    text, page = read_page(out)
    assert 'id="spectrum"' in text and len(page.images) == DYNAMIC_IMAGES_UR
    r = report("identify", UR, ur_positions_csv, "-o", tmp_path / "x.html", "--cutoff", "8")
    assert r.returncode == 2 and "--cutoff and --root-gravity go with --dynamic" in r.stderr
    r = report("identify", UR, ur_positions_csv, "-o", tmp_path / "x.html", "--dynamic", "--cutoff", "-3")
    assert r.returncode == 2 and "not a positive number" in r.stderr
    assert not (tmp_path / "x.html").exists()

    # a prediction from positions alone, with the fit's params file
    params = tmp_path / "params.json"
    assert run_cli("identify", UR, ur_positions_csv, "--dynamic", "--offset", "--cutoff", "8",
                   "-o", params).returncode == 0
    hold = massid.simulate(str(UR), massid.fourier_trajectory(str(UR), duration=6.0, rate=200.0, period=3.0,
                                                              seed=9), dynamic=True, seed=4)
    hold_csv = write_csv(tmp_path / "hold.csv", {k: v for k, v in hold.items()
                                                 if not k.endswith(("_vel", "_acc"))})
    pred = tmp_path / "pred.html"
    r = report("predict", UR, params, hold_csv, "-o", pred, "--cutoff", "8")
    assert r.returncode == 0, r.stderr
    text, page = read_page(pred)
    check_self_contained(text, page, DYNAMIC_IMAGES_UR)
    assert "model: dynamic (in motion)" in page.text
    n, kept = len(hold["t"]), np.isfinite(massid.predict(str(UR), params, hold_csv, cutoff=8.0)).all(axis=1)
    assert f"{int(kept.sum())} samples" in page.text and f"the {n - int(kept.sum())} rows" in page.text
    assert "compensated wrench (measured − predicted) against joint velocities" in alts(page)
    assert "measured − predicted − the identified sensor offsets" in page.text


def test_cli_reports_in_motion(massid: Any, tmp_path: Path, ur_positions_csv: Path) -> None:
    """massid predict --report with dynamic params, massid identify --dynamic --report."""
    plain = run_cli("identify", UR, ur_positions_csv, "--dynamic", "--offset", "-o", tmp_path / "plain.json")
    assert plain.returncode == 0, plain.stderr
    pred = run_cli("predict", UR, tmp_path / "plain.json", ur_positions_csv, "--report", tmp_path / "pred.html")
    assert pred.returncode == 0, pred.stderr
    text, page = read_page(tmp_path / "pred.html")
    assert 'id="spectrum"' in text and "model: dynamic (in motion)" in page.text

    r = run_cli("identify", UR, ur_positions_csv, "--dynamic", "--offset", "-o", tmp_path / "params.json",
                "--report", tmp_path / "fit.html")
    assert (tmp_path / "params.json").read_text() == (tmp_path / "plain.json").read_text()
    fit = tmp_path / "fit.html"
    assert r.returncode == 0, r.stderr
    assert 'id="spectrum"' in fit.read_text()
    assert r.stdout.startswith(plain.stdout.replace("plain.json", "params.json"))
    fit_text, fit_page = read_page(fit)
    assert "model: dynamic (in motion)" in fit_page.text
    ident = massid.identify(str(UR), ur_positions_csv, dynamic=True, offset=True)
    for p in ident.base_parameters:
        assert fit_page.row(p.name)[1][1] == f"{p.value:.6g}"


def test_report_shows_the_delay_scan_and_the_velocity_limits(massid: Any, tmp_path: Path) -> None:
    """A wrench 3 ms late: the report's clock-alignment section gives the estimate with its
    std and draws the scan; the velocity histograms give each joint's peak against the
    URDF's <limit velocity> (3.15 rad/s on the UR-like arm's first joints)."""
    traj = massid.fourier_trajectory(str(UR), duration=4.0, rate=1000.0, period=4.0, seed=5)
    data = massid.simulate(str(UR), traj, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=2)
    for a in AXES:
        data[a] = np.concatenate([np.repeat(data[a][:1], 3), data[a][:-3]])
    ident = massid.identify(str(UR), data, dynamic=True, delay="auto")
    out = tmp_path / "late.html"
    massid.report.write_identify_report(out, ident)
    text, page = read_page(out)
    check_self_contained(text, page, DYNAMIC_IMAGES_UR + 1)
    d = ident.delay
    assert abs(d["value"] - 0.003) < 2e-4
    assert 'id="delay"' in text and "delay scan" in alts(page)
    assert f"lags the joints by {d['value'] * 1e3:.4g} ± {d['std'] * 1e3:.2g} ms" in page.text
    joint = ident.model.joints[0]
    assert joint.velocity_limit == pytest.approx(3.15)
    peak = float(np.max(np.abs(np.asarray(ident.qd)[:, 0]))) / joint.velocity_limit
    assert f"\npeaks at {peak * 100:.0f} % of its limit" in _figure_titles(ident, tmp_path)


def _figure_titles(ident: Any, tmp_path: Path) -> str:
    """The titles the velocity histograms are drawn with (read from the figure code, since
    the PNG's text is not searchable)."""
    from massid.report import _Figures, _joint_infos

    titles: list[str] = []
    with _Figures() as figs:
        orig = figs.new

        def spy(*a: Any, **k: Any) -> Any:
            fig = orig(*a, **k)
            titles.append(fig)
            return fig
        figs.new = spy  # type: ignore[method-assign]
        figs.joint_coverage(np.asarray(ident.qd), _joint_infos(ident.model), derivative=1)
    return " ".join(ax.get_title() for fig in titles for ax in fig.axes)


def test_report_shows_the_physical_bodies(massid: Any, tmp_path: Path) -> None:
    """identify(physical=True): the report's bodies section has one row per link with its
    mass, centre of mass, principal moments and consistency mark, and names the base
    parameters reproduced beyond their std."""
    traj = massid.fourier_trajectory(str(UR), duration=4.0, rate=200.0, period=4.0, seed=5)
    data = massid.simulate(str(UR), traj, dynamic=True, noise_force=0.1, noise_moment=0.01, seed=2)
    ident = massid.identify(str(UR), data, dynamic=True, physical=True)
    out = tmp_path / "bodies.html"
    massid.report.write_identify_report(out, ident)
    text, page = read_page(out)
    assert 'id="physical"' in text and 'href="#physical"' in text
    for link in ident.physical.links:
        cls, cells = page.row(link.name)
        assert cells[1] == f"{link.mass:.5g}"
        assert ("real body" in cells[-1]) and (("NOT" in cells[-1]) != link.consistent)
    worst = ident.base_parameters[ident.physical.worst].name
    assert f"{worst} {ident.physical.worst_mismatch:+.3g} std" in page.text
    beyond = [p.name for p, m in zip(ident.base_parameters, ident.physical.mismatch) if abs(m) > 1]
    assert ("Every base parameter is reproduced within its std" in page.text) == (not beyond)
