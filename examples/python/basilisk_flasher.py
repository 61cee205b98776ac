# %% [markdown]
# # A flasher deploying under Basilisk's flight software
#
# The small flasher of `examples/flasher-small.toml` (6 gores, 3 rings, 66 panels on 96
# hinges) deploys from its hub while Basilisk's standard attitude flight software holds the
# hub: inertial3D (hold the start frame) → attTrackingError → mrpFeedback → rwMotorTorque, at
# 10 Hz, commanding three reaction wheels on the hub. foldsim is the spacecraft: its
# `foldsim.basilisk.FoldsimSpacecraft` module integrates the flexible structure between
# Basilisk's samples and publishes the hub's state as Basilisk's own spacecraft would
# (docs/interop.md). The hub starts 0.1 rad off its target and tumbling at 0.6 rev/min; the
# unwrapping panels turn it a further 0.7 rad before the wheels bring it back.
#
# mrpFeedback reads the vehicle's inertia from the module's `vehConfigOutMsg`, which follows
# the structure as it opens (the inertia about the hub's centre of mass grows from 80 to
# 290 kg·m² about z here), and the wheels' speeds from `rwSpeedOutMsg` for its gyroscopic
# term. Run it after `pip install "./python[basilisk,examples]"`, naming the figure:
#
#     python examples/python/basilisk_flasher.py basilisk_flasher.png
#
# About 7 s (15 s simulated; a 2-core AMD EPYC at load ~1). Cells are marked `# %%` for editors that run them one by one.

# %%
import math
import sys
from pathlib import Path

import numpy as np

import foldsim
from foldsim.basilisk import FoldsimSpacecraft

if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
    sys.exit("usage: python basilisk_flasher.py FIGURE.png  (where to write the figure)")
out = sys.argv[1]
foldsim._foldsim.check_outputs([], [("the figure", out)])

from Basilisk.architecture import messaging  # noqa: E402
from Basilisk.fswAlgorithms import attTrackingError, inertial3D, mrpFeedback, rwMotorTorque  # noqa: E402
from Basilisk.utilities import SimulationBaseClass, macros, simIncludeRW  # noqa: E402

# %% The structure: the flasher, its hub turned and tumbling, three wheels on the hub with no
# law of foldsim's own (Basilisk's flight software commands them).
ROOT = Path(__file__).resolve().parents[2]
base = ROOT / "examples" / "flasher-small.toml"
AXES = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
JS, UMAX = 0.5, 20.0  # kg·m², N·m
text = base.read_text().replace("roll = 0.0\nomega_rpm = [0.0, 0.0, 0.0]", "roll = 0.1\nomega_rpm = [0.3, -0.2, 0.5]", 1)
assert "roll = 0.1" in text, "the example's hub initial state moved: update this script"
text += '\n[control]\nlaw = "none"\n' + "".join(
    f'\n[[control.wheel]]\nname = "rw_{a}"\naxis = {axis}\ninertia = {JS}\nmax_torque = {UMAX}\n' for a, axis in zip("xyz", AXES)
)
text = text.replace("duration = 5.0", "duration = 15.0", 1)  # the deployment, then the hold
scenario = foldsim.from_toml(text, "basilisk-flasher.toml", base=base.parent)
duration = scenario.get("run.duration")

# %% Basilisk: the structure's task first, the flight software after it, both at 10 Hz.
PERIOD = 0.1
sim = SimulationBaseClass.SimBaseClass()
proc = sim.CreateNewProcess("proc")
proc.addTask(sim.CreateNewTask("structure", macros.sec2nano(PERIOD)), 200)
proc.addTask(sim.CreateNewTask("fsw", macros.sec2nano(PERIOD)), 100)
sc = FoldsimSpacecraft(scenario)
sim.AddModelToTask("structure", sc)

