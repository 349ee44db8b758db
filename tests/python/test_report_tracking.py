"""The report of a tracked log: `massid compensate --track --report` and
massid.report.write_tracking_report.

The log is docs/tracking.md's worked example (examples/tracking/make_logs.py:
a gripper on a wrist sensor, an object grasped and put down, drifting
offsets, a contact; the truth in true_* columns). The report's summary is
checked against the output CSV, read here with the csv module: the events
counted, the payload periods cut at the change rows, their estimates and the
truth on each period's last free row.
"""

import base64
import csv
import math
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import massid_cli

REPO = pathlib.Path(__file__).resolve().parents[2]
ROBOT = REPO / "tests" / "data" / "ur_wrist_ft.urdf"
MAKE_LOGS = REPO / "examples" / "tracking" / "make_logs.py"
AXES = ("fx", "fy", "fz", "mx", "my", "mz")
INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def run(*args, **kw):
    return subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True, **kw)


def images(html):
    return [base64.b64decode(m) for m in re.findall(r'src="data:image/png;base64,([^"]+)"', html)]


def cells(html, row_id):
    """The text of the cells of the table row with id ROW_ID."""
    m = re.search(rf'<tr id="{re.escape(row_id)}">(.*?)</tr>', html)
    assert m, f"no row {row_id}"
    return [re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<td[^>]*>(.*?)</td>", m.group(1))]


def number(text):
    return math.nan if text == "—" else float(text)


@pytest.fixture(scope="module")
def tracked(tmp_path_factory):
    """The example's logs, the gripper identified, the tracked log through compensate
    --track --report (TMPDIR a scratch directory, to see the spool go)."""
    d = tmp_path_factory.mktemp("tracking")
    r = subprocess.run([sys.executable, str(MAKE_LOGS), "--massid", massid_cli(), "--out", str(d)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = run("identify", ROBOT, d / "free.csv", "--sensor", "ft_sensor", "--dynamic", "--offset",
            "--fixed", "finger_joint=0.02", "-o", d / "tool.json")
    assert r.returncode == 0, r.stderr
    scratch = d / "scratch"
    scratch.mkdir()
    with open(d / "tracked.csv") as f:
        r = run("compensate", ROBOT, d / "tool.json", "--track", "--payload-link", "gripper",
                "--report", d / "track.html", stdin=f, env=dict(os.environ, TMPDIR=str(scratch)))
    assert r.returncode == 0, r.stderr
    (d / "out.csv").write_text(r.stdout)
    return d, r, scratch


def test_compensate_report_leaves_the_stream_alone_and_removes_its_spool(tracked):
    d, r, scratch = tracked
    with open(d / "tracked.csv") as f:
        plain = run("compensate", ROBOT, d / "tool.json", "--track", "--payload-link", "gripper",
                    stdin=f)
    assert plain.returncode == 0, plain.stderr
    assert r.stdout == plain.stdout  # the data on stdout, as without --report
    assert f"wrote {d / 'track.html'}" in r.stderr and "wrote" not in r.stdout
    assert list(scratch.iterdir()) == []  # the spool is gone


def test_report_sections_and_figures(tracked):
    d, _, _ = tracked
    html = (d / "track.html").read_text()
    assert "<title>massid tracking — stdin</title>" in html
    for section in ("summary", "events", "mass", "com", "inertia", "offsets", "compensated"):
        assert f'id="{section}"' in html, section
    pngs = images(html)
    # mass, centre of mass, principal moments, offsets, offset errors, compensated wrench
    assert len(pngs) == 6 and all(p.startswith(b"\x89PNG\r\n\x1a\n") for p in pngs)
    assert "http://" not in html and "https://" not in html and "<script" not in html.lower()
    assert "no band" in html  # the log has no offset std columns


def test_report_loads_cleanly_in_a_browser(tracked, chromium):
    import browser

    d, _, _ = tracked
    r = browser.load_page(d / "track.html", width=1280, chromium=chromium)
    assert r.errors == [] and r.broken_images == []
    assert len(r.images) == 6
    assert all(im["naturalWidth"] > 200 and im["naturalHeight"] > 200 for im in r.images)
    assert r.title == "massid tracking — stdin"
    assert r.scroll_width <= 1280  # no horizontal scrolling at 1280 px


def test_summary_against_the_csv(tracked):
    d, _, _ = tracked
    html = (d / "track.html").read_text()
    with open(d / "out.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    event = [row["event"] for row in rows]
    n = len(rows)
    change = [i for i, e in enumerate(event) if e == "change"]
    contact = sum(e == "contact" for e in event)
    episodes = sum(1 for i, e in enumerate(event) if e == "contact" and (i == 0 or event[i - 1] != "contact"))
    assert len(change) == 2 and contact > 0  # the example: a grasp and a release
    assert cells(html, "count-rows")[1] == str(n)
    assert cells(html, "count-change")[1] == "2"
    assert cells(html, "count-contact")[1] == str(contact)
    assert cells(html, "count-episodes")[1] == str(episodes)
    touching = [any(float(row[f"true_{a}_comp"]) != 0 for a in AXES) for row in rows]
    flagged_in = sum(t and e == "contact" for t, e in zip(touching, event))
    flagged_free = sum((not t) and e == "contact" for t, e in zip(touching, event))
    assert cells(html, "count-true-contact")[1] == f"{flagged_in} of {sum(touching)}"
    assert cells(html, "count-free-flagged")[1] == f"{flagged_free} of {n - sum(touching)}"

    # The payload periods: before the grasp, holding the object, after the release.
    cuts = [0, *change, n]
    for j in range(3):
        last = max(i for i in range(cuts[j], cuts[j + 1]) if event[i] == "")
        row = rows[last]
        assert f"t = {float(row['t']):.6g} s (line {last + 2})" in html
        value, std, truth, err, z, unit = cells(html, f"p{j}-payload_m")[1:]
        m, s, tm = float(row["payload_m"]), float(row["payload_m_std"]), float(row["true_payload_m"])
        assert number(value) == pytest.approx(m, rel=1e-5, abs=1e-12)
        assert number(std) == pytest.approx(s, rel=1e-2)
        assert number(truth) == tm
        assert number(err) == pytest.approx(m - tm, rel=1e-2, abs=1e-12)
        assert number(z) == pytest.approx((m - tm) / s, rel=1e-2)
        assert unit == "kg"
        for c in "xyz":
            value, std, truth = cells(html, f"p{j}-payload_c{c}")[1:4]
            assert number(value) == pytest.approx(float(row[f"payload_c{c}"]), rel=1e-5, abs=1e-12)
            assert number(std) == pytest.approx(float(row["payload_c_std"]), rel=1e-2)
            t = row[f"true_payload_c{c}"]
            assert (math.isnan(number(truth)) if t == "" else number(truth) == float(t))
        for a in AXES:
            value, std, truth = cells(html, f"p{j}-offset_{a}")[1:4]
            assert number(value) == pytest.approx(float(row[f"offset_{a}"]), rel=1e-5)
            assert std == "—"
            assert number(truth) == pytest.approx(float(row[f"true_offset_{a}"]), rel=1e-5)
    # Holding the object: the principal moments, from the written inertia, against the truth.
    last = max(i for i in range(cuts[1], cuts[2]) if event[i] == "")
    row = rows[last]

    def moments(prefix):
        i = {k: float(row[prefix + k]) for k in INERTIA}
        m = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                      [i["ixz"], i["iyz"], i["izz"]]])
        return sorted(np.linalg.eigvalsh(m), reverse=True)

    for k, (est, true) in enumerate(zip(moments("payload_"), moments("true_payload_"))):
        value, _, truth = cells(html, f"p1-I{k + 1}")[1:4]
        assert number(value) == pytest.approx(est, rel=1e-5)
        assert number(truth) == pytest.approx(true, rel=1e-5)
    # The card: the last row's mass.
    assert f'{float(rows[-1]["payload_m"]):.4g} kg' in html


def synthetic(n=400, inertia=False, offset_std=False):
    """A tracked log in memory: a change at row 250, contact on rows 100-119 and 300."""
    t = np.arange(n) * 0.01
    cols = {"t": t}
    for a in AXES:
        cols[f"{a}_comp"] = np.zeros(n)
    holding = np.arange(n) >= 250
    cols["payload_m"] = np.where(holding, 0.5, 0.0)
    cols["payload_cx"], cols["payload_cy"], cols["payload_cz"] = (np.zeros(n), np.zeros(n),
                                                                   np.where(holding, 0.1, 0.0))
    cols["payload_m_std"] = np.full(n, 1e-3)
    cols["payload_c_std"] = np.full(n, 2e-3)
    for k in INERTIA:
        cols["payload_" + k] = (np.where(holding, 1e-3 if k in ("ixx", "iyy", "izz") else 0.0, np.nan)
                                if inertia else np.full(n, np.nan))
    for a in AXES:
        cols[f"offset_{a}"] = np.linspace(0.0, 0.1, n)
        if offset_std:
            cols[f"offset_{a}_std"] = np.full(n, 0.01)
    event = [""] * n
    for i in range(100, 120):
        event[i] = "contact"
    event[250] = "change"
    event[300] = "contact"
    cols["event"] = event
    return cols


def test_python_function_on_columns(tmp_path, massid):
    from massid import report

    out = tmp_path / "cols.html"
    report.write_tracking_report(out, synthetic(), title="a synthetic log")
    html = out.read_text()
    assert "<title>a synthetic log</title>" in html
    assert cells(html, "count-contact")[1] == "21"
    assert cells(html, "count-episodes")[1] == "2"
    assert cells(html, "count-change")[1] == "1"
    assert 'id="inertia"' not in html  # never written: no principal moments
    assert "count-true-contact" not in html  # no truth
    assert len(images(html)) == 4  # mass, centre of mass, offsets, compensated wrench
    assert cells(html, "p1-payload_m")[1:3] == ["0.5", "0.001"]
    # the periods' last free rows: 249 (before the change), 399
    assert "t = 2.49 s (line 250)" in html and "t = 3.99 s (line 400)" in html

    report.write_tracking_report(out, synthetic(inertia=True, offset_std=True))
    html = out.read_text()
    assert 'id="inertia"' in html and len(images(html)) == 5
    assert cells(html, "p1-I1")[1] == "0.001"
    assert cells(html, "p1-offset_fx")[2] == "0.01"  # the std column is read
    assert "with ± 1 std" in html


def test_the_csv_read_in_blocks_is_the_csv(tracked, monkeypatch, massid):
    """The CSV is converted in blocks of rows: blocks of 7 give what one block gives, and
    the same as the csv module (an empty field NaN)."""
    from massid import report

    d, _, _ = tracked
    whole = report.read_tracked_log(d / "out.csv")
    monkeypatch.setattr(report, "CSV_BLOCK_ROWS", 7)
    blocks = report.read_tracked_log(d / "out.csv")
    assert list(blocks.values) == list(whole.values)
    for name, v in whole.values.items():
        np.testing.assert_array_equal(blocks.values[name], v)
    np.testing.assert_array_equal(blocks.event, whole.event)
    np.testing.assert_array_equal(blocks.lines, np.arange(2, len(whole) + 2))
    with open(d / "out.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for name in ("payload_m", "payload_ixx", "true_payload_cx", "offset_mz", "t"):
        expected = [float(r[name]) if r[name] else math.nan for r in rows]
        np.testing.assert_array_equal(blocks.values[name], expected)
    assert list(blocks.event) == [r["event"] for r in rows]


def test_principal_moments_of_a_rotated_body(massid):
    from massid import report

    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    i = q @ np.diag([3.0, 2.0, 1.5]) @ q.T
    rows = np.array([[i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2]],
                     [np.nan] * 6])
    pm = report.principal_moments(rows)
    assert pm[0] == pytest.approx([3.0, 2.0, 1.5], rel=1e-12)
    assert np.isnan(pm[1]).all()


def test_bad_logs_are_named_and_an_older_report_is_kept(tmp_path, massid):
    from massid import report

    out = tmp_path / "r.html"
    out.write_text("older")
    cols = synthetic()
    lines = [",".join(cols)]
    for i in range(5):
        lines.append(",".join(str(cols[k][i]) for k in cols))
    good = "\n".join(lines) + "\n"
    (tmp_path / "ok.csv").write_text(good)
    report.write_tracking_report(tmp_path / "ok.html", tmp_path / "ok.csv")
    assert "massid tracking — ok.csv" in (tmp_path / "ok.html").read_text()

    fields = lines[3].split(",")
    fields[1] = "x"  # fx_comp on line 4
    (tmp_path / "bad.csv").write_text("\n".join(lines[:3] + [",".join(fields)]) + "\n")
    with pytest.raises(massid.InputError, match=r"bad\.csv:4:2: 'x' is not a number \(column fx_comp\)"):
        report.write_tracking_report(out, tmp_path / "bad.csv")
    header = lines[0].replace(",payload_m_std", ",m_std")
    (tmp_path / "cols.csv").write_text("\n".join([header] + lines[1:]) + "\n")
    with pytest.raises(massid.InputError, match=r"cols\.csv:1: no column\(s\) payload_m_std: is it "
                                                r"the output of massid compensate --track\?"):
        report.write_tracking_report(out, tmp_path / "cols.csv")
    (tmp_path / "event.csv").write_text("\n".join(lines[:2] + [lines[2] + "grasp"]) + "\n")
    with pytest.raises(massid.InputError, match=r"event\.csv:3:\d+: event 'grasp'"):
        report.write_tracking_report(out, tmp_path / "event.csv")
    # The command line: exit 2, the file named, the older report untouched.
    r = subprocess.run([sys.executable, "-m", "massid.report", "track", str(tmp_path / "bad.csv"),
                        "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 2 and "bad.csv:4:2" in r.stderr
    assert out.read_text() == "older"
