"""foldsim from Python: deployment dynamics of folded spacecraft structures.

    import foldsim
    s = foldsim.load("examples/paper-3panel.toml")
    r = s.run()                 # the GIL is released while it integrates; Ctrl-C stops it
    r["h1_yaw"], r.t            # NumPy arrays, one value per output row
    r.report["steps_accepted"]  # the run report as Python values
    r.to_pandas()               # a DataFrame, when pandas is installed
    s.overlaps(r)               # how deep any two bodies overlapped, apart from the contact code

    s2 = s.with_values({"hinge.h1.law.k_theta": 2.0})    # change any value by key path
    d = foldsim.from_dict({...})                          # a scenario file's structure as a dict
    z = foldsim.generate.zfold(8, k_fold=2.0)             # the generators
    table = foldsim.sweep("examples/sweep-paper-1panel.toml")   # a DataFrame, one row per run
    table = foldsim.sweep(s, client=dask_client)          # the same table from a Dask cluster
    f = foldsim.fit(s, "data.csv", free={"hinge.h1.law.k_theta": (1, 100)})   # fit to measurements
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from . import _foldsim, generate
from ._checks import path_arg
from ._foldsim import Scenario as _Scenario
from ._foldsim import __version__
from .sweeps import sweep
from .fitting import FitResult, fit

__all__ = ["FitResult", "fit", "Result", "Scenario", "Simulation", "State", "load", "from_toml", "from_dict", "generate", "sweep", "__version__"]


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


# The columns of a body's pose (docs/outputs.md): its centre of mass in N and its attitude, as
# a quaternion or, in CSVs written before the quaternions, as 3-2-1 angles.
_POSE_SUFFIXES = ("_R_x", "_R_y", "_R_z", "_q_w", "_q_x", "_q_y", "_q_z", "_yaw", "_pitch", "_roll")


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

    def get(self, path: str, *default: Any) -> Any:
        """The value at a key path such as ``hinge.h1.law.k_theta``. KeyError when the
        scenario has nothing there (a key left out, or one that does not exist), unless a
        default is given: ``s.get("hinge.h1.law.c_theta", 0.0)``."""
        if len(default) > 1:
            raise TypeError(f"get() takes a path and at most one default, not {1 + len(default)} arguments")
        path_arg(path, "path")
        try:
            return self._native.get(path)
        except KeyError:
            if default:
                return default[0]
            raise

    def with_values(self, changes: dict[str, Any] | None = None, **kwargs: Any) -> "Scenario":
        """A copy with values changed by key path, checked as a file would be:
        ``s.with_values({"hinge.h1.law.k_theta": 2.0, "run.duration": 5.0})``."""
        return Scenario(self._native.with_values({**(changes or {}), **kwargs}))

    def save(self, path: str | Path) -> None:
        """Writes the scenario as a TOML file (through ``<path>.partial``, renamed when
        complete; never over a table file the scenario reads)."""
        path = Path(path_arg(path, "path"))
        _foldsim.check_outputs(self._native.inputs, [("save()", str(path))])
        partial = path.with_name(path.name + ".partial")
        partial.write_text(self.text)
        os.replace(partial, path)

    def run(self, columns: list[str] | str | None = None, progress: bool | None = None) -> Result:
        """Runs the scenario; `columns` are names or patterns as `run.columns` takes them, as
        a list or comma-separated (``"t,h*_yaw"``, as the command line's ``--columns``).
        `progress`: a progress bar (tqdm) in a notebook or on a terminal; default: when there
        is one."""
        if isinstance(columns, str):
            columns = [c.strip() for c in columns.split(",") if c.strip()]
        elif columns is not None:
            columns = list(columns)
            bad = [c for c in columns if not isinstance(c, str)]
            if bad:
                raise TypeError(f"run(columns=...) takes column names (str), not {type(bad[0]).__name__}")
        bar = _progress_bar(self._native.duration, "s", progress)
        try:
            names, arrays, report = self._native.run(columns, bar.update_to if bar else None)
        finally:
            if bar:
                bar.close()
        return Result(names, arrays, report)

    def overlaps(self, run: "Result | str | os.PathLike", *, sharp: bool = False) -> list[dict]:
        """How deep any two bodies overlap over a finished run of this scenario, measured
        from its poses alone, apart from the contact code (parry's GJK/EPA on each body's
        solid; docs/contact.md §3), as ``foldsim overlaps`` does. `run`: the `Result` of
        ``run()`` (with every body's ``_R_*`` and ``_q_*`` columns, as by default) or the
        path of the CSV ``foldsim run`` wrote. One dict per pair that overlaps at some row,
        deepest first: ``body_a``, ``body_b``, ``depth`` (m), ``of_thickness`` (the depth
        over the thinner body's thickness) and ``t`` (s). Thin plates as the contact samples
        describe them (rims rounded with half the thickness), or as sharp prisms with
        ``sharp=True``."""
        if not isinstance(sharp, (bool, np.bool_)):
            raise TypeError(f"sharp is True or False, got {sharp!r}")
        if isinstance(run, Result):
            # Only the times and the poses cross over (a starshade's run has some 14,000 columns).
            wanted = {"t"} | {b + end for b in self.bodies for end in _POSE_SUFFIXES}
            names = [c for c in run.columns if c in wanted]
            return self._native.overlaps(
                names=names, columns=[np.asarray(run[c], dtype=float).tolist() for c in names], sharp=bool(sharp)
            )
        return self._native.overlaps(csv=path_arg(run, "run"), sharp=bool(sharp))

    def start(self, columns: list[str] | str | None = None) -> "Simulation":
        """Starts a run to advance piece by piece with your own controller in the loop
        (docs/gnc.md): ``sim = s.start(); sim.advance(0.01); sim.state["w_B_z"]``.
        `columns` choose what ``result()`` gives, as for ``run``."""
        return Simulation(self._native.start(_columns(columns)))

    def linearize(
        self,
        at: float = 0.0,
        *,
        deployed: bool = False,
        inputs: list[str] | str | None = None,
        outputs: list[str] | str | None = None,
        modes: int | None = None,
        hub_held: bool = False,
    ) -> dict:
        """The linear state-space model ``ẋ = A x + B u``, ``y = C x + D u`` at time `at` of
        the run, or about the design state with ``deployed=True`` (docs/linear.md): a dict
        with ``A``, ``B``, ``C``, ``D`` (NumPy arrays: ``control.ss(m["A"], m["B"], m["C"],
        m["D"])`` in python-control), ``y0`` (the outputs at the state), ``t``, ``residual``
        and the names of ``states``, ``inputs`` and ``outputs``. `inputs`: the bodies that
        take force and torque inputs (default the hub); `outputs`: output column names or
        patterns (default the hub's MRPs and rates). `modes`: reduced to the six rigid-body
        modes and that many flexible free-free modes, or with ``hub_held=True`` to the hub's
        six coordinates and that many modes with the hub held; the rigid-body poles exactly
        at zero (docs/linear.md, *Reduced models*; about a state at rest and in balance)."""
        if modes is not None and (
            isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or not 1 <= modes <= 10**9
        ):
            raise ValueError(f"modes is a whole number from 1 to 1e9 of flexible modes to keep, got {modes!r}")
        if not isinstance(hub_held, (bool, np.bool_)):
            raise TypeError(f"hub_held is True or False, got {hub_held!r}")
        return self._native.linearize(
            float(at), bool(deployed), _columns(inputs), _columns(outputs), None if modes is None else int(modes), bool(hub_held)
        )

    def modes(self, at: float = 0.0, *, deployed: bool = False, count: int | None = None) -> dict:
        """The natural modes at time `at` of the run, or of the design state with
        ``deployed=True`` (docs/linear.md): ``{"free": …, "hub_fixed": …, "appendage_total":
        […]}``, each set a dict of arrays ``frequency_hz``, ``omega``, ``omega_squared``,
        ``damping_ratio``, ``rigid``, ``shapes`` (one column per mode, 6 coordinates per body)
        and ``effective`` (per mode, the effective masses and inertias about the hub). Every
        mode by the dense solver, or the `count` lowest flexible ones by Lanczos."""
        return self._native.modes(float(at), bool(deployed), None if count is None else int(count))

    def __repr__(self) -> str:
        return f"<foldsim.Scenario {self.title!r}: {len(self.bodies)} bodies, {len(self.hinges)} hinges>"


def _columns(columns):
    if isinstance(columns, str):
        return [c.strip() for c in columns.split(",") if c.strip()]
    if columns is not None:
        columns = list(columns)
        bad = [c for c in columns if not isinstance(c, str)]
        if bad:
            raise TypeError(f"columns takes column names (str), not {type(bad[0]).__name__}")
    return columns


def _vector(value, what: str) -> list[float]:
    v = [float(x) for x in value]
    if len(v) != 3:
        raise ValueError(f"{what} is three numbers [x, y, z], got {len(v)}")
    return v


class State(dict):
    """Every output column at one time, by name (docs/outputs.md). A name that is not there
    raises KeyError naming the closest ones; :meth:`vector` gathers a vector's columns."""

    def __missing__(self, key):
        import difflib

        close = difflib.get_close_matches(str(key), list(self), n=5, cutoff=0.5)
        hint = f"; the closest are {', '.join(close)}" if close else ""
        raise KeyError(f"no column {key!r}{hint} (docs/outputs.md lists every column)")

    def vector(self, prefix: str) -> "np.ndarray":
        """The columns ``prefix_w/_x/_y/_z`` (a quaternion) or ``prefix_x/_y/_z`` as a NumPy
        array, in that order: ``state.vector("q_B")``, ``state.vector("w_B")``."""
        for parts in (("w", "x", "y", "z"), ("x", "y", "z")):
            names = [f"{prefix}_{p}" for p in parts]
            if all(n in self for n in names):
                return np.array([self[n] for n in names])
        for n in (f"{prefix}_x", f"{prefix}_w"):
            self[n]  # KeyError naming the closest columns
        raise KeyError(f"{prefix!r} has no _x/_y/_z or _w/_x/_y/_z columns")


class Simulation:
    """A run advanced piece by piece, for a controller outside foldsim (docs/gnc.md).

        sim = scenario.start()
        while sim.t < 10.0:
            x = sim.state                       # every output column at sim.t, by name
            sim.set_torque("hub", my_law(x), frame="body")
            sim.advance(0.01)                   # integrates to exactly t + 0.01
        r = sim.result()                        # the rows so far, as Scenario.run gives them

    Commands hold until changed, like the scenario's own loads; their work is in ``W``.
    """

    def __init__(self, native):
        self._native = native

    @property
    def t(self) -> float:
        """The time reached, s."""
        return self._native.t

    @property
    def state(self) -> State:
        """Every output column at the time reached (docs/outputs.md), by name:
        ``sim.state["H_z"]``, the hub's quaternion ``q_B_w`` … ``q_B_z``, rates ``w_B_*``,
        MRPs ``sigma_B_*``; ``sim.state.vector("q_B")`` as a NumPy array."""
        return State(self._native.state())

    @property
    def hub_attitude(self) -> "np.ndarray":
        """The hub's attitude quaternion ``[w, x, y, z]`` (N to hub, scalar first)."""
        return self.state.vector("q_B")

    @property
    def hub_mrp(self) -> "np.ndarray":
        """The hub's MRPs ``σ_{B/N}``, the short way round."""
        return self.state.vector("sigma_B")

    @property
    def hub_rates(self) -> "np.ndarray":
        """The hub's angular velocity ``ω_{B/N}``, rad/s, hub components."""
        return self.state.vector("w_B")

    def advance(self, dt: float) -> None:
        """Integrates to exactly t + dt (s) with the scenario's adaptive integrator."""
        self._native.advance(float(dt))

    @property
    def inputs(self) -> list[str]:
        """Every input's name, as ``foldsim linearize``, the FMU and the C library name them:
        ``<body>_F_x`` … ``<body>_T_z`` (the body's own frame), ``<motor>_effort``,
        ``<actuator>_torque`` (docs/interop.md)."""
        return self._native.inputs

    def set_input(self, name: str, value: float) -> None:
        """Sets an input by name from now on (N, N·m; forces and torques in the body's own
        frame, at its centre of mass), as the FMU's and the C library's inputs are set. A
        body's three torque (or force) inputs make its whole torque: :meth:`set_torque` on
        the same body replaces it, and the next ``set_input`` replaces that."""
        self._native.set_input(name, float(value))

    def discard_rows(self) -> None:
        """Keeps no output rows from now on (``result()`` then has none): for a host that
        reads :attr:`state` at its own times over a long run, whose memory then stays flat."""
        self._native.discard_rows()

    def mass_properties(self) -> tuple[float, "np.ndarray", "np.ndarray"]:
        """The whole structure's mass properties at the time reached, in the hub's frame:
        total mass (kg), the barycenter from the hub's centre of mass (m, 3), and the inertia
        about the hub's centre of mass (kg·m², 3 × 3), reaction wheels' spin inertias
        included: what changes as the structure deploys (Basilisk's ``SCMassPropsMsg``)."""
        m, c, inertia = self._native.mass_properties()
        return m, np.array(c), np.array(inertia)

    def set_torque(self, body: str, torque, *, frame: str) -> None:
        """The torque (N·m) on `body` from now on, in `frame`: "body" (turning with it) or
        "inertial"; replaces the torque set before."""
        self._native.set_torque(body, _vector(torque, "torque"), frame)

    def set_force(self, body: str, force, *, frame: str, point=(0.0, 0.0, 0.0)) -> None:
        """The force (N) on `body` from now on, in `frame`, at `point` (m from its centre
        of mass, body frame); replaces the force set before."""
        self._native.set_force(body, _vector(force, "force"), frame, _vector(point, "point"))

    def set_motor(self, name: str, value: float | None) -> None:
        """A motor's effort (N·m about an angle, N along a displacement) from now on; None
        gives the motor back to its drive in the scenario."""
        self._native.set_motor(name, None if value is None else float(value))

    def set_wheel_torque(self, values) -> None:
        """The control's actuator torques (N·m, one per wheel or thruster, in the scenario's
        order) from now on, replacing the control law; None gives them back to the law.
        Each actuator's torque limit still applies."""
        self._native.set_wheel_torque(None if values is None else [float(v) for v in values])

    def result(self) -> Result:
        """The output rows so far and the report so far."""
        return Result(*self._native.result())

    def __repr__(self) -> str:
        return f"<foldsim.Simulation at t = {self.t} s>"


def _interactive() -> bool:
    """Whether a person is watching: standard error is a terminal, or this is a notebook."""
    try:
        if sys.stderr.isatty():
            return True
    except (AttributeError, ValueError):
        pass
    return "ipykernel" in sys.modules


class _Bar:
    """A tqdm bar driven by absolute positions (simulated time, runs done)."""

    def __init__(self, total: float, unit: str):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=total, unit=unit, leave=False, bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} {unit} [{elapsed}<{remaining}]")

    def update_to(self, position: float, **postfix: Any) -> None:
        if postfix:
            self.bar.set_postfix(**postfix, refresh=False)
        self.bar.update(position - self.bar.n)

    def close(self) -> None:
        self.bar.close()


class _Lines:
    """Off a terminal and out of a notebook (a script, a batch job): one line to standard
    error at most every 30 s (``FOLDSIM_PROGRESS_EVERY`` seconds), so a long run is seen to
    move in a log and a short one stays quiet."""

    def __init__(self, total: float, unit: str):
        import time

        self.total, self.unit, self.n = total, unit, 0.0
        self.clock = time.monotonic
        self.started = self.last = self.clock()
        try:
            self.every = float(os.environ.get("FOLDSIM_PROGRESS_EVERY", "30"))
        except ValueError:
            self.every = 30.0
    def update_to(self, position: float, **_postfix: Any) -> None:
        self.n = position
        now = self.clock()
        if now - self.last >= self.every:
            self.last = now
            elapsed = now - self.started
            left = elapsed * (self.total - position) / position if position > 0 else float("nan")
            sys.stderr.write(
                f"foldsim: {position:.4g} of {self.total:.4g} {self.unit} ({100 * position / self.total:.0f} %), {elapsed:.0f} s so far, about {left:.0f} s left\n"
            )
            sys.stderr.flush()

    def close(self) -> None:
        pass


def _progress_bar(total: float, unit: str, progress: bool | None) -> _Bar | _Lines | None:
    """A progress bar when asked for (progress=True) or, by default, when someone watches (a
    terminal, a notebook); by default elsewhere, a line every 30 s; nothing for progress=False."""
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"progress must be True, False or None, not {type(progress).__name__}")
    if progress is None:
        return _Bar(total, unit) if _interactive() else _Lines(total, unit)
    return _Bar(total, unit) if progress else None


def load(path: str | Path) -> Scenario:
    """Reads a scenario file (ValueError naming the file, line and key when it is bad)."""
    return Scenario(_Scenario.load(path_arg(path, "path")))


def from_toml(text: str, name: str = "scenario", base: str | Path | None = None) -> Scenario:
    """Reads a scenario from TOML text; table files are read relative to `base`."""
    if not isinstance(text, str):
        raise TypeError(f"text must be a str of TOML, not {type(text).__name__}")
    return Scenario(_Scenario.from_toml(text, name, None if base is None else str(base)))


def from_dict(d: dict, name: str = "scenario dict", base: str | Path | None = None) -> Scenario:
    """Builds a scenario from a dict with a scenario file's structure: ``{"run": {...},
    "body": [{...}, ...], "hinge": [{...}, ...], "initial": {...}}``. Errors (ValueError) name
    the key path."""
    if not isinstance(d, dict):
        raise TypeError(f"from_dict() takes a dict, not {type(d).__name__}")
    return Scenario(_Scenario.from_dict(d, name, None if base is None else str(base)))
