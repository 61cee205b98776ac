"""foldsim from Python: deployment dynamics of folded spacecraft structures.

    import foldsim
    s = foldsim.load("examples/paper-3panel.toml")
    r = s.run()                 # the GIL is released while it integrates; Ctrl-C stops it
    r["h1_yaw"], r.t            # NumPy arrays, one value per output row
    r.report["steps_accepted"]  # the run report as Python values
    r.to_pandas()               # a DataFrame, when pandas is installed

    s2 = s.with_values({"hinge.h1.law.k_theta": 2.0})    # change any value by key path
    d = foldsim.from_dict({...})                          # a scenario file's structure as a dict
    z = foldsim.generate.zfold(8, k_fold=2.0)             # the generators
    table = foldsim.sweep("examples/sweep-paper-1panel.toml")   # a DataFrame, one row per run
    table = foldsim.sweep(s, client=dask_client)          # the same table from a Dask cluster
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from . import generate
from ._foldsim import Scenario as _Scenario
from ._foldsim import __version__
from .sweeps import sweep

__all__ = ["Result", "Scenario", "load", "from_toml", "from_dict", "generate", "sweep", "__version__"]


class Result:
    """A finished run: every output column as a NumPy array, and the run report."""

    def __init__(self, names: list[str], arrays: list[np.ndarray], report: dict):
        self.columns = list(names)
        self._arrays = dict(zip(names, arrays))
        self.report = report

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._arrays[name]
        except KeyError:
            raise KeyError(f"no output column {name!r}; this run has {len(self.columns)}, e.g. {self.columns[:8]}") from None

    def __contains__(self, name: str) -> bool:
        return name in self._arrays

    @property
    def t(self) -> np.ndarray:
        """Output times, s."""
        return self["t"]

    def to_pandas(self):
        """The columns as a pandas DataFrame (pandas must be installed)."""
        import pandas as pd

        return pd.DataFrame(self._arrays, columns=self.columns)

    def __repr__(self) -> str:
        return f"<foldsim.Result: {len(self.t) if 't' in self else 0} rows × {len(self.columns)} columns>"


class Scenario:
    """A scenario (structure, initial state, run settings): docs/scenario.md."""

    def __init__(self, native: _Scenario):
        self._native = native

    @property
    def title(self) -> str | None:
        return self._native.title

    @property
    def bodies(self) -> list[str]:
        """Body names, hub first."""
        return self._native.bodies

    @property
    def hinges(self) -> list[str]:
        """Hinge names."""
        return self._native.hinges

    @property
    def text(self) -> str:
        """The scenario as TOML text (what a file of it holds)."""
        return self._native.text

    @property
    def warnings(self) -> list[str]:
        """Values that are valid but probably not meant."""
        return self._native.warnings

    def get(self, path: str) -> Any:
        """The value at a key path such as ``hinge.h1.law.k_theta`` (None if left out)."""
        return self._native.get(path)

    def with_values(self, changes: dict[str, Any] | None = None, **kwargs: Any) -> "Scenario":
        """A copy with values changed by key path, checked as a file would be:
        ``s.with_values({"hinge.h1.law.k_theta": 2.0, "run.duration": 5.0})``."""
        return Scenario(self._native.with_values({**(changes or {}), **kwargs}))

    def save(self, path: str | Path) -> None:
        """Writes the scenario as a TOML file."""
        Path(path).write_text(self.text)

    def run(self, columns: list[str] | None = None) -> Result:
        """Runs the scenario; `columns` are names or patterns as `run.columns` takes them."""
        names, arrays, report = self._native.run(columns)
        return Result(names, arrays, report)

    def __repr__(self) -> str:
        return f"<foldsim.Scenario {self.title!r}: {len(self.bodies)} bodies, {len(self.hinges)} hinges>"


def load(path: str | Path) -> Scenario:
    """Reads a scenario file (ValueError naming the file, line and key when it is bad)."""
    return Scenario(_Scenario.load(str(path)))


def from_toml(text: str, name: str = "scenario", base: str | Path | None = None) -> Scenario:
    """Reads a scenario from TOML text; table files are read relative to `base`."""
    return Scenario(_Scenario.from_toml(text, name, None if base is None else str(base)))


def from_dict(d: dict, name: str = "scenario dict", base: str | Path | None = None) -> Scenario:
    """Builds a scenario from a dict with a scenario file's structure: ``{"run": {...},
    "body": [{...}, ...], "hinge": [{...}, ...], "initial": {...}}``. Errors (ValueError) name
    the key path."""
    return Scenario(_Scenario.from_dict(d, name, None if base is None else str(base)))