factory = simIncludeRW.rwFactory()
for axis in AXES:
    factory.create("custom", axis, Js=JS, u_max=UMAX, Omega=0.0, Omega_max=1e5, RWModel=messaging.BalancedWheels)
wheel_params = factory.getConfigMessage()
ref = inertial3D.inertial3D()
ref.sigma_R0N = [0.0, 0.0, 0.0]
err = attTrackingError.attTrackingError()
err.attNavInMsg.subscribeTo(sc.attOutMsg)
err.attRefInMsg.subscribeTo(ref.attRefOutMsg)
ctrl = mrpFeedback.mrpFeedback()
ctrl.K, ctrl.P, ctrl.Ki = 300.0, 300.0, -1.0  # N·m, N·m·s; no integral term
ctrl.guidInMsg.subscribeTo(err.attGuidOutMsg)
ctrl.vehConfigInMsg.subscribeTo(sc.vehConfigOutMsg)  # the deploying structure's inertia
ctrl.rwParamsInMsg.subscribeTo(wheel_params)
ctrl.rwSpeedsInMsg.subscribeTo(sc.rwSpeedOutMsg)
motor = rwMotorTorque.rwMotorTorque()
motor.controlAxes_B = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
motor.vehControlInMsg.subscribeTo(ctrl.cmdTorqueOutMsg)
motor.rwParamsInMsg.subscribeTo(wheel_params)
sc.rwMotorTorqueInMsg.subscribeTo(motor.rwMotorTorqueOutMsg)
for i, m in enumerate((ref, err, ctrl, motor)):
    sim.AddModelToTask("fsw", m, 10 - i)

states = sc.scStateOutMsg.recorder()
props = sc.scMassOutMsg.recorder()
torques = motor.rwMotorTorqueOutMsg.recorder()
for r in (states, props):
    sim.AddModelToTask("structure", r)
sim.AddModelToTask("fsw", torques)
sim.InitializeSimulation()
sim.ConfigureStopTime(macros.sec2nano(duration))
sim.ExecuteSimulation()

# %% What happened: pointing error (the rotation angle of σ_B/N, 4 atan|σ|), the structure's
# inertia about the hub's z as it opens, the wheels' commands.
t = states.times() * 1e-9
angle = 4.0 * np.arctan(np.linalg.norm(states.sigma_BN, axis=1))
izz = np.array(props.ISC_PntB_B)[:, 2, 2]
u = np.array(torques.motorTorque)[:, :3]
print(f"pointing error {angle[0]:.3f} rad at t = 0 -> {angle[-1]:.2e} rad at t = {t[-1]:.1f} s")
print(f"inertia about the hub's z: {izz[0]:.1f} -> {izz[-1]:.1f} kg·m²; largest wheel command {np.abs(u).max():.3f} N·m")
deployed = sc.simulation.state["deployed"]
print(f"deployed: {deployed:.3f} of the design radius")
# The unwrapping panels turn the hub (0.8 rad at 2 s, their momentum against its); the
# wheels, saturated at first, bring it back.
print(f"largest pointing error {angle.max():.3f} rad at t = {t[angle.argmax()]:.1f} s")
assert angle[-1] < 0.05 < angle.max(), "the flight software did not bring the hub back to its target"

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
ax[0].semilogy(t, np.maximum(angle, 1e-9))
ax[0].set_ylabel("pointing error, rad")
ax[1].plot(props.times() * 1e-9, izz)
ax[1].set_ylabel("I_zz about hub, kg·m²")
for k, a in enumerate("xyz"):
    ax[2].plot(torques.times() * 1e-9, u[:, k], label=f"rw_{a}")
ax[2].set_ylabel(f"wheel command, N·m\n(applied within ±{UMAX:g})")
ax[2].set_xlabel("t, s")
ax[2].legend()
fig.suptitle("flasher deploying under Basilisk's mrpFeedback (foldsim.basilisk)")
fig.tight_layout()
fig.savefig(out, dpi=100)
print("wrote", out)
