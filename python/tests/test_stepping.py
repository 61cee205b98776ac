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


def test_non_finite_commands_are_refused_at_the_call():
    """NaN or inf in a command is refused where it is given, not blamed on the hinges at the
    next advance (issue 33, item 16)."""
    sim = three_panel().start()
    bad = [float("nan"), float("inf"), -float("inf")]
    for x in bad:
        with pytest.raises(ValueError, match="finite"):
            sim.set_torque("hub", [0.0, x, 0.0], frame="body")
        with pytest.raises(ValueError, match="finite"):
            sim.set_force("p1", [x, 0.0, 0.0], frame="inertial")
        with pytest.raises(ValueError, match="finite"):
            sim.set_force("p1", [1.0, 0.0, 0.0], frame="inertial", point=[0.0, x, 0.0])
    sim.advance(0.1)  # the refused commands left nothing behind
    hold = foldsim.load(ROOT / "examples" / "zfold-attitude-hold.toml").start()
    with pytest.raises(ValueError, match="finite"):
        hold.set_wheel_torque([0.0, float("nan"), 0.0])


def test_state_names_the_closest_columns_and_gives_vectors():
    sim = three_panel().start()
    with pytest.raises(KeyError, match="q_B_w"):
        sim.state["q_B_W"]
    s = sim.state
    assert s.vector("q_B").shape == (4,) and s.vector("w_B").shape == (3,)
    np.testing.assert_array_equal(sim.hub_attitude, [s[f"q_B_{a}"] for a in "wxyz"])
    np.testing.assert_array_equal(sim.hub_rates, [s[f"w_B_{a}"] for a in "xyz"])
    # The hub's MRPs in every scenario (no [control] here), as the short way round of q_B.
    q = sim.hub_attitude
    q = q if q[0] >= 0 else -q
    np.testing.assert_allclose(sim.hub_mrp, q[1:] / (1.0 + q[0]), rtol=0, atol=1e-15)


def test_a_loop_steps_a_sampled_controller_to_the_end():
    """advance(0.1) lands within round-off of the 10 Hz control samples; it stopped at
    t = 1.4 ("step size fell to 2.2e-16 s"). Now every dt reaches the end (item 11)."""
    s = foldsim.load(ROOT / "examples" / "zfold-attitude-hold.toml").with_values({"run.duration": 2.0})
    for dt in (0.1, 0.04):
        sim = s.start()
        n = round(2.0 / dt)
        for _ in range(n):
            sim.advance(dt)
        assert abs(sim.t - 2.0) < 1e-9


def test_mass_properties_from_the_bodies_poses():
    """`Simulation.mass_properties()` (what foldsim.basilisk publishes as SCMassPropsMsg)
    against the same sums made here from the output columns: each body's mass and inertia
    from the scenario file, its pose from `<body>_R_*` and `<body>_q_*` (parallel-axis
    theorem), the wheels' spin inertias in the hub's; after 1 s of the three-panel spin, to
    1e-12 relative (the same arithmetic in another order)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("peer", ROOT / "bench" / "peers" / "basilisk_hinged.py")
    peer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(peer)
    sim = foldsim.from_toml(peer.foldsim_scenario(5.0, 1e-10), "hinged.toml").start()
    sim.advance(1.0)
    s = sim.state

    def dcm(body):  # [N body] from its quaternion (scalar first)
        w, x, y, z = (s[f"{body}_q_{a}"] for a in "wxyz")
        return np.array([
            [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
        ])

    bodies = [("hub", peer.HUB_MASS, np.diag(peer.HUB_I)), ("p1", peer.PANEL_MASS, np.diag(peer.PANEL_I)),
              ("p2", peer.PANEL_MASS, np.diag(peer.PANEL_I))]
    r_hub, c_hub = np.array([s[f"hub_R_{a}"] for a in "xyz"]), dcm("hub")
    mass, first, inertia = 0.0, np.zeros(3), np.zeros((3, 3))
    for name, m, i_own in bodies:
        r = c_hub.T @ (np.array([s[f"{name}_R_{a}"] for a in "xyz"]) - r_hub)
        c = c_hub.T @ dcm(name)
        inertia += c @ i_own @ c.T + m * (r @ r * np.eye(3) - np.outer(r, r))
        mass += m
        first += m * r
    m, com, i = sim.mass_properties()
    assert abs(m - mass) <= 1e-12 * mass
    assert np.abs(com - first / mass).max() <= 1e-12 * np.abs(first / mass).max()
    assert np.abs(i - inertia).max() <= 1e-12 * np.abs(inertia).max()
    assert np.abs(i - np.diag(peer.HUB_I)).max() > 100.0  # the panels count: not the hub alone


def test_inputs_by_name_are_the_commands_they_name():
    """`set_input` (the FMU's and the C library's names) commands what `set_torque`,
    `set_force` and `set_wheel_torque` command: the same run, bit for bit, over 1 s; an
    unknown name or a value that is not a number is refused in words."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("peer", ROOT / "bench" / "peers" / "basilisk_hinged.py")
    peer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(peer)
    scenario = foldsim.from_toml(peer.foldsim_scenario(5.0, 1e-10), "hinged.toml")
    a, b = scenario.start(), scenario.start()
    assert a.inputs[:6] == ["hub_F_x", "hub_F_y", "hub_F_z", "hub_T_x", "hub_T_y", "hub_T_z"]
    assert a.inputs[-3:] == ["rw_x_torque", "rw_y_torque", "rw_z_torque"]
    a.set_input("hub_T_y", 0.3)
    a.set_input("hub_T_z", -0.2)
    a.set_input("p1_F_x", 1.5)
    a.set_input("rw_y_torque", 0.1)
    b.set_torque("hub", [0.0, 0.3, -0.2], frame="body")
    b.set_force("p1", [1.5, 0.0, 0.0], frame="body")
    b.set_wheel_torque([0.0, 0.1, 0.0])
    for _ in range(10):
        a.advance(0.1)
        b.advance(0.1)
    sa, sb = a.state, b.state
    assert all(sa[k] == sb[k] for k in sa), [k for k in sa if sa[k] != sb[k]][:5]
    assert sa["rw_y_torque"] == 0.1
    with pytest.raises(ValueError, match="no input"):
        a.set_input("hub_T_w", 1.0)
    with pytest.raises(ValueError, match="finite"):
        a.set_input("hub_T_z", float("nan"))
