"""Fitting scenario values to measurements from Python (docs/fit.md, docs/python.md):
``foldsim.fit(scenario, data, free=...)``, the same fit as ``foldsim fit`` on the command line."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from . import _foldsim
from ._checks import path_arg


class FitResult:
    """A finished fit. ``values``, ``standard_errors`` and ``warnings`` are dicts by key path
    (a standard error is None where the data do not determine the value or it is pinned at a
    bound, and the warning says which); ``correlation`` is the parameters' correlation matrix
    (NaN where a parameter has no standard error); ``columns`` holds, per measured column, the
    measured and fitted values at the data's times ``t``, the residuals' RMS and count;
    ``scenario`` is the scenario with the fitted values; ``report`` the command line's text."""

    def __init__(self, d: dict, scenario_cls, base: str):
        self.paths: list[str] = list(d["paths"])
        self.values: dict[str, float] = dict(zip(self.paths, d["values"]))
        self.standard_errors: dict[str, float | None] = dict(zip(self.paths, d["standard_errors"]))
        self.warnings: dict[str, str | None] = dict(zip(self.paths, d["warnings"]))
        self.starts: dict[str, float] = dict(zip(self.paths, d["starts"]))
        self.bounds: dict[str, tuple[float, float]] = dict(zip(self.paths, d["bounds"]))
        self.correlation: np.ndarray = d["correlation"]
        self.jacobian: np.ndarray = d["jacobian"]
        self.residuals: np.ndarray = d["residuals"]
        self.variance: float = d["variance"]
        self.dof: int = d["dof"]
        self.condition: float = d["condition"]
        self.converged: bool = d["converged"]
        self.stop: str = d["stop"]
        self.iterations: int = d["iterations"]
        self.runs: int = d["runs"]
        self.wall_seconds: float = d["wall_seconds"]
        self.residual_norm: tuple[float, float] = tuple(d["residual_norm"])
        self.t: np.ndarray = d["t"]
        self.columns: dict[str, dict[str, Any]] = d["columns"]
        self.report: str = d["report"]
        self.scenario = scenario_cls(_foldsim.Scenario.from_toml(d["text"], "fitted", base))

    def __repr__(self) -> str:
        parts = []
        for p in self.paths:
            se = self.standard_errors[p]
            parts.append(f"{p} = {self.values[p]:.6g}" + (f" ± {se:.2g}" if se is not None else " (no error)"))
        return f"<foldsim.FitResult: {'; '.join(parts)}>"


def _free_args(free: Any) -> list[str]:
    if isinstance(free, str):
        return [free]
    if isinstance(free, Mapping):
        out = []
        for path, bounds in free.items():
            if not isinstance(path, str):
                raise TypeError(f"fit(free=...): key paths are str, not {type(path).__name__}")
            if bounds is None:
                out.append(path)
                continue
            try:
                low, high = bounds
            except (TypeError, ValueError):
                raise TypeError(f"fit(free={{{path!r}: ...}}): bounds are (low, high) or None, not {bounds!r}") from None
            def side(b):
                if b is None or (isinstance(b, float) and math.isinf(b)):
                    return ""
                if isinstance(b, bool) or not isinstance(b, (int, float)):
                    raise TypeError(f"fit(free={{{path!r}: ...}}): a bound is a number or None, not {b!r}")
                return repr(float(b))
            out.append(f"{path}={side(low)}:{side(high)}")
        return out
    out = list(free)
    bad = [f for f in out if not isinstance(f, str)]
    if bad:
        raise TypeError(f"fit(free=...): give key paths (str, 'KEY=LOW:HIGH') or a dict of bounds, not {type(bad[0]).__name__}")
    return out


def _data_text(data: Any) -> tuple[str, str]:
    """The data as CSV text and the label its errors carry."""
    if isinstance(data, (str, Path)):
        p = Path(path_arg(data, "data"))
        try:
            return p.read_text(), str(p)
        except (OSError, UnicodeDecodeError) as e:
            raise ValueError(f"fit(data={str(p)!r}): cannot read it: {e}") from None
    try:
        import pandas as pd

        if isinstance(data, pd.DataFrame):
            data = {str(c): data[c].to_numpy() for c in data.columns}
    except ImportError:
        pass
    if not isinstance(data, Mapping):
        raise TypeError(f"fit(data=...): a CSV path, a pandas DataFrame or a dict of arrays, not {type(data).__name__}")
    names = [str(k) for k in data]
    cols = [np.asarray(v, dtype=object) for v in data.values()]
    lengths = {len(c) for c in cols}
    if len(lengths) > 1:
        raise ValueError(f"fit(data=...): the columns have different lengths {sorted(lengths)}")
    rows = [",".join(names)]
    for i in range(lengths.pop() if lengths else 0):
        cells = []
        for c in cols:
            v = c[i]
            # None is a value not measured then; NaN is refused by name, as in a file.
            cells.append("" if v is None else repr(float(v)))
        rows.append(",".join(cells))
    return "\n".join(rows) + "\n", "data (line 1 the header, line k + 2 row k)"


def fit(scenario: Any, data: Any, free: Any, sigma: Mapping[str, float] | None = None, max_iterations: int = 100) -> FitResult:
    """Fits scenario values to measurements (docs/fit.md).

    ``scenario``: a Scenario or a scenario file's path. ``data``: a CSV file's path, a pandas
    DataFrame or a dict of arrays, with a ``t`` column (s) and output columns by name
    (None marks a value not measured then). ``free``: key paths, as ``"KEY"`` or
    ``"KEY=LOW:HIGH"`` strings or a dict ``{path: (low, high) or None}`` (None for a side
    without a bound); a wildcard ties one value across entries. ``sigma``: per column, its
    measurement noise in its unit. The runs of each Jacobian go to every core, the GIL
    released.
    """
    from . import Scenario, load

    if isinstance(scenario, (str, Path)):
        scenario = load(scenario)
    if not isinstance(scenario, Scenario):
        raise TypeError(f"fit(scenario=...): a foldsim.Scenario or a path, not {type(scenario).__name__}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int) or not 1 <= max_iterations <= 1_000_000:
        raise ValueError(f"fit(max_iterations={max_iterations!r}): a whole number from 1 to 1,000,000")
    text, name = _data_text(data)
    if sigma is not None and not isinstance(sigma, Mapping):
        raise TypeError(f"fit(sigma=...): a dict of column: noise, not {type(sigma).__name__}")
    sig = []
    for c, v in (sigma or {}).items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise TypeError(f"fit(sigma={{{c!r}: {v!r}}}): a number")
        sig.append((str(c), float(v)))
    d = _foldsim.fit(scenario._native, text, name, _free_args(free), sig, max_iterations)
    return FitResult(d, Scenario, str(scenario._native.base))
