"""The HTML report (massid.report): its content, its figures and its command line."""

from __future__ import annotations

import base64
import io
import json
import math
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from typing import Any, Optional

import numpy as np
import pytest

from conftest import AXES, write_csv

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
        "track", "wbr"}
# fit, residuals against index, residuals against the 3 joints, correlation,
# joint coverage, tilt
IDENTIFY_IMAGES_PUMA = 6


class Page(HTMLParser):
    """A parsed report: images, table rows (with their class), text; strict nesting."""

    def __init__(self, text: str) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.nesting_errors: list[str] = []
        self.images: list[dict[str, Optional[str]]] = []
        self.links: list[dict[str, Optional[str]]] = []
        self.metas: list[dict[str, Optional[str]]] = []
        self.rows: list[tuple[str, list[str]]] = []  # (tr class, cell texts)
        self.text_parts: list[str] = []
        self._row: Optional[list[str]] = None
        self._row_class = ""
        self._cell: Optional[list[str]] = None
        self.feed(text)
        self.close()
        if self.stack:
            self.nesting_errors.append(f"unclosed: {self.stack}")

    def handle_starttag(self, tag: str, attrs: list[tuple[str, Optional[str]]]) -> None:
        a = dict(attrs)
        if tag == "img":
            self.images.append(a)
        elif tag == "link":
            self.links.append(a)
        elif tag == "meta":
            self.metas.append(a)
        elif tag == "tr":
            self._row, self._row_class = [], a.get("class") or ""
        elif tag in ("td", "th"):
            self._cell = []
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, Optional[str]]]) -> None:
        self.handle_starttag(tag, attrs)
        if tag not in VOID:
            self.stack.pop()

    def handle_endtag(self, tag: str) -> None:
        if not self.stack or self.stack[-1] != tag:
            self.nesting_errors.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'}")
            return
        self.stack.pop()
        if tag in ("td", "th") and self._cell is not None and self._row is not None:
            self._row.append("".join(self._cell).strip())
            self._cell = None
        elif tag == "tr" and self._row is not None:
            self.rows.append((self._row_class, self._row))
            self._row = None

    def handle_data(self, data: str) -> None:
        self.text_parts.append(data)
        if self._cell is not None:
            self._cell.append(data)

    @property
    def text(self) -> str:
        return re.sub(r"\s+", " ", " ".join(self.text_parts))

    def row(self, first_cell: str) -> tuple[str, list[str]]:
        found = [r for r in self.rows if r[1] and r[1][0] == first_cell]
        assert len(found) == 1, f"expected one table row for {first_cell!r}, found {len(found)}"
        return found[0]


def read_page(path: Path) -> tuple[str, Page]:
    text = path.read_text(encoding="utf-8")
    page = Page(text)
    assert page.nesting_errors == []
    return text, page


def decode_png(src: str) -> np.ndarray:
    """A data: URI's PNG as an image array (checks the signature)."""
    import matplotlib.image

    prefix = "data:image/png;base64,"
    assert src.startswith(prefix), src[:40]
    raw = base64.b64decode(src[len(prefix):], validate=True)
    assert raw[:8] == PNG_SIGNATURE
    return matplotlib.image.imread(io.BytesIO(raw), format="png")


def check_self_contained(text: str, page: Page, images: int) -> None:
    """One file, no script, no network; N valid, non-blank PNG figures."""
    low = text.lower()
    assert "http://" not in low and "https://" not in low
    assert "<script" not in low
    assert any(m.get("charset", "").lower() == "utf-8" for m in page.metas)
    assert {"rel": "icon", "href": "data:,"} in page.links
    assert len(page.images) == images
    for im in page.images:
        assert im.get("alt")
        pixels = decode_png(im["src"] or "")
        assert pixels.ndim == 3 and pixels.shape[2] in (3, 4)
        h, w = pixels.shape[:2]
        assert 250 <= w <= 1500 and 250 <= h <= 1500, (w, h)
        assert float(pixels[..., :3].std()) > 0.05  # drawn on, not a blank canvas


def parameter_scales(ident: Any) -> dict[str, float]:
    """The scale of each base parameter from the params file: M L^k for kg m^k."""
    return {p["name"]: p["scale"] for p in json.loads(ident.to_json())["base_parameters"]}


def expected_flags(std: float, scale: float) -> bool:
    """The report's rule: std > 1 % of the parameter's scale M L^k."""
    return abs(std) > 0.01 * scale


