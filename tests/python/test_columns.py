"""Columns named otherwise: columns={ROLE: NAME} and the recorders' spellings of the
wrench give the canonical names' numbers bit for bit, with a MassidWarning naming
what was read as what; a bad binding is an InputError."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import pytest

from conftest import AXES, write_csv

ROS = {"fx": "/ft_sensor/wrench/force/x", "fy": "/ft_sensor/wrench/force/y",
       "fz": "/ft_sensor/wrench/force/z", "mx": "/ft_sensor/wrench/torque/x",
       "my": "/ft_sensor/wrench/torque/y", "mz": "/ft_sensor/wrench/torque/z"}


def renamed(data: Mapping[str, Any], names: Mapping[str, str]) -> dict[str, Any]:
    return {names.get(k, k): v for k, v in data.items()}


def test_spellings_and_bindings_identify_as_the_canonical_names(
        massid: Any, puma_urdf: Path, puma_data: Mapping[str, Any], tmp_path: Path) -> None:
    ref = massid.identify(str(puma_urdf), puma_data, offset=True)
    ros = renamed(puma_data, ROS)
    with pytest.warns(massid.MassidWarning, match="/ft_sensor/wrench/torque/x as mx"):
        got = massid.identify(str(puma_urdf), ros, offset=True)
    np.testing.assert_array_equal(got.values, ref.values)
    np.testing.assert_array_equal(got.std, ref.std)
    # A file, and names bound by columns=.
    odd = {k: f"channel {i}" for i, k in enumerate(AXES)}
    path = write_csv(tmp_path / "odd.csv", renamed(puma_data, odd))
    with pytest.warns(massid.MassidWarning, match="read channel 0 as fx"):
        bound = massid.identify(str(puma_urdf), str(path), offset=True, columns=odd)
    # (a file is streamed: compared with the canonical names' file, bit for bit)
    ref_file = massid.identify(str(puma_urdf), str(write_csv(tmp_path / "c.csv", puma_data)),
                               offset=True)
    np.testing.assert_array_equal(bound.values, ref_file.values)
    np.testing.assert_array_equal(bound.std, ref_file.std)
    # Without the binding the error lists the header and proposes the keyword.
    with pytest.raises(massid.InputError, match=r"no measured wrench.*columns=\{'fx': 'NAME'"):
        massid.identify(str(puma_urdf), str(path), offset=True)


def test_predict_log_reads_ros_names_and_rejects_a_bad_binding(
        massid: Any, puma_urdf: Path, puma_data: Mapping[str, Any], puma_ident: Any,
        tmp_path: Path) -> None:
    ref = massid.predict_log(str(puma_urdf), puma_ident, dict(puma_data))
    path = write_csv(tmp_path / "ros.csv", renamed(puma_data, ROS))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lp = massid.predict_log(str(puma_urdf), puma_ident, str(path))
    assert any("/ft_sensor/wrench/force/x as fx" in str(w.message) for w in caught)
    assert lp.compensated is not None
    np.testing.assert_array_equal(lp.compensated, ref.compensated)
    with pytest.raises(massid.InputError, match="binds an unknown role 'torque_x'"):
        massid.predict_log(str(puma_urdf), puma_ident, str(path), columns={"torque_x": "mx"})
    with pytest.raises(massid.InputError, match="no column 'tx' to read as 'mx'"):
        massid.predict(str(puma_urdf), puma_ident, str(path), columns={"mx": "tx"})


def test_predict_report_reads_the_measured_wrench_under_other_names(
        massid: Any, puma_urdf: Path, puma_data: Mapping[str, Any], tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    params = tmp_path / "p.json"
    canonical = write_csv(tmp_path / "c.csv", puma_data)
    massid.identify(str(puma_urdf), str(canonical), offset=True).save(str(params))
    odd = {k: f"channel {i}" for i, k in enumerate(AXES)}
    spelled = write_csv(tmp_path / "ros.csv", renamed(puma_data, ROS))
    bound = write_csv(tmp_path / "odd.csv", renamed(puma_data, odd))
    pages = {}
    for name, path, columns in (("canonical", canonical, None), ("ros", spelled, None),
                                ("bound", bound, odd)):
        out = tmp_path / f"{name}.html"
        massid.report.write_predict_report(out, str(puma_urdf), str(params), str(path),
                                           columns=columns)
        pages[name] = out.read_text(encoding="utf-8")
    for name in ("ros", "bound"):
        assert "Compensated wrench" in pages[name], name
    # The same RMS of measured - predicted (the table row) as with the canonical names.
    row = lambda text: text[text.index("RMS of measured"):][:400]  # noqa: E731
    assert row(pages["ros"]) == row(pages["canonical"])
    assert row(pages["bound"]) == row(pages["canonical"])
