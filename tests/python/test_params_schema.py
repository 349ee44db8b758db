"""docs/params.schema.json against the params files the CLI writes.

A small validator for the JSON Schema keywords the schema uses (type, const,
enum, required, properties, additionalProperties, items, minItems, maxItems,
minimum, maximum, $ref, if/then, not): the interpreter here has no jsonschema
package. Besides validating, it reports every key a written file holds that
the schema does not declare, so a key the CLI starts writing cannot go
undocumented. The files come from the CLI: static (with offsets, held
joints, drift, robust, physical) and dynamic (physical, delay, level with
offsets: no total mass).

Run: cd <build> && MASSID_CLI=$PWD/massid /usr/bin/python3 -m pytest tests/python/test_params_schema.py
"""

from __future__ import annotations

import copy
import json
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import PUMA, REPO, massid_cli

SCHEMA_PATH = REPO / "docs" / "params.schema.json"
UR = REPO / "examples" / "ur_like" / "ur_like.urdf"

_TYPES = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "boolean": lambda v: isinstance(v, bool),
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "null": lambda v: v is None,
}
_HANDLED = {"$schema", "$id", "$defs", "title", "description", "examples", "type", "const",
            "enum", "required", "properties", "additionalProperties", "items", "minItems",
            "maxItems", "minimum", "maximum", "$ref", "if", "then", "not"}


def _resolve(root: dict[str, Any], ref: str) -> dict[str, Any]:
    assert ref.startswith("#/"), ref
    node: Any = root
    for part in ref[2:].split("/"):
        node = node[part]
    return node


def validate(value: Any, schema: dict[str, Any], root: dict[str, Any], path: str = "$",
             undeclared: list[str] | None = None) -> list[str]:
    """Errors of `value` against `schema` (empty: valid). Keys of objects whose schema
    lists properties but no additionalProperties, and that the schema does not declare,
    go to `undeclared`."""
    unknown = set(schema) - _HANDLED
    assert not unknown, f"the test's validator does not know {unknown} (at {path})"
    errors: list[str] = []
    if "$ref" in schema:
        errors += validate(value, _resolve(root, schema["$ref"]), root, path, undeclared)
    if "type" in schema and not _TYPES[schema["type"]](value):
        return errors + [f"{path}: {value!r:.60} is not of type {schema['type']}"]
    if "const" in schema and value != schema["const"]:
        errors.append(f"{path}: {value!r} is not {schema['const']!r}")
    if "enum" in schema and value not in schema["enum"]:
        errors.append(f"{path}: {value!r} is not one of {schema['enum']}")
    if "minimum" in schema and _TYPES["number"](value) and value < schema["minimum"]:
        errors.append(f"{path}: {value} < {schema['minimum']}")
    if "maximum" in schema and _TYPES["number"](value) and value > schema["maximum"]:
        errors.append(f"{path}: {value} > {schema['maximum']}")
    if isinstance(value, list):
        if "minItems" in schema and len(value) < schema["minItems"]:
            errors.append(f"{path}: {len(value)} items, fewer than {schema['minItems']}")
        if "maxItems" in schema and len(value) > schema["maxItems"]:
            errors.append(f"{path}: {len(value)} items, more than {schema['maxItems']}")
        if "items" in schema:
            for i, v in enumerate(value):
                errors += validate(v, schema["items"], root, f"{path}[{i}]", undeclared)
    if isinstance(value, dict):
        for key in schema.get("required", []):
            if key not in value:
                errors.append(f"{path}: required key '{key}' missing")
        props = schema.get("properties", {})
        extra = schema.get("additionalProperties")
        for key, v in value.items():
            if key in props:
                errors += validate(v, props[key], root, f"{path}.{key}", undeclared)
            elif isinstance(extra, dict):
                errors += validate(v, extra, root, f"{path}.{key}", undeclared)
            elif extra is False:
                errors.append(f"{path}: key '{key}' not allowed")
            elif props and undeclared is not None:
                undeclared.append(f"{path}.{key}")
    if "not" in schema and not validate(value, schema["not"], root, path):
        errors.append(f"{path}: matches the schema under 'not'")
    if "if" in schema and not validate(value, schema["if"], root, path):
        errors += validate(value, schema.get("then", {}), root, path, undeclared)
    return errors


@pytest.fixture(scope="module")
def schema() -> dict[str, Any]:
    return json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))