def check_scales(ident: Any, lo: float, hi: float) -> dict[str, float]:
    """The scales are the identified M times one length L (lo..hi m) to the unit's power."""
    scales = parameter_scales(ident)
    power = {"kg": 0, "kg m": 1, "kg m^2": 2}
    mass = ident.total_mass if math.isfinite(ident.total_mass) else None
    lengths = set()
    for p in ident.base_parameters:
        k = power[p.unit]
        if mass is not None and k == 0:
            assert scales[p.name] == pytest.approx(mass, rel=1e-12)
        if k > 0 and mass is not None:
            lengths.add(round((scales[p.name] / mass) ** (1.0 / k), 9))
    assert len(lengths) <= 1
    for length in lengths:
        assert lo <= length <= hi
    return scales


# --------------------------------------------------------------------------
# Identification report


def test_identify_report_content(massid: Any, identify_report: Path, puma_ident: Any) -> None:
    text, page = read_page(identify_report)
    check_self_contained(text, page, IDENTIFY_IMAGES_PUMA)
    ident = puma_ident
    body = page.text
    assert "puma260" in body and str(ident.source) in body
    assert f"massid {massid.__version__}" in body
    assert f"{ident.samples} samples" in body
    assert f"{ident.total_mass:.6g} kg" in body
    assert f"± {ident.total_mass_std:.2g} kg" in body
    assert f"{ident.condition_number:.4g}" in body
    assert "No warnings." in body or all(w in body for w in ident.warnings)
    # every base parameter with its value, std, unit and expression
    scales = check_scales(ident, 0.2, 1.0)  # the PUMA 260 reaches about half a metre
    for p in ident.base_parameters:
        cls, cells = page.row(p.name)
        assert cells[1] == f"{p.value:.6g}"
        assert cells[2] == f"{p.std:.2g}"
        assert cells[4] == p.unit and cells[5] == p.expression
        assert ("poor" in cls) == expected_flags(p.std, scales[p.name])
    # the six offsets follow, in their units
    for k, a in enumerate(AXES):
        _, cells = page.row(f"offset_{a}")
        assert cells[1] == f"{ident.offset[k]:.6g}"
        assert cells[4] == ("N" if a[0] == "f" else "N m")
    # per-axis figures: noise sigma and residual RMS
    _, sigma_row = page.row("noise sigma (estimated)" if ident.sigma_estimated else "noise sigma (given)")
    assert sigma_row[1:] == [f"{s:.4g}" for s in ident.sigma]
    _, rms_row = page.row("residual RMS")
    assert rms_row[1:] == [f"{s:.4g}" for s in ident.residual_rms]
    # the correlation of the offsets and first moments is named when strong
    corr = np.asarray(ident.correlation)
    strong = np.abs(corr - np.eye(len(corr))) >= 0.9
    assert ("Strongly correlated pairs" in body) == bool(strong.any())


def test_identify_report_flags_poorly_determined_parameters(massid: Any, tmp_path: Path,
                                                            puma_urdf: Path, puma_plan: Path) -> None:
    # the paper's 30 poses with 200-400x the noise: some parameters get lost in it
    data = massid.simulate(str(puma_urdf), str(puma_plan), noise_force=10.0, noise_moment=2.0, seed=1)
    ident = massid.identify(str(puma_urdf), data, checks=False)
    out = tmp_path / "noisy.html"
    massid.report.write_identify_report(out, ident, title="noisy <PUMA> & co")
    text, page = read_page(out)
    assert "<title>noisy &lt;PUMA&gt; &amp; co</title>" in text  # escaped
    scales = check_scales(ident, 0.2, 1.0)
    expected = {p.name for p in ident.base_parameters if expected_flags(p.std, scales[p.name])}
    flagged = {cells[0] for cls, cells in page.rows if "poor" in cls}
    assert expected and len(expected) < len(ident.base_parameters)
    assert flagged == expected
    near_zero = {p.name for p in ident.base_parameters if abs(p.value) < 2 * p.std}
    for p in ident.base_parameters:
        note = page.row(p.name)[1][6]
        assert ("of the robot's scale" in note) == (p.name in expected)
        if p.name not in expected:
            assert ("0 within 2 std" in note) == (p.name in near_zero)
    assert f"{len(expected)} poorly determined parameter(s)." in page.text


