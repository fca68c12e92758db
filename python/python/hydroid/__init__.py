"""hydroid from Python: CFD exports and model-test logs of marine vehicles to manoeuvring
models (hydrodynamic coefficients with uncertainties), as polars DataFrames.

Every function calls hydroid's Rust library in the compiled module ``hydroid._hydroid`` (not
the command line); docs/python.md in the repository shows an example. Numbers are SI (kg, m,
s, rad; propeller speed in rev/s), as in results.json. A DataFrame that carries units has
them in its ``units`` attribute, a dict from column name to SI unit.

Errors raise :class:`HydroidError`, whose message is hydroid's (it names the file, line,
column or configuration key) and whose ``problems`` list each problem as a dict
``{file, line, column, column_name, key, message}``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import polars as pl

from . import _hydroid
from ._hydroid import HydroidError

__version__ = _hydroid.__version__

__all__ = [
    "HydroidError",
    "Result",
    "run",
    "read",
    "check",
    "simulate",
    "models",
    "coefficients",
    "batch",
]

PathLike = Union[str, "os.PathLike[str]"]

#: The columns of :attr:`Result.coefficients`, in order: those of coefficients.csv.
COEFFICIENT_COLUMNS: List[str] = list(_hydroid.COEFFICIENT_COLUMNS)

_TEXT_COLUMNS = {"name", "unit", "source"}
_COEFFICIENT_SCHEMA = {c: (pl.Utf8 if c in _TEXT_COLUMNS else pl.Float64) for c in COEFFICIENT_COLUMNS}


def _with_units(df: pl.DataFrame, units: Mapping[str, Optional[str]]) -> pl.DataFrame:
    df.units = dict(units)  # type: ignore[attr-defined]
    return df


class Result:
    """What :func:`run` wrote: the output folder and its results.json, read back.

    Attributes:
        path: the output folder (results.json, coefficients.csv, states/, report.md ...).
        results: results.json as a dict (schema in docs/results.md).
    """

    def __init__(self, path: PathLike, results: Dict[str, Any]) -> None:
        self.path = Path(path)
        self.results = results

    @property
    def coefficients(self) -> pl.DataFrame:
        """Every coefficient of the run, as coefficients.csv lists them: name, value, sigma
        (one standard deviation, null when unknown), unit (SI), source (the stage, config,
        analytic or relation), analytic (Fossen's value, Lamb's k-factors) and its error in
        percent, reference (the configuration's published value) and its error; each row's SI unit
        is in its ``unit`` column."""
        rows = [{k: r.get(k) for k in COEFFICIENT_COLUMNS} for r in self.results["comparison"]]
        return pl.DataFrame(rows, schema=_COEFFICIENT_SCHEMA)

    @property
    def correlation(self) -> Optional[pl.DataFrame]:
        """The correlation matrix of the coefficients estimated together (a ``name`` column,
        then one column per coefficient), or None when the run estimated none jointly."""
        c = self.results.get("correlation")
        if not c:
            return None
        data: Dict[str, Any] = {"name": c["names"]}
        for j, n in enumerate(c["names"]):
            data[n] = [row[j] for row in c["matrix"]]
        return pl.DataFrame(data)

    @property
    def warnings(self) -> List[Dict[str, Any]]:
        """Everything the user should know, as results.json lists it: dicts with ``stage``,
        ``run`` (when it concerns one), ``message`` and ``meaning``."""
        return list(self.results["warnings"])

    def runs(self) -> List[str]:
        """The HEKF runs whose state series were written (names for :meth:`states`)."""
        hekf = (self.results.get("stages") or {}).get("hekf") or {}
        return [r["name"] for r in hekf.get("runs", []) if r.get("states")]

    def states(self, run: str) -> pl.DataFrame:
        """The filtered and smoothed state series of the HEKF run ``run`` (states/NAME.csv,
        docs/results.md, "State series"), SI. Raises KeyError naming the runs that have one."""
        hekf = (self.results.get("stages") or {}).get("hekf") or {}
        for r in hekf.get("runs", []):
            if r["name"] == run and r.get("states"):
                return pl.read_csv(self.path / r["states"])
        raise KeyError(f"no state series of a run '{run}'; runs with one: {self.runs()}")

    def __repr__(self) -> str:
        return f"hydroid.Result(path={str(self.path)!r}, coefficients={len(self.results['comparison'])})"


def run(
    config: PathLike,
    out: Optional[PathLike] = None,
    overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = None,
    force: bool = False,
) -> Result:
    """Runs every stage the configuration ``config`` enables and writes its output folder,
    as ``hydroid run CONFIG`` does: into ``out``, else the configuration's ``output.dir``
    (relative to it). The folder is written whole or not at all; a folder hydroid did not
    write is refused, and one changed since hydroid wrote it is replaced only with
    ``force=True``. ``overrides`` are ``--set`` overrides, as ``{"hekf.passes": 3}`` or
    ``["hekf.passes=3"]``."""
    path, results = _hydroid.run(
        os.fspath(config),
        None if out is None else os.fspath(out),
        _overrides(overrides),
        force,
    )
    return Result(path, json.loads(results))


def _overrides(overrides: Optional[Union[Mapping[str, Any], Sequence[str]]]) -> List[str]:
    if overrides is None:
        return []
    if isinstance(overrides, Mapping):
        return [f"{k}={_toml_value(v)}" for k, v in overrides.items()]
    if isinstance(overrides, str):
        return [overrides]
    return [str(o) for o in overrides]


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write override value {v!r} as TOML")


def read(file: PathLike, format: Optional[str] = None) -> pl.DataFrame:
    """One CFD export or log read as ``hydroid inspect`` reads it (``format`` a ``--format``
    name, default detected), one column per column of the file, values in SI (a missing
    cell is null). Column metadata are attributes of the DataFrame: ``units`` (column -> SI
    unit, None when the file states none), ``quantities`` (column -> the quantity hydroid
    takes it for, or None), ``format``, ``time`` (the time column) and ``warnings``."""
    r = json.loads(_hydroid.read(os.fspath(file), format))
    cols = r["columns"]
    df = pl.DataFrame({c["name"]: pl.Series(c["name"], c["values"], dtype=pl.Float64) for c in cols})
    _with_units(df, {c["name"]: c["si_unit"] for c in cols})
    df.quantities = {c["name"]: c["quantity"] for c in cols}  # type: ignore[attr-defined]
    df.format = r["format"]  # type: ignore[attr-defined]
    df.time = r["time"]  # type: ignore[attr-defined]
    df.warnings = r["warnings"]  # type: ignore[attr-defined]
    return df


def check(
    config: PathLike,
    overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = None,
    out: Optional[PathLike] = None,
) -> List[Dict[str, Any]]:
    """Checks the configuration and every input it names as ``hydroid check`` does, and
    returns every problem as a dict ``{file, line, column, column_name, key, message}``
    (empty when the configuration can run). A configuration file that cannot be read at all
    raises :class:`HydroidError`."""
    report = json.loads(
        _hydroid.check_config(
            os.fspath(config), _overrides(overrides), None if out is None else os.fspath(out)
        )
    )
    return list(report["problems"])


def models() -> pl.DataFrame:
    """Every model hydroid has: name, description, states, inputs (lists of names),
    coefficients (names) and the vehicle data it needs (``hydroid coefficients MODEL``)."""
    rows = []
    for m in json.loads(_hydroid.models()):
        rows.append(
            {
                "name": m["name"],
                "description": m["description"],
                "states": [s["name"] for s in m["states"]],
                "inputs": [i["name"] for i in m["inputs"]],
                "coefficients": [c["name"] for c in m["coefficients"]],
                "vehicle_needs": list(m["vehicle_needs"]),
            }
        )
    return pl.DataFrame(rows)


def coefficients(model: Optional[str] = None) -> pl.DataFrame:
    """The coefficient catalogue: with ``model``, that model's coefficients (name, unit,
    derived_by: the relation that derives it inside the model or null when it is free,
    range: the admissible values or null); without, every coefficient hydroid knows (name,
    unit, meaning, given_by). An unknown model raises :class:`HydroidError`."""
    data = json.loads(_hydroid.coefficients(model))
    if model is not None:
        rows = [
            {"name": c["name"], "unit": c["unit"], "derived_by": c.get("derived_by"), "range": c.get("range")}
            for c in data["coefficients"]
        ]
        schema = {"name": pl.Utf8, "unit": pl.Utf8, "derived_by": pl.Utf8, "range": pl.Utf8}
    else:
        rows = [
            {
                "name": e["name"],
                "unit": e["unit"],
                "meaning": e["meaning"],
                "given_by": [f"{p['source']}: {p['how']}" for p in e["given_by"]],
            }
            for e in data
        ]
        schema = {"name": pl.Utf8, "unit": pl.Utf8, "meaning": pl.Utf8, "given_by": pl.List(pl.Utf8)}
    return pl.DataFrame(rows, schema=schema)


def simulate(
    model: str,
    coefficients: Union[Mapping[str, float], pl.DataFrame, Result],
    vehicle: Union[PathLike, Mapping[str, Any]],
    inputs: Mapping[str, Any],
    *,
    fluid: Optional[Mapping[str, Any]] = None,
    initial: Optional[Mapping[str, float]] = None,
    substeps: int = 10,
) -> pl.DataFrame:
    """Integrates ``model`` (a name of :func:`models`) with hydroid's RK4, as ``hydroid
    simulate`` does, and returns ``t`` and the states at every time (SI; ``units``
    attribute).

    Args:
        coefficients: values by name (SI), or a coefficient DataFrame or :class:`Result`
            (its ``name`` and ``value``); the model's relations complete them.
        vehicle: a TOML file with ``[vehicle]`` and ``[fluid]`` tables (a run or simulation
            configuration), or a dict of the ``[vehicle]`` keys (then ``fluid`` gives
            ``rho`` and ``mu``).
        inputs: ``t`` (the output times, s, strictly increasing), and each input of the model
            by its key as :func:`models` names it, SI: a number (held) or one value per time
            (linear between the times).
        initial: the initial state by state name (others 0).
        substeps: RK4 steps per interval of ``t``.
    """
    if isinstance(coefficients, Result):
        coefficients = coefficients.coefficients
    if isinstance(coefficients, pl.DataFrame):
        coefficients = dict(zip(coefficients["name"].to_list(), coefficients["value"].to_list()))
    t = [float(x) for x in inputs["t"]]
    series = {}
    for k, v in inputs.items():
        if k == "t":
            continue
        if isinstance(v, (int, float)):
            series[k] = [float(v)] * len(t)
        else:
            series[k] = [float(x) for x in v]
    if isinstance(vehicle, Mapping):
        if fluid is None:
            raise HydroidError("simulate: a vehicle given as a dict needs fluid={'rho': ..., 'mu': ...}")
        vehicle_file, vehicle_json = None, json.dumps({"vehicle": dict(vehicle), "fluid": dict(fluid)})
    else:
        vehicle_file, vehicle_json = os.fspath(vehicle), None
    out = json.loads(
        _hydroid.simulate(
            model,
            {str(k): float(v) for k, v in coefficients.items()},
            vehicle_file,
            vehicle_json,
            t,
            series,
            {str(k): float(v) for k, v in (initial or {}).items()},
            int(substeps),
        )
    )
    df = pl.DataFrame(out["rows"], schema=out["columns"], orient="row")
    return _with_units(df, dict(zip(out["columns"], out["units"])))


from .batch import batch  # noqa: E402  (batch uses run and Result)
