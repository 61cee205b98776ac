"""foldsim.fit (docs/fit.md): the same optimum as scipy's least_squares on the same problem,
the same values as the command line, the data as a file, a DataFrame or a dict, and what is
refused."""

import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import least_squares

import foldsim

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "foldsim"
SCENARIO = ROOT / "examples" / "paper-1panel.toml"
DATA = ROOT / "examples" / "fit-paper-1panel.csv"
FREE = {"hinge.h1.law.k_theta": (1.0, 100.0), "hinge.h1.law.c_theta": (0.0, 5.0)}
SIGMA = {"h1_yaw": 6.2e-5, "h1_pitch": 8.5e-4, "h1_roll": 8.4e-4}
COLUMNS = ["h1_yaw", "h1_pitch", "h1_roll"]


def test_the_optimum_is_scipys():
    """scipy.optimize.least_squares (trust-region reflective, its own 3-point differences,
    tolerances 1e-12) on the same weighted residuals, computed from foldsim's Python runs on
    the output grid the data were written on: the same optimum to 1e-6 relative (both
    minimise one function; what separates them is each one's difference quotients, ~1e-9)."""
    data = pd.read_csv(DATA, comment="#", float_precision="round_trip")
    s = foldsim.load(SCENARIO)
    paths = list(FREE)

    def residuals(x):
        r = s.with_values(dict(zip(paths, map(float, x)))).run(columns=["t"] + COLUMNS)
        # The run's rows every 0.05 s from 0; the data's from 0.05.
        return np.concatenate([(r[c][1:] - data[c].to_numpy()) / SIGMA[c] for c in COLUMNS])

    low, high = zip(*FREE.values())
    ref = least_squares(residuals, [10.0, 0.0 + 1e-9], bounds=(low, high), jac="3-point", x_scale="jac",
                        ftol=1e-12, xtol=1e-12, gtol=1e-12)
    ours = foldsim.fit(s, DATA, free=FREE, sigma=SIGMA)
    assert ours.converged, ours.stop
    for k, p in enumerate(paths):
        rel = abs(ours.values[p] - ref.x[k]) / abs(ref.x[k])
        print(f"{p}: foldsim {ours.values[p]:.12g}, scipy {ref.x[k]:.12g}, relative difference {rel:.2e}")
        assert rel <= 1e-6
    # The same residuals at the optimum: the two problems are one.
    assert np.allclose(residuals(list(ours.values.values())), ours.residuals, rtol=1e-9, atol=1e-9)


def test_python_and_the_command_line_agree(tmp_path: Path):
    out = tmp_path / "fitted.toml"
    args = [str(CLI), "fit", str(SCENARIO), "--data", str(DATA), "-o", str(out)]
    for p, (lo, hi) in FREE.items():
        args += ["--free", f"{p}={lo!r}:{hi!r}"]
    for c, v in SIGMA.items():
        args += ["--sigma", f"{c}={v!r}"]
    subprocess.run(args, check=True, capture_output=True)
    cli = foldsim.load(out)
    ours = foldsim.fit(SCENARIO, DATA, free=FREE, sigma=SIGMA)
    for p in FREE:
        assert ours.values[p] == cli.get(p) == ours.scenario.get(p)
        assert ours.standard_errors[p] > 0 and ours.warnings[p] is None
    assert ours.correlation.shape == (2, 2) and ours.columns["h1_pitch"]["fitted"].shape == ours.t.shape
    assert "hinge.h1.law.k_theta" in ours.report


def test_a_dataframe_and_a_dict_are_the_file():
    frame = pd.read_csv(DATA, comment="#", float_precision="round_trip")
    a = foldsim.fit(SCENARIO, frame, free=FREE, sigma=SIGMA)
    b = foldsim.fit(SCENARIO, {c: frame[c].to_numpy() for c in frame.columns}, free=FREE, sigma=SIGMA)
    c = foldsim.fit(SCENARIO, DATA, free=[f"{p}={lo}:{hi}" for p, (lo, hi) in FREE.items()], sigma=SIGMA)
    assert a.values == b.values == c.values
    # None marks a value not measured then: fewer values, the same kind of answer.
    thin = {c: list(frame[c]) for c in frame.columns}
    thin["h1_yaw"] = [v if i % 2 == 0 else None for i, v in enumerate(thin["h1_yaw"])]
    d = foldsim.fit(SCENARIO, thin, free=FREE, sigma=SIGMA)
    assert d.columns["h1_yaw"]["count"] == (len(frame) + 1) // 2
    assert abs(d.values["hinge.h1.law.k_theta"] - 12.3) < 0.02 * 12.3


def test_bad_input_is_refused_by_name():
    frame = pd.read_csv(DATA, comment="#", float_precision="round_trip").head(5)
    nan = frame.copy()
    nan.loc[2, "h1_yaw"] = float("nan")
    with pytest.raises(ValueError, match=r"data \(line 1 the header, line k \+ 2 row k\):4: column 'h1_yaw': 'nan'"):
        foldsim.fit(SCENARIO, nan, free=FREE)
    with pytest.raises(ValueError, match="'nope' is not an output column"):
        foldsim.fit(SCENARIO, {"t": [0.1, 0.2], "nope": [0.0, 0.0]}, free=FREE)
    with pytest.raises(ValueError, match="outside the bounds"):
        foldsim.fit(SCENARIO, frame, free={"hinge.h1.law.k_theta": (20, 30)})
    with pytest.raises(ValueError, match="not a number"):
        foldsim.fit(SCENARIO, frame, free=["hinge.h1.law.type"])
    with pytest.raises(TypeError, match="bounds are"):
        foldsim.fit(SCENARIO, frame, free={"hinge.h1.law.k_theta": 3})
    with pytest.raises(TypeError):
        foldsim.fit(SCENARIO, 42, free=FREE)
    with pytest.raises(ValueError, match="1 row"):
        foldsim.fit(SCENARIO, frame.head(1), free=["hinge.h1.law.k_theta"])
