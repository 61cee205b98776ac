"""Fuzzing the Python values: random nested values (dicts, lists, tuples, NumPy arrays and
scalars, bytes, None, sets, non-finite and huge numbers, odd strings, values that contain
themselves) given to from_dict, with_values, get, sweep, fit and linearize's keywords. Each must give a scenario or raise
ValueError, TypeError or KeyError; never crash the interpreter, never another exception.

A small budget as a test; longer: FOLDSIM_FUZZ_INPUTS=5000 FOLDSIM_FUZZ_SEED=7 pytest python/tests/test_fuzz.py
"""

import math
import os
import random
from pathlib import Path

import numpy as np

import foldsim

ROOT = Path(__file__).resolve().parents[2]
BASE = foldsim.load(ROOT / "examples" / "paper-1panel.toml").with_values({"run.duration": 0.1})
BASE_DICT = {
    "run": {"duration": 0.1, "output_step": 0.05, "integrator": "dop853", "rtol": 1e-8, "atol": 1e-8},
    "body": [{"name": "hub", "mass": 100.0, "inertia": [100.0, 100.0, 100.0]}, {"name": "panel", "mass": 10.0, "inertia": [1.0, 1.0, 1.0]}],
    "hinge": [{"name": "h1", "parent": "hub", "child": "panel", "a0": {"position": [0.75, 0.433, 0.0]}, "a": {"child_com": [1.0, 1.0, 0.0]},
               "law": {"type": "euler-potential", "k_f": 100.0, "k_theta": 10.0}}],
}
PATHS = ["hinge.h1.law.k_theta", "hinge.*.law.c_f", "body.panel.mass", "body.1.inertia", "run.duration", "run.integrator",
         "initial.hub.omega", "title", "hinge.h9.x", "", "a..b", "body.hub.inertia.7", "sweep.runs", "run.nothing"]
ALLOWED = (ValueError, TypeError, KeyError)


def leaf(rng: random.Random):
    return rng.choice([
        0, 1, -1, 2**70, -(2**70), 0.5, -0.0, math.nan, math.inf, -math.inf, 1e300, 1e-300, True, None, "x", "", "h1",
        "dop853", "\u0000", "é" * 3, b"bytes", np.float64(2.0), np.int64(3), np.float32(np.nan), np.array([1.0, 2.0, 3.0]),
        np.zeros((2, 2)), np.array([]), np.array(["a"]), {1, 2}, complex(1, 2), object(),
    ])


def value(rng: random.Random, depth: int = 0):
    r = rng.random()
    if depth > 3 or r < 0.5:
        return leaf(rng)
    if r < 0.75:
        return [value(rng, depth + 1) for _ in range(rng.randrange(4))]
    if r < 0.85:
        return tuple(value(rng, depth + 1) for _ in range(rng.randrange(3)))
    d = {rng.choice(["mass", "name", "law", "k_f", "duration", 3, "inertia", "run", "x"]): value(rng, depth + 1) for _ in range(rng.randrange(4))}
    if rng.random() < 0.1:
        d["self"] = d
    return d


def mutated_dict(rng: random.Random) -> dict:
    import copy

    d = copy.deepcopy(BASE_DICT)
    for _ in range(1 + rng.randrange(3)):
        # Every dict in the tree (a mutation may already have replaced some).
        dicts, stack = [], [d]
        while stack:
            x = stack.pop()
            if isinstance(x, dict) and all(x is not y for y in dicts):
                dicts.append(x)
                stack.extend(x.values())
            elif isinstance(x, list):
                stack.extend(x)
        target = rng.choice(dicts)
        key = rng.choice(list(target.keys()) + ["extra", "inertia", "mass"])
        target[key] = value(rng)
    return d