def run(*args: str | Path) -> None:
    r = subprocess.run([massid_cli(), *map(str, args)], capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, f"massid {' '.join(map(str, args))}:\n{r.stderr}"


def read_rows(path: Path) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a CSV the CLI wrote (comment lines skipped)."""
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines()
             if ln and not ln.startswith("#")]
    return lines[0].split(","), [ln.split(",") for ln in lines[1:]]


def write_rows(path: Path, header: list[str], rows: list[list[str]]) -> None:
    path.write_text("\n".join(",".join(r) for r in [header, *rows]) + "\n", encoding="utf-8")


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, Any]]:
    """Params files the CLI writes, by what they exercise."""
    d = tmp_path_factory.mktemp("schema")
    out: dict[str, dict[str, Any]] = {}

    def identify(name: str, urdf: Path, data: Path, *opts: str) -> None:
        run("identify", urdf, data, "-o", d / f"{name}.json", *opts)
        out[name] = json.loads((d / f"{name}.json").read_text(encoding="utf-8"))

    # Static: the held-out poses (tilts in every direction, so the offsets are
    # determined) with noise and an offset.
    data = d / "data.csv"
    run("simulate", PUMA / "puma260.urdf", PUMA / "holdout.csv", "-o", data, "--noise-force",
        "0.05", "--noise-moment", "0.005", "--sensor-offset", "1,2,3,0.1,0.2,0.3", "--seed", "3")
    identify("static", PUMA / "puma260.urdf", data)
    identify("static_offset_physical", PUMA / "puma260.urdf", data, "--offset", "--physical",
             "--robust")
    header, rows = read_rows(data)

    # Without gx,gy,gz and the tilt columns (gravity from the force, eq. 37; the
    # tilts alone would give gravity as compensate takes it).
    keep = [i for i, c in enumerate(header)
            if c not in ("gx", "gy", "gz", "tilt_x_deg", "tilt_y_deg")]
    write_rows(d / "no_gravity.csv", [header[i] for i in keep],
               [[r[i] for i in keep] for r in rows])
    identify("static_gravity_from_force", PUMA / "puma260.urdf", d / "no_gravity.csv")

    # The same with a time column and a drifting offset.
    write_rows(d / "timed.csv", header + ["t"], [r + [str(k)] for k, r in enumerate(rows)])
    identify("static_drift", PUMA / "puma260.urdf", d / "timed.csv", "--drift", "linear")

    # The wrist joint held still (--fixed), as the paper held the PUMA's wrist.
    j3 = header.index("joint3")
    write_rows(d / "held_plan.csv", header,
               [[("0.5" if i == j3 else v) for i, v in enumerate(r)] for r in rows])
    run("simulate", PUMA / "puma260.urdf", d / "held_plan.csv", "-o", d / "held.csv",
        "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", "6")
    identify("static_held", PUMA / "puma260.urdf", d / "held.csv", "--fixed", "joint3=0.5")

    # Dynamic: a short trajectory of the UR-like arm, tilting (varying gravity) and level.
    traj, log = d / "traj.csv", d / "log.csv"
    run("design", UR, "--dynamic", "-o", traj, "--duration", "6", "--period", "3", "--rate",
        "200", "--evaluations", "0", "--min-height", "none", "--tilts", "0:0,0:30")
    run("simulate", UR, traj, "-o", log, "--dynamic", "--noise-force", "0.05",
        "--noise-moment", "0.005", "--seed", "4")
    identify("dynamic_physical", UR, log, "--dynamic", "--physical", "--delay", "auto")
    level, level_log = d / "level.csv", d / "level_log.csv"
    run("design", UR, "--dynamic", "-o", level, "--duration", "6", "--period", "3", "--rate",
        "200", "--evaluations", "0", "--min-height", "none")
    run("simulate", UR, level, "-o", level_log, "--dynamic", "--noise-force", "0.05",
        "--noise-moment", "0.005", "--sensor-offset", "1,2,3,0.1,0.2,0.3", "--seed", "5")
    identify("dynamic_level_offset", UR, level_log, "--dynamic", "--offset")
    return out


def test_schema_is_well_formed(schema: dict[str, Any]) -> None:
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    # Every $ref resolves and every keyword is one the validator knows (validate asserts).
    refs: list[str] = []

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            if "$ref" in node:
                refs.append(node["$ref"])
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(schema)
    assert refs
    for r in refs:
        assert isinstance(_resolve(schema, r), dict), r


def test_files_the_cli_writes_are_valid(schema: dict[str, Any],
                                        files: dict[str, dict[str, Any]]) -> None:
    for name, doc in files.items():
        undeclared: list[str] = []
        errors = validate(doc, schema, schema, "$", undeclared)
        assert not errors, f"{name}: {errors}"
        assert not undeclared, f"{name}: keys the schema does not declare: {undeclared}"


def test_the_files_exercise_every_section(files: dict[str, dict[str, Any]]) -> None:
    """The cases above write every optional section the schema describes but rest_windows
    (a continuous log; tests/test_rest_windows.cpp), so the schema is checked on each."""
    seen = set().union(*(doc.keys() for doc in files.values()))
    assert {"held_joints", "sensor_offset", "drift", "physical", "model", "motion",
            "delay"} <= seen
    assert "total_mass" not in files["dynamic_level_offset"]
    assert files["dynamic_physical"]["motion"]["gravity"] == "varying"
    assert files["dynamic_level_offset"]["motion"]["gravity"] == "fixed"
    assert files["static_offset_physical"]["outliers"]["method"] == "rejected"


def test_the_validator_rejects_broken_files(schema: dict[str, Any],
                                            files: dict[str, dict[str, Any]]) -> None:
    """Each edit breaks what read_params requires; the schema must say so."""
    static, dynamic = files["static_offset_physical"], files["dynamic_physical"]

    def broken(doc: dict[str, Any], edit: Any) -> list[str]:
        d = copy.deepcopy(doc)
        edit(d)
        return validate(d, schema, schema)

    cases = {
        "format": (static, lambda d: d.update(format="massid-params-2")),
        "no sensor_link": (static, lambda d: d.pop("sensor_link")),
        "joints not strings": (static, lambda d: d.update(joints=[1, 2])),
        "static without total_mass": (static, lambda d: d.pop("total_mass")),
        "base parameter without value": (static, lambda d: d["base_parameters"][0].pop("value")),
        "term without coef": (static, lambda d: d["base_parameters"][0]["terms"][0].pop("coef")),
        "unknown parameter kind": (
            static, lambda d: d["base_parameters"][0]["terms"][0].update(param="q")),
        "offset of two": (static, lambda d: d["sensor_offset"].update(force=[0.0, 1.0])),
        "samples negative": (static, lambda d: d.update(samples=-1)),
        "samples not integer": (static, lambda d: d.update(samples=2.5)),
        "model unknown": (static, lambda d: d.update(model="kinematic")),
        "physical link without izz": (
            static, lambda d: next(iter(d["physical"]["links"].values())).pop("izz")),
        "fixed gravity without vector": (
            dynamic, lambda d: d["motion"].update(gravity="fixed")),
    }
    for name, (doc, edit) in cases.items():
        assert broken(doc, edit), f"the schema accepts a file with: {name}"
    # Dynamic files need no total_mass.
    assert not broken(dynamic, lambda d: d.pop("total_mass", None))


def test_schema_matches_what_read_params_accepts(
        schema: dict[str, Any], files: dict[str, dict[str, Any]],
        tmp_path: Path) -> None:
    """A file the schema accepts with every optional record removed is still read by the
    CLI (predict), and predicts as the full file does: the schema's required keys are
    what read_params needs."""
    full = files["static_offset_physical"]
    minimal = {k: full[k] for k in schema["required"] + ["total_mass", "sensor_offset"]}
    minimal["base_parameters"] = [{k: p[k] for k in ("name", "value", "terms")}
                                  for p in full["base_parameters"]]
    assert not validate(minimal, schema, schema)
    (tmp_path / "full.json").write_text(json.dumps(full), encoding="utf-8")
    (tmp_path / "minimal.json").write_text(json.dumps(minimal), encoding="utf-8")
    plan = PUMA / "plan.csv"
    for name in ("full", "minimal"):
        run("predict", PUMA / "puma260.urdf", tmp_path / f"{name}.json", plan, "-o",
            tmp_path / f"{name}.csv")

    def pred(name: str) -> np.ndarray:
        header, rows = read_rows(tmp_path / f"{name}.csv")
        cols = [header.index(f"{a}_pred") for a in ("fx", "fy", "fz", "mx", "my", "mz")]
        return np.array([[float(r[c]) for c in cols] for r in rows])

    np.testing.assert_array_equal(pred("full"), pred("minimal"))