def test_parameters_zero_by_symmetry_are_not_poorly_determined(massid: Any, tmp_path: Path) -> None:
    """The published UR5's symmetric links make 10 of its 16 base parameters zero; with a
    designed plan and ordinary noise they are as well determined as the rest: none is
    flagged, while 0 lies within 2 std of several (the note says so)."""
    urdf = str(Path(__file__).resolve().parents[1] / "data" / "robots" / "ur5_robot.urdf")
    plan = massid.design(urdf, poses=40, tilt_max_deg=10)
    data = massid.simulate(urdf, plan, noise_force=0.05, noise_moment=0.005, seed=2)
    ident = massid.identify(urdf, data)
    out = tmp_path / "ur.html"
    massid.report.write_identify_report(out, ident)
    _, page = read_page(out)
    scales = check_scales(ident, 0.5, 2.0)
    near_zero = [p.name for p in ident.base_parameters if abs(p.value) < 2 * p.std]
    assert len(near_zero) >= 2, [(p.name, p.value, p.std) for p in ident.base_parameters]
    assert [cells[0] for cls, cells in page.rows if "poor" in cls] == []
    for name in near_zero:
        assert page.row(name)[1][6] == "0 within 2 std (zero by symmetry?)"
    assert all(p.std < 0.01 * scales[p.name] for p in ident.base_parameters)
    assert "Every base parameter is determined to better than 1 % of its scale." in page.text


def test_predict_report_takes_what_predict_takes(massid: Any, tmp_path: Path, puma_urdf: Path,
                                                 puma_data_csv: Path, puma_params: Path,
                                                 puma_ident: Any) -> None:
    """A params path, a massid.Params and a massid.Identification (robot None: its model)."""
    pages = []
    for name, robot, params in (("path", puma_urdf, puma_params),
                                ("params", puma_urdf, massid.load_params(puma_params)),
                                ("ident", None, puma_ident)):
        out = tmp_path / f"{name}.html"
        massid.report.write_predict_report(out, robot, params, puma_data_csv)
        pages.append(read_page(out)[1])
    for page in pages[1:]:
        assert page.row("M")[1][1:3] == pages[0].row("M")[1][1:3]  # value and std
    with pytest.raises(massid.InputError, match="params: expected a params file path"):
        massid.report.write_predict_report(tmp_path / "x.html", puma_urdf, 42, puma_data_csv)
    assert not (tmp_path / "x.html").exists()


def test_outliers_are_listed_and_rejected_ones_marked(massid: Any, tmp_path: Path, puma_urdf: Path,
                                                      puma_data: dict[str, np.ndarray]) -> None:
    spoiled = {k: np.array(v, dtype=float) for k, v in puma_data.items()}
    bad = [17, 120]
    for i in bad:  # a bump: 3 N and 0.4 N m
        spoiled["fx"][i] += 3.0
        spoiled["my"][i] -= 0.4
    csv = write_csv(tmp_path / "spoiled.csv", spoiled)
    for robust in (False, True):
        expected_warning = "rejected 2 of 200 samples" if robust else "implausible"
        with pytest.warns(massid.MassidWarning, match=expected_warning):
            ident = massid.identify(str(puma_urdf), str(csv), offset=True, robust=robust)
        assert sorted(o.sample for o in ident.outliers) == bad
        out = tmp_path / f"outliers_{robust}.html"
        massid.report.write_identify_report(out, ident)
        text, page = read_page(out)
        check_self_contained(text, page, IDENTIFY_IMAGES_PUMA)
        header = [cells for _, cells in page.rows if cells[:3] == ["line", "sample", "score d"]]
        assert len(header) == 1
        for o in ident.outliers:
            assert o.line == o.sample + 2  # the CSV header is line 1
            _, cells = page.row(str(o.line))
            assert cells[1] == str(o.sample)
            assert cells[2] == f"{o.score:.4g}" and o.score > ident.outlier_threshold
            assert cells[3] == ("rejected" if robust else "used")
        assert (f"({len(bad)} rejected)" in page.text) == robust
        assert any(expected_warning in w for w in ident.warnings)
        assert all(" ".join(w.split()) in page.text for w in ident.warnings)  # whole, unescaped


def test_report_without_outliers_has_no_outlier_table(identify_report: Path, puma_ident: Any) -> None:
    _, page = read_page(identify_report)
    has_table = any(cells[:3] == ["line", "sample", "score d"] for _, cells in page.rows)
    assert has_table == bool(puma_ident.outliers)


