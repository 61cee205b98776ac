"""foldsim.basilisk: Basilisk's flight software flying a foldsim structure through the
FoldsimSpacecraft module (docs/interop.md), on the case of bench/peers/basilisk_hinged.py:
a hub with two hinged panels and three reaction wheels under Basilisk's inertial3D →
attTrackingError → mrpFeedback → rwMotorTorque at 10 Hz.

Needs Basilisk (``pip install "./python[basilisk]"``; CI installs it).
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

import foldsim

pytest.importorskip("Basilisk")

from Basilisk.architecture import messaging  # noqa: E402
from Basilisk.fswAlgorithms import attTrackingError, inertial3D, mrpFeedback, rwMotorTorque  # noqa: E402
from Basilisk.utilities import SimulationBaseClass, macros, simIncludeRW  # noqa: E402

from foldsim.basilisk import FoldsimSpacecraft  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def peer():
    """bench/peers/basilisk_hinged.py as a module (its case and conversions)."""
    spec = importlib.util.spec_from_file_location("basilisk_hinged", ROOT / "bench" / "peers" / "basilisk_hinged.py")
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


def fly(scenario, hub_inertia, wheels, gains, period, duration):
    """Basilisk's flight software (as the peer script sets it up) flying `scenario` through
    FoldsimSpacecraft; the hub's quaternion at every flight-software sample, by time."""
    k_gain, p_gain = gains
    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("dyn", macros.sec2nano(period)), 200)  # the structure first
    proc.addTask(sim.CreateNewTask("fsw", macros.sec2nano(period)), 100)
    sc = FoldsimSpacecraft(scenario)
    sim.AddModelToTask("dyn", sc)

    factory = simIncludeRW.rwFactory()
    for axis, js, umax in wheels:
        factory.create("custom", axis, Js=js, u_max=umax, Omega=0.0, Omega_max=1e5, RWModel=messaging.BalancedWheels)
    ref = inertial3D.inertial3D()
    ref.sigma_R0N = [0.0, 0.0, 0.0]
    err = attTrackingError.attTrackingError()
    err.attNavInMsg.subscribeTo(sc.attOutMsg)
    err.attRefInMsg.subscribeTo(ref.attRefOutMsg)
    ctrl = mrpFeedback.mrpFeedback()
    ctrl.K, ctrl.P, ctrl.Ki = k_gain, p_gain, -1.0
    config = messaging.VehicleConfigMsgPayload()
    config.ISCPntB_B = np.diag(hub_inertia).flatten().tolist()
    config_msg = messaging.VehicleConfigMsg().write(config)
    ctrl.guidInMsg.subscribeTo(err.attGuidOutMsg)
    ctrl.vehConfigInMsg.subscribeTo(config_msg)
    params = factory.getConfigMessage()
    motor = rwMotorTorque.rwMotorTorque()
    motor.controlAxes_B = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    motor.vehControlInMsg.subscribeTo(ctrl.cmdTorqueOutMsg)
    motor.rwParamsInMsg.subscribeTo(params)
    sc.rwMotorTorqueInMsg.subscribeTo(motor.rwMotorTorqueOutMsg)
    for i, m in enumerate((ref, err, ctrl, motor)):
        sim.AddModelToTask("fsw", m, 10 - i)
    log = sc.scStateOutMsg.recorder(macros.sec2nano(period))
    sim.AddModelToTask("dyn", log)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(duration))
    sim.ExecuteSimulation()
    return {round(float(t) * 1e-9, 6): PEER.mrp_to_quat(s) for t, s in zip(log.times(), log.sigma_BN)}


PEER = peer()


def test_basilisk_flight_software_flies_foldsim_as_foldsim_control_does():
    """Basilisk's mrpFeedback and rwMotorTorque driving the structure through the module give
    the hub attitude foldsim's own `[control] law = "mrp_pd"` gives in the peer script's
    foldsim run (the same law, gains, sampling and limits): the largest angle between the two
    attitudes over 60 s at the 10-Hz samples ≤ 1e-10 rad. The two runs integrate the same
    equations at rtol 1e-12 with the same commands; they differ by the pieces' restarts
    (integration error) and the flight software's arithmetic, both far below 1e-10."""
    p = PEER
    duration = 60.0
    text = p.foldsim_scenario(duration, 1e-12)
    ours = {}
    own = foldsim.from_toml(text, "basilisk_hinged.toml").run()
    for t, *q in zip(own["t"], own["q_B_w"], own["q_B_x"], own["q_B_y"], own["q_B_z"]):
        ours[round(float(t), 6)] = q
    wheels = [(axis, p.WHEEL_JS, p.WHEEL_UMAX) for axis in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])]
    flown = fly(foldsim.from_toml(text, "basilisk_hinged.toml"), p.HUB_I, wheels, (p.K_GAIN, p.P_GAIN), p.PERIOD, duration)
    common = sorted(set(ours) & set(flown))
    assert len(common) == int(duration / p.PERIOD) + 1
    worst = max(p.angle_between(ours[t], flown[t]) for t in common)
    moved = p.angle_between(ours[common[0]], ours[common[-1]])
    print(f"Basilisk FSW through foldsim.basilisk against foldsim's own control: {worst:.2e} rad (the hub turned {moved:.3f} rad)")
    assert moved > 0.1  # the controller did turn the hub: the comparison is not of two idle runs
    assert worst <= 1e-10


