"""Type stubs of the compiled module (python/src/lib.rs). Each function returns JSON text
that the pure-Python part (hydroid/__init__.py) turns into DataFrames; call those instead."""

from typing import Dict, List, Optional, Tuple

__version__: str
COEFFICIENT_COLUMNS: List[str]

class HydroidError(Exception):
    """An error of hydroid: the message names the file, line, column or configuration key.

    Attributes:
        problems: each problem as {file, line, column, column_name, key, message} (the form
            of ``hydroid check --json``); absent when raised by the Python part.
        exit_code: the command line's exit code for the error.
    """

    problems: List[Dict[str, object]]
    exit_code: int

def run(
    config: str, out: Optional[str] = None, overrides: List[str] = ..., force: bool = False
) -> Tuple[str, str]:
    """Runs a configuration, writes its output folder; returns (folder, results.json text)."""

def check_config(config: str, overrides: List[str] = ..., out: Optional[str] = None) -> str:
    """``hydroid check --json``'s document, as JSON text."""

def read(file: str, format: Optional[str] = None) -> str:
    """One export as JSON text {file, format, columns, time, warnings}, values in SI."""

def models() -> str:
    """Every model of the catalogue, JSON text."""

def coefficients(model: Optional[str] = None) -> str:
    """The coefficient catalogue, or one model's entry, JSON text."""

def simulate(
    model: str,
    coefficients: Dict[str, float],
    vehicle_file: Optional[str],
    vehicle_json: Optional[str],
    t: List[float],
    inputs: Dict[str, List[float]],
    initial: Dict[str, float],
    substeps: int,
) -> str:
    """A simulation as JSON text {columns, units, rows}."""