def test_large_logs_are_subsampled_in_scatter_plots(massid: Any, tmp_path: Path, puma_urdf: Path,
                                                    puma_plan: Path) -> None:
    data = massid.simulate(str(puma_urdf), str(puma_plan), noise_force=0.05, noise_moment=0.005,
                           repeat=700, seed=2)  # 21 000 samples
    ident = massid.identify(str(puma_urdf), data)
    assert ident.samples == 21000
    out = tmp_path / "large.html"
    massid.report.write_identify_report(out, ident)
    text, page = read_page(out)
    check_self_contained(text, page, IDENTIFY_IMAGES_PUMA)
    assert "one sample in every 2 of the 21000 is plotted" in page.text


# --------------------------------------------------------------------------
# Prediction report


@pytest.fixture(scope="module")
def puma_params(tmp_path_factory: pytest.TempPathFactory, puma_ident: Any) -> Path:
    path = tmp_path_factory.mktemp("params") / "params.json"
    puma_ident.save(path)
    return path


def test_predict_report_with_measured_wrench(massid: Any, tmp_path: Path, puma_urdf: Path,
                                             puma_params: Path, puma_plan: Path) -> None:
    import json

    data = massid.simulate(str(puma_urdf), str(puma_plan), noise_force=0.05, noise_moment=0.005,
                           sensor_offset=[1.0, -2.0, 3.0, 0.1, -0.2, 0.3], seed=11)
    csv = write_csv(tmp_path / "check.csv", data, comment="30 poses of the paper")
    out = tmp_path / "predict.html"
    massid.report.write_predict_report(out, str(puma_urdf), str(puma_params), str(csv))
    text, page = read_page(out)
    # fit, compensated against index, against the joints, correlation, coverage, tilt
    check_self_contained(text, page, 6)
    doc = json.loads(puma_params.read_text())
    for p in doc["base_parameters"]:
        _, cells = page.row(p["name"])
        assert cells[1] == f"{p['value']:.6g}" and cells[2] == f"{p['std']:.2g}"
    predicted = massid.predict(str(puma_urdf), str(puma_params), str(csv))  # fx_pred
    measured = np.column_stack([data[a] for a in AXES])
    so = doc["sensor_offset"]  # fx_comp = measured - fx_pred - offset
    rms = np.sqrt(np.mean((measured - predicted - np.array(so["force"] + so["moment"])) ** 2, axis=0))
    _, row = page.row("RMS of measured − predicted")
    assert row[1:] == [f"{v:.4g}" for v in rms]
    assert np.all(rms < 0.1)  # offsets included: only the noise remains
    assert str(puma_params) in page.text and str(csv) in page.text
    assert "Compensated wrench" in page.text


def test_predict_report_without_measured_wrench(massid: Any, tmp_path: Path, puma_urdf: Path,
                                                puma_params: Path, puma_holdout: Path) -> None:
    cols = massid.read_csv(str(puma_holdout))
    # joints in degrees (JOINT_deg columns) from a dict of columns
    data = {f"{j}_deg": np.degrees(cols[j]) for j in ("joint1", "joint2", "joint3")}
    data.update({g: cols[g] for g in ("gx", "gy", "gz")})
    model = massid.load_model(str(puma_urdf))
    out = tmp_path / "predict_only.html"
    massid.report.write_predict_report(out, model, str(puma_params), data, title="held-out poses")
    text, page = read_page(out)
    # predicted wrench, correlation, coverage, tilt
    check_self_contained(text, page, 4)
    assert "no measured wrench" in page.text
    predicted = massid.predict(str(puma_urdf), str(puma_params), str(puma_holdout))
    _, lo = page.row("predicted min")
    assert lo[1:] == [f"{v:.4g}" for v in predicted.min(axis=0)]
    assert "Largest tilt 2" in page.text  # holdout tilts reach ~25 deg


# --------------------------------------------------------------------------
# Command line


def run_cli(env: dict[str, str], *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "massid.report", *args], env=env,
                          capture_output=True, text=True, timeout=120)


def test_cli_check(package_env: dict[str, str]) -> None:
    r = run_cli(package_env, "--check")
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""


