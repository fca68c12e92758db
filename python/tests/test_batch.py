"""hydroid.batch on a dask.distributed LocalCluster of 2 worker processes, and locally,
gives the serial runs' numbers."""

import polars as pl
import pytest

import hydroid

CONFIGS = ["spheroid.toml", "spheroid_paper.toml"]


@pytest.fixture(scope="module")
def serial(root, tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    frames = []
    for name in CONFIGS:
        r = hydroid.run(root / "configs" / name, out=out / name)
        frames.append(r.coefficients.with_columns(pl.lit(name[:-5]).alias("config")))
    return pl.concat(frames).select(["config", *hydroid.COEFFICIENT_COLUMNS])


def test_batch_on_a_local_dask_cluster_equals_the_serial_runs(root, tmp_path, serial):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        table = hydroid.batch([root / "configs" / c for c in CONFIGS], client, out=tmp_path)
    assert table.columns == ["config", *hydroid.COEFFICIENT_COLUMNS]
    assert table.equals(serial)
    assert (tmp_path / "spheroid_paper" / "results.json").is_file()


def test_batch_without_a_client_runs_locally_in_parallel(root, tmp_path, serial):
    table = hydroid.batch([root / "configs" / c for c in CONFIGS], out=tmp_path, max_workers=2)
    assert table.equals(serial)


def test_batch_raises_the_error_of_a_failing_run(root, tmp_path):
    with pytest.raises(hydroid.HydroidError, match="nope.toml"):
        hydroid.batch([tmp_path / "nope.toml"], out=tmp_path)