def test_fuzz_the_module_messages_and_times():
    """FoldsimSpacecraft's input surface: wheel torques and hub torques of any value (NaN,
    ±inf, huge, short and long arrays), Basilisk times in any order (backwards, repeated,
    past the run's horizon), resets. Each update publishes or raises ValueError (a command
    that is not finite, in words) or RuntimeError (a run that cannot go on, or a time past
    the horizon, in words); never another exception, never a crash; every published attitude
    finite."""
    import os
    import random

    from Basilisk.architecture import messaging

    n = int(os.environ.get("FOLDSIM_FUZZ_INPUTS", "200"))
    seed = int(os.environ.get("FOLDSIM_FUZZ_SEED", "1"))
    rng = random.Random(seed)
    text = PEER.foldsim_scenario(5.0, 1e-8)
    values = [0.0, 0.1, -0.2, 1e-300, 1e300, math.nan, math.inf, -math.inf, 5.0]
    counts = {"published": 0, "refused": 0, "run ended": 0}
    sc = None
    wheel_msg, torque_msg = messaging.ArrayMotorTorqueMsg(), messaging.CmdTorqueBodyMsg()
    nanos = 0
    for i in range(n):
        if sc is None or rng.random() < 0.05:
            sc = FoldsimSpacecraft(foldsim.from_toml(text, "fuzz.toml"))
            sc.rwMotorTorqueInMsg.subscribeTo(wheel_msg)
            sc.cmdTorqueInMsg.subscribeTo(torque_msg)
            nanos = 0
            sc.Reset(nanos)
        w = messaging.ArrayMotorTorqueMsgPayload()
        w.motorTorque = [rng.choice(values) for _ in range(rng.randrange(0, 5))]
        wheel_msg.write(w)
        c = messaging.CmdTorqueBodyMsgPayload()
        c.torqueRequestBody = [rng.choice(values) for _ in range(3)]
        torque_msg.write(c)
        nanos = max(0, nanos + rng.choice([0, 1, 10_000_000, 100_000_000, 1_000_000_000, -50_000_000, 3_000_000_000]))
        try:
            sc.UpdateState(nanos)
            sigma = list(sc.scStateOutMsg.read().sigma_BN)
            assert all(math.isfinite(x) for x in sigma), f"seed {seed} input {i}: sigma {sigma}"
            counts["published"] += 1
        except ValueError as e:
            assert str(e), f"seed {seed} input {i}: an empty ValueError"
            counts["refused"] += 1
        except RuntimeError as e:
            assert str(e), f"seed {seed} input {i}: an empty RuntimeError"
            counts["run ended"] += 1
            sc = None
    print(f"fuzz foldsim.basilisk (seed {seed}): {n} updates: {counts}")
    assert counts["published"] > 0 and counts["refused"] > 0


def test_a_commanded_hub_torque_adds_its_impulse():
    """cmdTorqueInMsg: 2 N·m about the hub's z (its spin axis, which stays along N's z) for
    5 s of the radial spin, written once by a Basilisk message, adds 10 N·m·s to H_z (to
    1e-8 of |H|), and the module's scMassOutMsg grows the inertia about z as the panels open."""
    from Basilisk.architecture import messaging
    from Basilisk.utilities import SimulationBaseClass, macros

    scenario = foldsim.load(ROOT / "examples" / "radial-spin.toml")
    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("dyn", macros.sec2nano(0.1)), 200)
    sc = FoldsimSpacecraft(scenario, keep_rows=True)
    sim.AddModelToTask("dyn", sc)
    payload = messaging.CmdTorqueBodyMsgPayload()
    payload.torqueRequestBody = [0.0, 0.0, 2.0]
    torque = messaging.CmdTorqueBodyMsg().write(payload)
    sc.cmdTorqueInMsg.subscribeTo(torque)
    props = sc.scMassOutMsg.recorder()
    sim.AddModelToTask("dyn", props)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(5.0))
    sim.ExecuteSimulation()
    r = sc.simulation.result()
    h = np.sqrt(r["H_x"] ** 2 + r["H_y"] ** 2 + r["H_z"] ** 2).max()
    gained = r["H_z"][-1] - r["H_z"][0]
    assert abs(sc.simulation.t - 5.0) < 1e-12
    assert abs(gained - 10.0) <= 1e-8 * h, gained
    izz = np.array(props.ISC_PntB_B)[:, 2, 2]
    assert izz[-1] > 1.05 * izz[0]  # the panels opening outward (62 -> 69 kg·m² by 5 s)


def test_an_error_in_the_module_stops_basilisk_with_its_words(capsys):
    """A command foldsim refuses (a torque that is not finite) stops Basilisk's
    ExecuteSimulation with a RuntimeError, and the traceback Basilisk prints above it carries
    the module's own words; the run does not go on with stale messages."""
    from Basilisk.architecture import messaging
    from Basilisk.utilities import SimulationBaseClass, macros

    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("dyn", macros.sec2nano(0.1)), 200)
    sc = FoldsimSpacecraft(foldsim.load(ROOT / "examples" / "radial-spin.toml"))
    sim.AddModelToTask("dyn", sc)
    payload = messaging.CmdTorqueBodyMsgPayload()
    payload.torqueRequestBody = [0.0, 0.0, math.nan]
    torque = messaging.CmdTorqueBodyMsg().write(payload)
    sc.cmdTorqueInMsg.subscribeTo(torque)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(1.0))
    with pytest.raises(RuntimeError):
        sim.ExecuteSimulation()
    assert "cmdTorqueInMsg: the torque must be finite numbers" in capsys.readouterr().err
    assert sc.simulation.t == 0.0
