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
    return {round(float(t) * 1e-9, 6): p.mrp_to_quat(s) for t, s in zip(log.times(), log.sigma_BN) for p in [PEER]}


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