def test_cli_identify_and_predict(package_env: dict[str, str], tmp_path: Path, puma_urdf: Path,
                                  puma_data_csv: Path, puma_params: Path) -> None:
    out = tmp_path / "cli.html"
    out.write_text("an older report")  # replaced
    r = run_cli(package_env, "identify", str(puma_urdf), str(puma_data_csv), "-o", str(out),
                "--offset", "--sigma-force", "0.05", "--sigma-moment", "0.005")
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"wrote {out}" and r.stderr == ""
    text, page = read_page(out)
    check_self_contained(text, page, IDENTIFY_IMAGES_PUMA)
    assert "noise sigma (given)" in page.text
    _, sigma = page.row("noise sigma (given)")
    assert sigma[1:] == ["0.05"] * 3 + ["0.005"] * 3
    assert [p for p in out.parent.iterdir() if p.name.endswith(".tmp")] == []

    out2 = tmp_path / "cli_predict.html"
    r = run_cli(package_env, "predict", str(puma_urdf), str(puma_params), str(puma_data_csv),
                "-o", str(out2))
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"wrote {out2}"
    read_page(out2)


def test_cli_missing_file_is_exit_2(package_env: dict[str, str], tmp_path: Path, puma_urdf: Path) -> None:
    missing = tmp_path / "no_such_data.csv"
    out = tmp_path / "r.html"
    r = run_cli(package_env, "identify", str(puma_urdf), str(missing), "-o", str(out))
    assert r.returncode == 2
    assert r.stderr.startswith("massid: error: ") and "no_such_data.csv" in r.stderr
    assert "Traceback" not in r.stderr
    assert not out.exists()
    r = run_cli(package_env, "predict", str(puma_urdf), str(tmp_path / "nope.json"), str(missing),
                "-o", str(out))
    assert r.returncode == 2 and "nope.json" in r.stderr and "Traceback" not in r.stderr


def test_cli_bad_option_is_exit_2(package_env: dict[str, str], tmp_path: Path, puma_urdf: Path,
                                  puma_data_csv: Path) -> None:
    r = run_cli(package_env, "identify", str(puma_urdf), str(puma_data_csv), "-o",
                str(tmp_path / "r.html"), "--fixed", "joint3")
    assert r.returncode == 2
    assert r.stderr.strip() == "massid: error: --fixed: 'joint3' should read JOINT=VALUE"


def test_cli_unidentifiable_is_exit_3(massid: Any, package_env: dict[str, str], tmp_path: Path,
                                      puma_urdf: Path, puma_data: dict[str, np.ndarray]) -> None:
    frozen = {k: np.array(v, dtype=float) for k, v in puma_data.items()}
    frozen["joint3"][:] = 0.5  # joint3 never moves
    data = massid.simulate(str(puma_urdf), frozen, noise_force=0.05, noise_moment=0.005, seed=4)
    csv = write_csv(tmp_path / "frozen.csv", data)
    out = tmp_path / "r.html"
    r = run_cli(package_env, "identify", str(puma_urdf), str(csv), "-o", str(out))
    assert r.returncode == 3, r.stderr
    assert r.stderr.startswith("massid: error: ") and "Traceback" not in r.stderr
    assert not out.exists()
    # holding the joint still makes the same data identifiable
    r = run_cli(package_env, "identify", str(puma_urdf), str(csv), "-o", str(out),
                "--fixed", "joint3=0.5")
    assert r.returncode == 0, r.stderr
    assert out.exists()


def test_cli_without_matplotlib_is_exit_2(package_env: dict[str, str]) -> None:
    # A finder that refuses matplotlib, then the module run as `python3 -m massid.report --check`.
    script = (
        "import sys, runpy\n"
        "class NoMatplotlib:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'matplotlib' or name.startswith('matplotlib.'):\n"
        "            raise ImportError('No module named ' + repr(name))\n"
        "sys.meta_path.insert(0, NoMatplotlib())\n"
        "sys.argv = ['massid.report', '--check']\n"
        "runpy.run_module('massid.report', run_name='__main__', alter_sys=True)\n"
    )
    r = subprocess.run([sys.executable, "-c", script], env=package_env, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr.strip() == ("massid: error: --report needs matplotlib "
                                "(Debian: apt-get install python3-matplotlib)")


def test_import_massid_does_not_import_matplotlib(package_env: dict[str, str]) -> None:
    r = subprocess.run([sys.executable, "-c",
                        "import sys, massid; print('matplotlib' in sys.modules)"],
                       env=package_env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "False"


def test_a_failed_report_leaves_the_old_file(massid: Any, tmp_path: Path) -> None:
    out = tmp_path / "keep.html"
    out.write_text("old report")
    with pytest.raises(AttributeError):
        massid.report.write_identify_report(out, object())  # not an Identification
    assert out.read_text() == "old report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.html"]
