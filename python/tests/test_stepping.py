"""A run advanced piece by piece from Python, with a controller outside foldsim
(docs/gnc.md)."""

from pathlib import Path

import numpy as np
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]


def three_panel(extra: str = "", tol: float = 1e-11) -> foldsim.Scenario:
    """The paper's three-panel case (law 2), its hub spinning, 2 s, rows every 10 ms."""
    text = (ROOT / "examples" / "paper-3panel-euler.toml").read_text()
    text = (
        text.replace("duration = 20.0", "duration = 2.0")
        .replace("output_step = 0.05", "output_step = 0.01")
        .replace("rtol = 1e-12", f"rtol = {tol:e}")
        .replace("atol = 1e-12", f"atol = {tol:e}")
    )
    return foldsim.from_toml(text + "\n[initial.hub]\nomega = [0.05, -0.1, 0.3]\n" + extra, "stepped.toml")


def mrp_pd(state: dict, k: float, p: float) -> list[float]:
    """L = −K σ − P ω (Schaub & Junkins §8.4) from the hub's quaternion and rates."""
    q = np.array([state[f"q_B_{a}"] for a in "wxyz"])
    if q[0] < 0.0:
        q = -q  # the short way round
    sigma = q[1:] / (1.0 + q[0])
    omega = np.array([state[f"w_B_{a}"] for a in "xyz"])
    return list(-k * sigma - p * omega)


def test_python_controller_equals_the_built_in_one():
    """The same MRP PD law written in Python, held for 10 ms, gives the built-in law's
    trajectory sampled at 10 ms: the runs differ by integration error (DOP853 at 1e-11;
    bound 1e-8 rad on the hub's quaternion)."""
    k, p = 30.0, 80.0
    built_in = three_panel(f'[control]\nlaw = "mrp_pd"\nk = {k}\np = {p}\ntarget = [1.0, 0.0, 0.0, 0.0]\nperiod = 0.01\n')
    reference = built_in.run()
    sim = three_panel().start()
    for _ in range(200):
        sim.set_torque("hub", mrp_pd(sim.state, k, p), frame="body")
        sim.advance(0.01)
    r = sim.result()
    assert len(r.t) == len(reference.t)
    diff = max(np.max(np.abs(r[f"q_B_{a}"] - reference[f"q_B_{a}"])) for a in "wxyz")
    assert diff < 1e-8, diff
    # The law did work on the hub (W), so the comparison is not of two idle runs.
    assert abs(r["W"][-1]) > 1e-3


def test_thousand_pieces_agree_with_one_call():
    """advance() in 1,000 pieces gives one call's rows to the integrator's tolerance (bound
    1e-9 at rtol 1e-12), and `state` is the row at the time reached."""
    s = three_panel(tol=1e-12)
    whole = s.run()
    sim = s.start()
    for _ in range(1000):
        sim.advance(0.002)
    r = sim.result()
    for name in ["q_B_x", "h1_yaw", "h31_roll", "H_z"]:
        assert np.max(np.abs(r[name] - whole[name])) < 1e-9, name
    assert sim.t == pytest.approx(2.0, abs=1e-12)
    assert sim.state["h1_yaw"] == pytest.approx(r["h1_yaw"][-1], abs=1e-12)
    assert r.report["steps_accepted"] >= 1000


def test_commands_are_checked():
    sim = three_panel().start()
    with pytest.raises(ValueError, match="frame"):
        sim.set_torque("hub", [0, 0, 1], frame="hub")
    with pytest.raises(ValueError, match="no body"):
        sim.set_torque("hbu", [0, 0, 1], frame="body")
    with pytest.raises(ValueError, match="no motor"):
        sim.set_motor("m", 1.0)
    with pytest.raises(ValueError, match="control"):
        sim.set_wheel_torque([0.1])
    with pytest.raises(RuntimeError, match="run.duration"):
        sim.advance(5.0)
