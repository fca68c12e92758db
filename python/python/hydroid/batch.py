"""Many identifications at once: :func:`batch` maps :func:`hydroid.run` over a Dask
cluster (``dask.distributed``), or over local processes without one. The scheduling is
Dask's (``client.map`` and ``client.gather``) or the standard library's
(``concurrent.futures``); hydroid adds none of its own."""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, List, Optional, Sequence, Union

import polars as pl

PathLike = Union[str, "os.PathLike[str]"]


def _run_one(config: str, out: Optional[str], overrides: List[str], force: bool) -> dict:
    """One run, on a worker: its coefficients as plain columns (picklable)."""
    import hydroid

    r = hydroid.run(config, out=out, overrides=overrides, force=force)
    return r.coefficients.to_dict(as_series=False)


def batch(
    configs: Sequence[Union[PathLike, Any]],
    client: Any = None,
    *,
    out: Optional[PathLike] = None,
    overrides: Optional[Sequence[str]] = None,
    force: bool = False,
    max_workers: Optional[int] = None,
) -> pl.DataFrame:
    """Runs every configuration of ``configs`` and returns one table: the coefficients of
    each run (the columns of :attr:`hydroid.Result.coefficients`) with a first column
    ``config``, the configuration's file name without ``.toml``, in the order given.

    With ``client`` (a ``dask.distributed.Client``) the runs are mapped over its workers
    (``client.map``, then ``client.gather``); every worker needs the ``hydroid`` package and
    the configurations' files at the same paths. Without, they run in parallel in local
    processes (``concurrent.futures.ProcessPoolExecutor``, spawned, ``max_workers``). Each run writes
    its output folder as :func:`hydroid.run` does: into ``out/NAME`` when ``out`` is given,
    else its configuration's ``output.dir``, so two configurations must not share one. The
    first run that fails raises its :class:`hydroid.HydroidError`.
    """
    paths = [os.fspath(c) for c in configs]
    names = [Path(p).stem for p in paths]
    if len(set(names)) != len(names):
        raise ValueError(f"batch: two configurations share a name: {names}")
    outs = [None if out is None else os.fspath(Path(out) / n) for n in names]
    sets = [list(overrides or [])] * len(paths)
    forces = [force] * len(paths)
    if client is not None:
        # pure=False: a run writes files, Dask must not skip it as a cached result
        futures = client.map(_run_one, paths, outs, sets, forces, pure=False)
        tables = client.gather(futures)
    else:
        # spawned, not forked: a fork of a process whose Rust thread pool (rayon) already ran
        # would wait for threads the child does not have
        spawn = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=max_workers, mp_context=spawn) as pool:
            tables = list(pool.map(_run_one, paths, outs, sets, forces))
    frames = [
        pl.DataFrame(t, schema=_schema()).with_columns(pl.lit(n).alias("config")).select(
            ["config", *_schema().keys()]
        )
        for n, t in zip(names, tables)
    ]
    return pl.concat(frames)


def _schema() -> dict:
    from . import _COEFFICIENT_SCHEMA

    return dict(_COEFFICIENT_SCHEMA)
