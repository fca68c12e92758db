"""hydroid.run on the bundled spheroid example gives exactly the command line's numbers."""

import csv
import json

import polars as pl
import pytest

import hydroid
from conftest import copy_config


def test_run_gives_the_cli_coefficients_exactly(spheroid_py, spheroid_cli):
    cli = json.loads((spheroid_cli / "results.json").read_text())
    df = spheroid_py.coefficients
    with open(spheroid_cli / "coefficients.csv", newline="") as f:
        header = next(csv.reader(f))
    assert df.columns == header[: len(df.columns)]
    assert {"name", "value", "sigma", "unit", "source", "analytic", "reference"} <= set(df.columns)
    assert df["name"].to_list() == [r["name"] for r in cli["comparison"]]
    assert df["value"].to_list() == [r["value"] for r in cli["comparison"]]
    assert df["sigma"].to_list() == [r["sigma"] for r in cli["comparison"]]
    # and coefficients.csv as the CLI wrote it (shortest round-trip digits: exact)
    with open(spheroid_cli / "coefficients.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert df["value"].to_list() == [float(r["value"]) for r in rows]
    assert df["sigma"].to_list() == [float(r["sigma"]) if r["sigma"] else None for r in rows]
    assert df["unit"].to_list() == [r["unit"] for r in rows]
    assert df["source"].to_list() == [r["source"] for r in rows]
    # the same files, byte for byte, but for where they were written
    assert (spheroid_py.path / "coefficients.csv").read_bytes() == (spheroid_cli / "coefficients.csv").read_bytes()


def test_result_carries_correlation_warnings_states_and_path(spheroid_py):
    r = spheroid_py
    assert (r.path / "results.json").is_file()
    corr = r.correlation
    assert corr is not None and corr.columns[0] == "name"
    names = corr["name"].to_list()
    for i, n in enumerate(names):
        assert corr[n][i] == pytest.approx(1.0)
        assert all(-1.0 <= v <= 1.0 for v in corr[n])
    assert isinstance(r.warnings, list)
    runs = r.runs()
    assert runs, "the spheroid example's HEKF writes a state series"
    states = r.states(runs[0])
    assert states.height > 10 and "t" in states.columns[0]
    with pytest.raises(KeyError, match="no state series"):
        r.states("no such run")


def test_to_pandas_works_when_pandas_is_installed(spheroid_py):
    pytest.importorskip("pandas")
    pd = spheroid_py.coefficients.to_pandas()
    assert list(pd["name"]) == spheroid_py.coefficients["name"].to_list()


def test_run_refuses_a_folder_hydroid_did_not_write(tmp_path, root):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my notes")
    with pytest.raises(hydroid.HydroidError, match="mine"):
        hydroid.run(root / "configs" / "spheroid.toml", out=mine, force=True)
    assert (mine / "notes.txt").read_text() == "my notes"


def test_overrides_reach_the_run(tmp_path, root):
    cfg = copy_config(root, tmp_path, "spheroid.toml")
    r = hydroid.run(cfg, out=tmp_path / "o", overrides={"output.plots": False, "title": "over"})
    assert r.results["title"] == "over"
    assert not (r.path / "plots").exists()


def test_errors_raise_hydroid_error_with_the_file_and_key(tmp_path, root):
    cfg = copy_config(root, tmp_path, "spheroid.toml", lambda s: s.replace("izz = 3.7", "izz = -3.7"))
    with pytest.raises(hydroid.HydroidError) as e:
        hydroid.run(cfg, out=tmp_path / "o")
    assert "spheroid.toml" in str(e.value)
    assert any(p["key"] == "vehicle.izz" for p in e.value.problems)
    with pytest.raises(hydroid.HydroidError, match="nothing_here.csv"):
        hydroid.read(tmp_path / "nothing_here.csv")
    assert not (tmp_path / "o").exists()


def test_check_lists_problems_as_dicts_naming_the_key(tmp_path, root):
    assert hydroid.check(root / "configs" / "spheroid.toml", out=tmp_path / "o") == []
    cfg = copy_config(root, tmp_path, "spheroid.toml", lambda s: s.replace("izz = 3.7", "izzz = 3.7"))
    problems = hydroid.check(cfg)
    assert problems, "a misspelt key is a problem"
    assert all(set(p) >= {"file", "line", "column", "key", "message"} for p in problems)
    p = next(p for p in problems if p["key"] and "izzz" in p["key"])
    assert p["file"].endswith("spheroid.toml") and p["line"] is not None
    assert "izz" in p["message"]
