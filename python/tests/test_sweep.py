"""Sweeps from Python: the CLI's table, identical on any number of workers and on Dask,
failures recorded, streamed files, Ctrl-C."""

import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "foldsim"
SWEEP = ROOT / "examples" / "sweep-paper-1panel.toml"
RUNS = 120


def numbers(df: pd.DataFrame) -> np.ndarray:
    return df.drop(columns=["status", "error"]).to_numpy(dtype=float)


def test_the_table_equals_the_cli_csv_bit_for_bit(tmp_path: Path):
    out = tmp_path / "s.csv"
    subprocess.run([str(CLI), "sweep", str(SWEEP), "--runs", str(RUNS), "-q", "-o", str(out)], check=True)
    cli = pd.read_csv(out, float_precision="round_trip")  # pandas 3's default parser is not exact
    py = foldsim.sweep(SWEEP, runs=RUNS)
    assert list(py.columns) == list(cli.columns)
    assert np.array_equal(numbers(py), numbers(cli), equal_nan=True)
    assert (py.status == cli.status).all()


def test_the_table_is_the_same_on_1_2_and_5_workers():
    tables = [foldsim.sweep(SWEEP, runs=RUNS, workers=w) for w in (1, 2, 5)]
    assert tables[0].equals(tables[1]) and tables[0].equals(tables[2])
    other = foldsim.sweep(SWEEP, runs=RUNS, seed=7)
    assert not other.equals(tables[0])


def test_parameters_and_metrics_from_python_and_failures_recorded():
    s = foldsim.load(ROOT / "examples" / "paper-1panel.toml")
    table = foldsim.sweep(
        s,
        {"hinge.h1.law.k_theta": {"distribution": "normal", "mean": 0.5, "sd": 1.0}},
        {"pitch_max": {"column": "h1_pitch", "stat": "max"}},
        runs=40,
        seed=5,
    )
    assert list(table.columns[:4]) == ["run", "status", "hinge.h1.law.k_theta", "pitch_max"]
    failed = table.status == "failed"
    assert failed.any() and not failed.all()
    assert (failed == (table["hinge.h1.law.k_theta"] < 0)).all()
    assert table.error[failed].str.contains("k_theta").all()
    assert table.pitch_max[failed].isna().all() and table.pitch_max[~failed].notna().all()
    with pytest.raises(ValueError, match="'sd' must be a finite number|needs 'sd'"):
        foldsim.sweep(s, {"hinge.h1.law.k_theta": {"distribution": "normal", "mean": 1.0}}, runs=3, seed=1)


def test_streamed_files_are_the_table(tmp_path: Path):
    table = foldsim.sweep(SWEEP, runs=RUNS, output=tmp_path / "t.csv", workers=2)
    assert not (tmp_path / "t.csv.partial").exists()
    back = pd.read_csv(tmp_path / "t.csv", float_precision="round_trip")
    assert np.array_equal(numbers(back), numbers(table), equal_nan=True)
    pytest.importorskip("pyarrow")
    foldsim.sweep(SWEEP, runs=RUNS, output=tmp_path / "t.parquet", workers=2)
    back = pd.read_parquet(tmp_path / "t.parquet")
    assert np.array_equal(numbers(back), numbers(table), equal_nan=True)


def test_dask_local_cluster_gives_the_same_table():
    distributed = pytest.importorskip("distributed")
    local = foldsim.sweep(SWEEP, runs=RUNS)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            for chunk in (None, 7, RUNS):
                remote = foldsim.sweep(SWEEP, runs=RUNS, client=client, chunk_size=chunk)
                assert remote.equals(local), chunk


def test_ctrl_c_stops_a_sweep(ctrl_c):
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        foldsim.sweep(SWEEP, runs=1_000_000, workers=2)
    assert time.monotonic() - started < 5.0
