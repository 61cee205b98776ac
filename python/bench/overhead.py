"""Measures what the Python issue asks (a benchmark, not a test: these machines are shared).

    python python/bench/overhead.py            # from the repository root, package installed

1. A Python run() of paper-3panel against the CLI's own integration time (its report's wall
   time), medians of repeated runs.
2. The 1000-run paper-1panel sweep on 1 and 2 worker threads: wall time, CPU time, speed-up.
3. The same sweep on a 2-worker Dask LocalCluster against the local 2-thread sweep.
4. The tables of 1, 2, N workers and of Dask compared for equality.
The machine's load average is printed beside each figure.
"""

from __future__ import annotations

import os
import re
import resource
import statistics
import subprocess
import time
from pathlib import Path

import foldsim

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "foldsim"
PAPER3 = ROOT / "examples" / "paper-3panel.toml"
SWEEP = ROOT / "examples" / "sweep-paper-1panel.toml"


def load() -> str:
    return "load %.2f %.2f %.2f" % os.getloadavg()


def cpu() -> float:
    """CPU seconds of this process and its finished children."""
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def overhead(repeats: int = 15) -> None:
    cli, py, core = [], [], []
    s = foldsim.load(PAPER3)
    for _ in range(repeats):
        out = subprocess.run([str(CLI), "run", str(PAPER3), "--csv", "/tmp/foldsim-bench.csv"], check=True, capture_output=True, text=True).stdout
        cli.append(float(re.search(r"wall time\s+([0-9.]+) s", out).group(1)))
        t0 = time.perf_counter()
        r = s.run()
        py.append(time.perf_counter() - t0)
        core.append(r.report["wall_seconds"])
    c, p, k = statistics.median(cli), statistics.median(py), statistics.median(core)
    print(f"paper-3panel: CLI integration {c * 1e3:.2f} ms, Python run() {p * 1e3:.2f} ms (its integration {k * 1e3:.2f} ms): "
          f"run() / CLI = {p / c:.3f}  [{repeats} each, medians; {load()}]")


def timed_sweep(**kwargs):
    c0, t0 = cpu(), time.perf_counter()
    table = foldsim.sweep(SWEEP, **kwargs)
    return table, time.perf_counter() - t0, cpu() - c0


def parallel() -> dict:
    tables = {}
    t1s, t2s = [], []
    for _ in range(3):
        tables[1], w1, c1 = timed_sweep(workers=1)
        t1s.append((w1, c1, load()))
        tables[2], w2, c2 = timed_sweep(workers=2)
        t2s.append((w2, c2, load()))
    for w in (3, 8):
        tables[w], _, _ = timed_sweep(workers=w)
    w1 = min(t1s)
    w2 = min(t2s)
    print(f"1000-run sweep, 1 worker: {w1[0]:.2f} s wall, {w1[1]:.2f} s CPU [{w1[2]}]")
    print(f"1000-run sweep, 2 workers: {w2[0]:.2f} s wall, {w2[1]:.2f} s CPU [{w2[2]}]")
    print(f"  speed-up {w1[0] / w2[0]:.2f}x (parallel efficiency {w1[0] / w2[0] / 2:.0%}); "
          f"every pair of 1/1, 2/2 alternating: {[round(a[0] / b[0], 2) for a, b in zip(t1s, t2s)]}")
    return tables


def dask(tables: dict) -> None:
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        foldsim.sweep(SWEEP, runs=10, client=client)  # workers import foldsim
        ratios = []
        for _ in range(3):
            local, wl, _ = timed_sweep(workers=2)
            remote, wd, _ = timed_sweep(client=client)
            ratios.append((wd / wl, wd, wl, load()))
        best = min(ratios)
        print(f"2-worker LocalCluster: {best[1]:.2f} s against {best[2]:.2f} s local on 2 threads: {best[0]:.2f}x [{best[3]}]; all: {[round(r[0], 2) for r in ratios]}")
        same = all(t.equals(remote) for t in tables.values())
        print(f"tables equal for workers {sorted(tables)} and Dask: {same}")


if __name__ == "__main__":
    overhead()
    dask(parallel())
