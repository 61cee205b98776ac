"""Sweeps from Python: many runs of a scenario with values drawn per run, one summary row
per run (docs/sweep.md), on this machine's cores or on a Dask cluster.

Run ``i`` draws its values from its own random stream of the seed, so the table is the same
whichever worker runs which run, on one machine or many.
"""

from __future__ import annotations

import functools
import math
import os
import uuid
import warnings
from pathlib import Path
from typing import Any

from . import _foldsim
from ._checks import count


def _native_scenario(scenario):
    from . import Scenario, load

    if isinstance(scenario, (str, Path)):
        scenario = load(scenario)
    if isinstance(scenario, Scenario):
        return scenario._native
    if isinstance(scenario, _foldsim.Scenario):
        return scenario
    raise TypeError(f"sweep() takes a foldsim.Scenario or a scenario file's path, not {type(scenario).__name__}")


def _frame(columns: dict, header: list[str]):
    import pandas as pd

    return pd.DataFrame({name: columns[name] for name in header}, columns=header)


@functools.lru_cache(maxsize=8)
def _worker_sweep(text: str, name: str, base: str, runs: int, seed: int) -> "_foldsim.Sweep":
    """The sweep rebuilt on a worker from its text (cached: one parse per worker)."""
    scenario = _foldsim.Scenario.from_toml(text, name, base)
    return _foldsim.Sweep(scenario, None, runs, seed)


def _run_chunk(text: str, name: str, base: str, runs: int, seed: int, start: int, stop: int) -> dict:
    """Runs start..stop of a sweep on a Dask worker (one thread: Dask spreads the chunks)."""
    return _worker_sweep(text, name, base, runs, seed).run(start, stop, 1)


def _chunks(runs: int, size: int):
    return [(a, min(a + size, runs)) for a in range(0, runs, size)]