def test_python_values_give_a_scenario_or_a_named_exception():
    n = int(os.environ.get("FOLDSIM_FUZZ_INPUTS", "300"))
    seed = int(os.environ.get("FOLDSIM_FUZZ_SEED", "1"))
    rng = random.Random(seed)
    counts = {"built": 0, "refused": 0}
    for i in range(n):
        kind = rng.randrange(6)
        try:
            if kind == 5:
                # A fit: data, free values and noise levels of any Python values.
                t = [0.02, 0.05, 0.08] if rng.random() < 0.6 else value(rng)
                data = {"t": t, rng.choice(["h1_yaw", "h1_pitch", "E", "nope", 3]): value(rng) if rng.random() < 0.4 else [0.1, leaf(rng), None]}
                if rng.random() < 0.2:
                    data = value(rng)
                free = rng.choice([["hinge.h1.law.k_theta=1:100"], {"hinge.h1.law.c_theta": (0, 5)}, value(rng), {rng.choice(PATHS): value(rng)}])
                sigma = rng.choice([None, {"h1_yaw": leaf(rng)}, value(rng)])
                foldsim.fit(BASE, data, free=free, sigma=sigma, max_iterations=rng.choice([2, 0, leaf(rng)]))
            elif kind == 4:
                # The linear model, reduced or not, with any values for its keywords.
                BASE.linearize(deployed=rng.random() < 0.8, modes=rng.choice([None, 1, 3, 6, leaf(rng)]), hub_held=rng.choice([False, True, leaf(rng)]))
            elif kind == 0:
                foldsim.from_dict(mutated_dict(rng))
            elif kind == 1:
                BASE.with_values({rng.choice(PATHS): value(rng) for _ in range(1 + rng.randrange(2))})
            elif kind == 2:
                BASE.get(rng.choice(PATHS + [value(rng)]))
            else:
                params = {rng.choice(PATHS): value(rng) if rng.random() < 0.5 else {"distribution": "uniform", "low": leaf(rng), "high": leaf(rng)}}
                foldsim.sweep(BASE, params, runs=2, seed=1, progress=False, workers=1)
            counts["built"] += 1
        except ALLOWED:
            counts["refused"] += 1
        except RuntimeError as e:
            # Every run of a sweep failed: a refusal in words, with the first run's error.
            assert (kind == 3 and "every run of the sweep failed" in str(e)) or (kind == 5 and "the run with" in str(e)), f"seed {seed} input {i}: {e!r}"
            counts["refused"] += 1
        except Exception as e:  # noqa: BLE001: the point is to catch any other kind
            raise AssertionError(f"seed {seed} input {i} (kind {kind}): {type(e).__name__}: {e}") from e
    print(f"fuzz Python values (seed {seed}): {n} inputs: {counts}")
    assert counts["built"] > 0 and counts["refused"] > 0


HOLD = foldsim.load(ROOT / "examples" / "zfold-attitude-hold.toml").with_values({"run.duration": 1.0})
MOTORS = foldsim.load(ROOT / "examples" / "zfold-motor-deploy.toml").with_values({"run.duration": 1.0})


def test_python_stepping_gives_a_state_or_a_named_exception():
    """Stepping from Python (issue 33): advance with any dt, commands with any values (NaN,
    inf, huge, wrong lengths and names), inputs by name, state lookups by any key, mass
    properties, rows discarded, on a run with wheels and one with motors. Each call gives its result or raises ValueError, TypeError, KeyError or
    RuntimeError (a run that cannot go on, in words); never another exception, never a
    crash."""
    n = int(os.environ.get("FOLDSIM_FUZZ_INPUTS", "300"))
    seed = int(os.environ.get("FOLDSIM_FUZZ_SEED", "1"))
    rng = random.Random(seed)
    counts = {"done": 0, "refused": 0, "run ended": 0}
    sims = []
    for i in range(n):
        if not sims or rng.random() < 0.05:
            sims = [HOLD.start(), MOTORS.start()]
        sim = rng.choice(sims)
        kind = rng.randrange(9)
        num = lambda: rng.choice([0.0, 1.0, -1.0, 0.1, 1e-300, 1e300, math.nan, math.inf, -math.inf, 3, "x", None])  # noqa: E731
        try:
            if kind == 0:
                sim.advance(rng.choice([0.01, 0.1, 0.3 / 7.0, 1e-12, 0.0, -0.1, math.nan, math.inf, 2.0, 1e-300]))
            elif kind == 1:
                sim.set_torque(rng.choice(["hub", "p1", "nobody", ""]), [num(), num(), num()][: rng.randrange(5)], frame=rng.choice(["body", "inertial", "x"]))
            elif kind == 2:
                sim.set_force(rng.choice(["hub", "p2"]), [num(), 0.0, 0.0], frame="inertial", point=[0.0, num(), 0.0])
            elif kind == 3:
                sim.set_motor(rng.choice(["root", "mid", "x"]), num())
            elif kind == 4:
                sim.set_wheel_torque(rng.choice([None, [num(), num(), num()], [0.1], []]))
            elif kind == 5:
                s = sim.state
                key = rng.choice(["q_B_w", "q_B_W", "w_B_z", "", "sigma_B_x", "nothing"])
                s[key]
                s.vector(rng.choice(["q_B", "w_B", "sigma_B", "zz"]))
            elif kind == 6:
                m, c, inertia = sim.mass_properties()
                assert m > 0.0 and all(map(math.isfinite, c)) and all(math.isfinite(x) for row in inertia for x in row)
            elif kind == 7 and rng.random() < 0.2:
                sim.discard_rows()
            elif kind == 7:
                sim.set_input(rng.choice(sim.inputs + ["", "hub_T_w", "nothing"]), num())
            else:
                sim.result()
            counts["done"] += 1
        except (ValueError, TypeError, KeyError):
            counts["refused"] += 1
        except RuntimeError as e:
            # advance past the run's end, or a run the commands drove where it cannot go on.
            assert str(e), f"seed {seed} input {i}: an empty RuntimeError"
            counts["run ended"] += 1
            sims.remove(sim)
        except Exception as e:  # noqa: BLE001: the point is to catch any other kind
            raise AssertionError(f"seed {seed} input {i} (kind {kind}): {type(e).__name__}: {e}") from e
    print(f"fuzz Python stepping (seed {seed}): {n} calls: {counts}")
    assert counts["done"] > 0 and counts["refused"] > 0


