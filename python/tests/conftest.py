"""Shared fixtures: the repository's root, and the hydroid command-line binary the CLI
comparison runs (HYDROID_BIN, else target/debug/hydroid, which `cargo test` or `cargo build`
leaves there)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def hydroid_bin() -> str:
    given = os.environ.get("HYDROID_BIN")
    path = Path(given) if given else ROOT / "target" / "debug" / "hydroid"
    if not path.is_file():
        pytest.fail(f"the hydroid binary {path} is missing: run `cargo build` (or set HYDROID_BIN)")
    return str(path)


@pytest.fixture(scope="session")
def spheroid_cli(tmp_path_factory, hydroid_bin):
    """The bundled spheroid example run by the command line: its output folder."""
    out = tmp_path_factory.mktemp("cli") / "spheroid"
    subprocess.run(
        [hydroid_bin, "-q", "run", str(ROOT / "configs" / "spheroid.toml"), "--out", str(out)],
        check=True,
        capture_output=True,
    )
    return out


@pytest.fixture(scope="session")
def spheroid_py(tmp_path_factory):
    """The bundled spheroid example run from Python."""
    import hydroid

    return hydroid.run(ROOT / "configs" / "spheroid.toml", out=tmp_path_factory.mktemp("py") / "spheroid")


def copy_config(root: Path, tmp: Path, name: str, edit=lambda s: s) -> Path:
    """configs/NAME copied into tmp with its relative input paths made absolute, edited."""
    text = (root / "configs" / name).read_text()
    text = text.replace('"../cfd_exports/', f'"{root}/cfd_exports/').replace('"../out/', f'"{tmp}/out/')
    p = tmp / name
    p.write_text(edit(text))
    return p


__all__ = ["ROOT", "copy_config", "shutil"]