class _Writer:
    """Streams chunks of the table to CSV or Parquet through ``<file>.partial``, renamed once
    the last run is done: a sweep that stops leaves no file that looks complete."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self.partial = self.path.with_name(self.path.name + ".partial")
        suffix = self.path.suffix.lower()
        if suffix not in (".csv", ".parquet"):
            raise ValueError(f"{self.path}: the summary is written as .csv or .parquet")
        self.parquet = suffix == ".parquet"
        self.writer = None
        self.first = True

    def write(self, frame) -> None:
        if self.parquet:
            import pyarrow as pa
            import pyarrow.parquet as pq

            table = pa.Table.from_pandas(frame, preserve_index=False)
            if self.writer is None:
                self.writer = pq.ParquetWriter(self.partial, table.schema)
            self.writer.write_table(table)
        else:
            frame.to_csv(self.partial, mode="w" if self.first else "a", header=self.first, index=False)
        self.first = False

    def finish(self) -> None:
        if self.writer is not None:
            self.writer.close()
        os.replace(self.partial, self.path)


class _Progress:
    """Runs done and failed, on a tqdm bar when someone watches (a terminal, a notebook)."""

    def __init__(self, total: int, progress: bool | None):
        from . import _progress_bar

        self.done, self.failed = 0, 0
        self.bar = _progress_bar(total, "runs", progress)

    def add(self, frame) -> None:
        self.done += len(frame)
        self.failed += int((frame["status"] != "ok").sum())
        if self.bar:
            self.bar.update_to(self.done, failed=self.failed)

    def close(self) -> None:
        if self.bar:
            self.bar.close()


def sweep(
    scenario,
    parameters: dict[str, dict] | None = None,
    metrics: dict[str, dict] | None = None,
    runs: int | None = None,
    seed: int | None = None,
    *,
    workers: int | None = None,
    client=None,
    chunk_size: int | None = None,
    output: str | Path | None = None,
    progress: bool | None = None,
):
    """Runs a sweep and returns its summary table as a pandas DataFrame, one row per run in
    run order: ``run``, ``status`` (ok or failed), the swept values (columns named by key
    path), the metrics, the built-in metrics (deployment_time, energy_drift, energy_balance,
    momentum_drift, angular_momentum_drift, steps) and ``error`` (why a run failed).

    scenario: a :class:`foldsim.Scenario` or a scenario file's path.
    parameters, metrics: the ``[sweep.parameters]`` and ``[sweep.metrics]`` tables as dicts,
        e.g. ``{"hinge.h1.law.k_theta": {"distribution": "normal", "mean": 1.0, "sd": 0.1}}``
        and ``{"yaw_max": {"column": "h1_yaw", "stat": "max"}}``; without them the
        scenario's own ``[sweep]`` table is used.
    runs, seed: the run count and seed (override the table's).
    workers: threads on this machine (default: one per core).
    client: a ``dask.distributed.Client``: the runs go to its workers in chunks of
        `chunk_size` (default: four chunks per worker thread) and come back as the same table.
    output: also stream the table to this .csv or .parquet file as chunks finish.
    progress: a progress bar (tqdm; default: on a terminal or in a notebook; then local runs
        go in chunks of 16 per worker so that it moves).

    A sweep in which every run fails raises RuntimeError with the first run's error (the
    table, if written to `output`, is kept: it says why each run failed).
    """
    workers = count(workers, "workers")
    chunk_size = count(chunk_size, "chunk_size")
    runs = count(runs, "runs")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ValueError(f"seed must be a whole number >= 0; got {seed!r}")
    native = _native_scenario(scenario)
    spec = None
    if parameters is not None:
        spec = {k: v for k, v in {"runs": runs, "seed": seed, "parameters": parameters, "metrics": metrics or {}}.items() if v is not None}
    elif metrics is not None:
        raise ValueError("metrics= needs parameters= too (or put both in the scenario's [sweep] table)")
    sw = _foldsim.Sweep(native, spec, runs, seed)
    header = list(sw.header)
    n = sw.runs
    if output is not None:
        output = Path(os.fspath(output))
        _foldsim.check_outputs([str(p) for p in sw.inputs], [("output", str(output))])
    writer = _Writer(output) if output is not None else None
    import pandas as pd

    report = _Progress(n, progress)
    if client is None:
        workers = workers or os.cpu_count() or 1
        if workers > n:
            warnings.warn(f"foldsim.sweep: {workers} workers for {n} runs; using {n}", stacklevel=2)
            workers = n
        # Streaming to a file or showing progress runs in chunks (each over every worker);
        # otherwise one go.
        size = chunk_size or (max(64, 16 * workers) if writer or progress else n)
        parts = []
        for a, b in _chunks(n, size):
            frame = _frame(sw.run(a, b, workers), header)
            if writer:
                writer.write(frame)
            report.add(frame)
            parts.append(frame)
    else:
        if workers is not None:
            raise ValueError("workers= is for this machine; on Dask the cluster's workers run the chunks")
        threads = sum(client.nthreads().values()) or 1
        size = chunk_size or max(1, math.ceil(n / (4 * threads)))
        bounds = _chunks(n, size)
        args = (sw.text, sw.name, str(sw.base), n, sw.seed)
        token = uuid.uuid4().hex  # a fresh key per call: Dask must not reuse another sweep's results
        futures = client.map(
            _run_chunk, *zip(*[(*args, a, b) for a, b in bounds]), key=[f"foldsim-sweep-{token}-{a}-{b}" for a, b in bounds]
        )
        parts = []
        for future in futures:  # in run order, each as soon as it and those before are done
            frame = _frame(future.result(), header)
            if writer:
                writer.write(frame)
            report.add(frame)
            parts.append(frame)
    report.close()
    if writer:
        writer.finish()
    table = pd.concat(parts, ignore_index=True) if parts else _frame({h: [] for h in header}, header)
    if len(table) and (table["status"] != "ok").all():
        where = f"; the table of failures is in {output}" if output is not None else ""
        raise RuntimeError(f"every run of the sweep failed ({len(table)} runs); run 0: {table['error'].iloc[0]}{where}")
    return table