PANEL_HUB = foldsim.load(ROOT / "examples" / "contact-panel-hub.toml").with_values({"run.duration": 1.0, "run.output_step": 0.05})


def test_python_overlaps_give_pairs_or_a_named_exception():
    """`Scenario.overlaps` on a run's columns mutated (values NaN, inf, huge; columns dropped,
    renamed or cut short; rows out of order) and on odd arguments: each call gives its list of
    pairs or raises ValueError or TypeError naming what is wrong; never another exception,
    never a crash."""
    n = int(os.environ.get("FOLDSIM_FUZZ_INPUTS", "300"))
    seed = int(os.environ.get("FOLDSIM_FUZZ_SEED", "1"))
    rng = random.Random(seed)
    base = PANEL_HUB.run()
    counts = {"measured": 0, "refused": 0}
    for i in range(n):
        names = list(base.columns)
        cols = [np.array(base[c], dtype=float) for c in names]
        for _ in range(1 + rng.randrange(3)):
            k = rng.randrange(len(names))
            kind = rng.randrange(6)
            if kind == 0:
                cols[k] = cols[k].copy()
                cols[k][rng.randrange(len(cols[k]))] = rng.choice([math.nan, math.inf, -math.inf, 1e300, -1e300, 0.0, 1e-320, 7.0])
            elif kind == 1:
                del names[k], cols[k]
            elif kind == 2:
                names[k] = rng.choice(["zz", "t", names[0], ""])
            elif kind == 3:
                cols[k] = cols[k][: rng.randrange(len(cols[k]) + 1)]
            elif kind == 4:
                cols = [c[::-1].copy() if rng.random() < 0.5 else c for c in cols]
            else:
                with np.errstate(all="ignore"):  # inf × 0 is NaN, on purpose
                    cols[k] = cols[k] * rng.choice([0.0, -1.0, 1e6, 0.5])
        try:
            r = foldsim.Result(names, cols, {})
            found = PANEL_HUB.overlaps(r, sharp=rng.random() < 0.5)
            assert all(p["depth"] > 0.0 and math.isfinite(p["t"]) for p in found)
            counts["measured"] += 1
        except (ValueError, TypeError, KeyError) as e:
            assert str(e), f"seed {seed} input {i}: an empty {type(e).__name__}"
            counts["refused"] += 1
        except Exception as e:  # noqa: BLE001: the point is to catch any other kind
            raise AssertionError(f"seed {seed} input {i}: {type(e).__name__}: {e}") from e
    for odd in [None, 3, "no-such.csv", b"x"]:
        try:
            PANEL_HUB.overlaps(odd)
            raise AssertionError(f"{odd!r} was measured")
        except (ValueError, TypeError):
            pass
    try:
        PANEL_HUB.overlaps(base, sharp="yes")
        raise AssertionError("sharp='yes' was taken")
    except TypeError:
        pass
    print(f"fuzz Python overlaps (seed {seed}): {n} inputs: {counts}")
    assert counts["measured"] > 0 and counts["refused"] > 0
