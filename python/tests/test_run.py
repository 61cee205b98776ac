"""The Python package against the command line, and its run's manners (GIL, Ctrl-C, errors).

Run from the repository root after `maturin develop --release` in python/ and
`cargo build --release` (for the CLI): `pytest python/tests`.
"""

import csv
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "foldsim"
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return [c.strip() for c in rows[0]], np.array([[float(x) for x in r] for r in rows[1:]])


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_columns_equal_the_cli_csv_bit_for_bit(example: Path, tmp_path: Path):
    """Every column of every example, as the CLI writes it (shortest round-trip digits,
    which parse back to the same doubles): equal, NaN where NaN."""
    out = tmp_path / "run.csv"
    subprocess.run([str(CLI), "run", str(example), "--csv", str(out), "-q"], check=True)
    names, table = read_csv(out)
    r = foldsim.load(example).run()
    assert r.columns == names
    for i, name in enumerate(names):
        assert np.array_equal(table[:, i], r[name], equal_nan=True), name
    assert r.report["rows"] == len(table)


def test_bad_input_names_file_line_and_key():
    with pytest.raises(ValueError, match=r"bad\.toml:\d+:\d+: .*output_step"):
        foldsim.from_toml("[run]\nduration = 1.0\n", "bad.toml")
    with pytest.raises(KeyError, match="no output column 'nope'"):
        foldsim.load(ROOT / "examples" / "paper-1panel.toml").run()["nope"]


def test_auto_reports_its_methods():
    text = (ROOT / "examples" / "paper-1panel.toml").read_text().replace('integrator = "dop853"', "")
    s = foldsim.from_toml(text, "auto.toml")
    r = s.run(columns=["t"])
    assert r.report["methods"] == [(0.0, "dop853", "the start")]
    assert r.report["refactorizations"] == 0


def test_position_tolerance_reports_its_estimate():
    """run.position_tolerance from Python: the report's estimate within what was asked, the
    output the run of that rtol, and a stepped run refused with the key named."""
    text = (ROOT / "examples" / "paper-1panel.toml").read_text()
    text = text.replace("rtol = 1e-12\natol = 1e-12", "position_tolerance = 1e-4")
    assert "position_tolerance" in text, "the example's [run] table changed: update this test"
    s = foldsim.from_toml(text, "ptol.toml")
    a = s.run(columns=["t"]).report["position_accuracy"]
    assert a["asked"] == 1e-4 and 0 < a["estimated"] <= 1e-4
    assert len(a["runs"]) >= 2 and a["rtol"] in [r[0] for r in a["runs"]]
    assert a["check_rtol"] in [r[0] for r in a["runs"]] and a["check_rtol"] < a["rtol"]
    with pytest.raises(Exception, match="position_tolerance"):
        s.start()


def test_the_gil_is_released_while_it_integrates():
    """Another Python thread keeps running during a run (it would stall with the GIL held)."""
    s = foldsim.load(ROOT / "examples" / "flasher-small.toml")
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    s.run(columns=["t"])
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    assert end - start > 0.3 and len(during) > 0.3 * (end - start) / 0.005


def test_ctrl_c_stops_a_run(ctrl_c):
    s = foldsim.load(ROOT / "examples" / "flasher-starshade.toml")
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt, match="interrupted at t ="):
        s.run(columns=["t"])
    assert time.perf_counter() - start < 3.0


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    r = foldsim.load(ROOT / "examples" / "paper-1panel.toml").run()
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == r.columns and len(df) == len(r.t)
