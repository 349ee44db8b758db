"""massid identify/predict --report: the CLI runs python -m massid.report and
writes the HTML next to its usual outputs, unchanged by the report."""

import base64
import pathlib
import re
import subprocess
from html import escape as html_escape

from conftest import massid_cli

REPO = pathlib.Path(__file__).resolve().parents[2]
PUMA = REPO / "examples" / "puma260" / "puma260.urdf"
PLAN = REPO / "examples" / "puma260" / "plan.csv"
HOLDOUT = REPO / "examples" / "puma260" / "holdout.csv"


def run(*args):
    return subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True)


def images(html: str):
    return [base64.b64decode(m) for m in re.findall(r'src="data:image/png;base64,([^"]+)"', html)]


def test_identify_and_predict_reports(tmp_path):
    data = tmp_path / "data.csv"
    assert run("simulate", PUMA, PLAN, "-o", data, "--noise-force", "0.05", "--noise-moment", "0.005",
               "--repeat", "3").returncode == 0
    # one spoiled sample: its warning must appear once, not again from the report
    lines = data.read_text().splitlines()
    header = lines[0].split(",")
    row = lines[10].split(",")
    row[header.index("fz")] = repr(float(row[header.index("fz")]) + 3.0)
    lines[10] = ",".join(row)
    data.write_text("\n".join(lines) + "\n")

    plain = run("identify", PUMA, data, "-o", tmp_path / "plain.json")
    assert plain.returncode == 0, plain.stderr
    r = run("identify", PUMA, data, "-o", tmp_path / "params.json", "--report", tmp_path / "fit.html")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "params.json").read_text() == (tmp_path / "plain.json").read_text()
    assert r.stdout.startswith(plain.stdout.replace("plain.json", "params.json"))
    assert f"wrote {tmp_path / 'fit.html'}" in r.stdout
    assert r.stderr == plain.stderr, "the report repeats no warning"
    assert "line 11" in r.stderr or "lines 11" in r.stderr or "11 (d =" in r.stderr
    html = (tmp_path / "fit.html").read_text()
    # The report lists the warning as the command printed it: the CLI's option as the hint.
    warned = [w[len("massid: warning: "):] for w in r.stderr.splitlines()
              if w.startswith("massid: warning: ") and "implausible" in w]
    assert len(warned) == 1 and warned[0].endswith("(--robust)"), r.stderr
    assert html_escape(warned[0], quote=True) in html
    pngs = images(html)
    assert len(pngs) >= 5 and all(p.startswith(b"\x89PNG\r\n\x1a\n") for p in pngs)
    for name in ("p1", "p9", "M"):
        assert f">{name}<" in html
    assert "http://" not in html and "https://" not in html and "<script" not in html.lower()

    r = run("predict", PUMA, tmp_path / "params.json", HOLDOUT, "--report", tmp_path / "pred.html")
    assert r.returncode == 0, r.stderr
    pred_html = (tmp_path / "pred.html").read_text()
    assert len(images(pred_html)) >= 3
    assert "holdout.csv" in pred_html


def test_report_errors_keep_the_clis_exit_codes(tmp_path):
    r = run("predict", PUMA, tmp_path / "missing.json", HOLDOUT, "--report", tmp_path / "x.html")
    assert r.returncode == 2 and "missing.json" in r.stderr
    assert not (tmp_path / "x.html").exists()


def test_identify_report_draws_the_fit_the_command_made(tmp_path):
    """identify --report hands its fit to the report in a record (no second fit): the
    record holds exactly the params file's values and every sample, the report shows
    them, and the record is removed afterwards."""
    import json
    import os
    import sys

    import massid

    data = tmp_path / "data.csv"
    assert run("simulate", PUMA, PLAN, "-o", data, "--noise-force", "0.05", "--noise-moment", "0.005",
               "--repeat", "4").returncode == 0
    # An interpreter that keeps a copy of the record it is given, then runs the report.
    kept = tmp_path / "kept.record"
    wrapper = tmp_path / "python_wrapper.sh"
    wrapper.write_text(f'#!/bin/sh\n[ "$3" = draw-identify ] && cp "$4" "{kept}"\n'
                       f'exec "{sys.executable}" "$@"\n')
    wrapper.chmod(0o755)
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    env = dict(os.environ, MASSID_PYTHON=str(wrapper), TMPDIR=str(scratch))
    r = subprocess.run([massid_cli(), "identify", str(PUMA), str(data), "-o",
                        str(tmp_path / "params.json"), "--report", str(tmp_path / "fit.html")],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert list(scratch.iterdir()) == []  # the record is gone
    ident = massid.load_identification(kept)
    params = json.loads((tmp_path / "params.json").read_text())
    assert [p["value"] for p in params["base_parameters"]] == [p.value for p in ident.base_parameters]
    assert params["samples"] == ident.samples == 4 * 30
    assert ident.to_json() == (tmp_path / "params.json").read_text()
    html = (tmp_path / "fit.html").read_text()
    for p in ident.base_parameters:
        assert f">{p.value:.6g}<" in html
    # not a record: exit 2 with the file named
    r = subprocess.run([sys.executable, "-m", "massid.report", "draw-identify", str(data), "-o",
                        str(tmp_path / "x.html")], capture_output=True, text=True)
    assert r.returncode == 2 and "data.csv: not a massid identification record" in r.stderr
    assert not (tmp_path / "x.html").exists()
