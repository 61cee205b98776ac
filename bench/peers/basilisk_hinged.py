#!/usr/bin/env python3
"""foldsim against Basilisk on a hub with two hinged panels held by reaction wheels under
Basilisk's MRP feedback law (the issue's comparison; docs/gnc.md).

The same spacecraft in both:
- a hub (750 kg, inertia diag(900, 800, 600) kg·m² about its centre of mass B);
- two panels on 1-DOF hinges (Basilisk's `hingedRigidBodyStateEffector`: 100 kg,
  IPntS_S = diag(100, 50, 50) kg·m², d = 1.5 m from hinge to centre of mass along −ŝ1,
  k = 100 N·m/rad, c = 5 N·m·s/rad, rotation θ about ĥ2); in foldsim each hinge locks five
  directions and has the spring and damper on its pitch (3-2-1 θ2, which is rotation about
  A's y axis when roll and yaw are held at zero: Basilisk's M2(θ));
- three balanced reaction wheels along the hub's axes (J_s = 0.1 kg·m², torque limit
  0.2 N·m). Basilisk's balanced wheels add no mass or inertia of their own: the hub's
  `IHubPntBc_B` is the spacecraft's with its wheels, as foldsim's hub `inertia` is
  (docs/gnc.md), so both take the same hub (checked: with the wheels idle and no panels the
  two tumble alike to 7e-15 rad over 20 s);
- Basilisk's flight software at 10 Hz: inertial3D (σ_R/N = 0), attTrackingError,
  mrpFeedback (K, P, no integral term), rwMotorTorque (control axes = the hub's); foldsim's
  `[control] law = "mrp_pd"` with the same K, P, `period = 0.1`, the same limits.

Both start with the hub turned (σ_B/N = (0.1, 0.2, −0.3)) and tumbling, the first panel at
5°. The script prints the largest difference of the hub's attitude over the run (the angle
of the relative rotation, rad) at the 10-Hz samples, both wall times, and the machine load.

Usage (from the repository root):
    python3 bench/peers/basilisk_hinged.py [--duration 600] [--dt 0.001]

It creates bench/peers/.venv-basilisk with Basilisk (`bsk`) and NumPy from PyPI on first use,
and builds foldsim with cargo. A measurement, not a test: nothing here runs in CI.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile
import time
import venv

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VENV = os.path.join(HERE, ".venv-basilisk")

HUB_MASS, HUB_I = 750.0, (900.0, 800.0, 600.0)
PANEL_MASS, PANEL_I, D, K_HINGE, C_HINGE = 100.0, (100.0, 50.0, 50.0), 1.5, 100.0, 5.0
# Hinge points (m, hub frame) and the hinge frames' yaw about the hub's z (H = M3(yaw) B).
HINGES = [((0.5, 0.0, 1.0), 0.0), ((-0.5, 0.0, 1.0), math.pi)]
THETA0 = (math.radians(5.0), 0.0)
WHEEL_JS, WHEEL_UMAX = 0.1, 0.2
K_GAIN, P_GAIN, PERIOD = 6.0, 60.0, 0.1
SIGMA0, OMEGA0 = (0.1, 0.2, -0.3), (0.01, -0.01, 0.005)


def ensure_venv():
    """Re-executes this script inside bench/peers/.venv-basilisk, creating it if needed."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        print("creating", VENV, "with Basilisk (bsk) and numpy from PyPI ...", flush=True)
        venv.create(VENV, with_pip=True)
        subprocess.check_call([py, "-m", "pip", "install", "-q", "bsk", "numpy"])
    os.execv(py, [py] + sys.argv)


def mrp_to_dcm(s):
    """[B N] of MRPs σ_B/N (Schaub & Junkins eq. 3.152)."""
    s2 = sum(x * x for x in s)
    sk = [[0.0, -s[2], s[1]], [s[2], 0.0, -s[0]], [-s[1], s[0], 0.0]]
    sk2 = [[sum(sk[i][k] * sk[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    d = (1.0 + s2) ** 2
    return [[(i == j) + (8.0 * sk2[i][j] - 4.0 * (1.0 - s2) * sk[i][j]) / d for j in range(3)] for i in range(3)]


def mrp_to_quat(s):
    s2 = sum(x * x for x in s)
    return [(1.0 - s2) / (1.0 + s2)] + [2.0 * x / (1.0 + s2) for x in s]


def angle_between(q1, q2):
    """The rotation angle between two attitudes given as quaternions (scalar first), rad:
    2 atan2(|v|, |w|) of q1* ⊗ q2 (acos of the dot product loses half the digits near 0)."""
    a0, a1, a2, a3 = q1[0], -q1[1], -q1[2], -q1[3]
    b0, b1, b2, b3 = q2
    w = a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3
    v = (a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2, a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0)
    return 2.0 * math.atan2(math.sqrt(sum(x * x for x in v)), abs(w))


def foldsim_scenario(duration, tol):
    """The spacecraft as a foldsim scenario (docs/scenario.md, docs/gnc.md)."""
    c = mrp_to_dcm(SIGMA0)  # [B N]
    yaw, pitch, roll = math.atan2(c[0][1], c[0][0]), -math.asin(c[0][2]), math.atan2(c[1][2], c[2][2])
    # The hub with its wheels held (both codes' convention).
    inertia = list(HUB_I)
    lines = [
        'title = "hub, two 1-DOF hinged panels, three wheels, MRP feedback (Basilisk comparison)"',
        "[run]",
        f"duration = {duration}",
        f"output_step = {PERIOD}",
        'integrator = "dop853"',
        f"rtol = {tol}",
        f"atol = {tol}",
        "[[body]]",
        'name = "hub"',
        f"mass = {HUB_MASS}",
        f"inertia = {inertia}",
    ]
    for k in range(2):
        lines += ["[[body]]", f'name = "p{k + 1}"', f"mass = {PANEL_MASS}", f"inertia = {list(PANEL_I)}"]
    for k, (r, yaw_h) in enumerate(HINGES):
        lines += [
            "[[hinge]]",
            f'name = "h{k + 1}"',
            'parent = "hub"',
            f'child = "p{k + 1}"',
            f"a0 = {{ position = {list(r)}, yaw = {yaw_h} }}",
            f"a = {{ child_com = [{-D}, 0.0, 0.0] }}",
            "[hinge.law]",
            'type = "directional"',
            'angles = "euler"',
        ]
        lines += [f"{d} = {{ locked = true }}" for d in ("x", "y", "z", "rx", "rz")]
        lines += [f"ry = {{ k = {K_HINGE}, damping = {C_HINGE} }}"]
    lines += [
        "[control]",
        'law = "mrp_pd"',
        "target = [1.0, 0.0, 0.0, 0.0]",
        f"k = {K_GAIN}",
        f"p = {P_GAIN}",
        f"period = {PERIOD}",
    ]
    for name, axis in zip("xyz", ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])):
        lines += ["[[control.wheel]]", f'name = "rw_{name}"', f"axis = {axis}", f"inertia = {WHEEL_JS}", f"max_torque = {WHEEL_UMAX}"]
    lines += ["[initial.hub]", f"yaw = {yaw!r}", f"pitch = {pitch!r}", f"roll = {roll!r}", f"omega = {list(OMEGA0)}"]
    for k, th in enumerate(THETA0):
        lines += [f"[initial.hinge.h{k + 1}]", f"pitch = {th!r}"]
    return "\n".join(lines) + "\n"


def run_foldsim(duration, tol):
    work = tempfile.mkdtemp(prefix="foldsim-basilisk-")
    path = os.path.join(work, "basilisk_hinged.toml")
    out = os.path.join(work, "basilisk_hinged.csv")
    with open(path, "w") as f:
        f.write(foldsim_scenario(duration, tol))
    exe = os.path.join(ROOT, "target", "release", "foldsim")
    t0 = time.perf_counter()
    subprocess.check_call([exe, "run", path, "--csv", out, "-q"])
    wall = time.perf_counter() - t0
    with open(out) as f:
        rows = list(csv.DictReader(f))
    return {round(float(r["t"]), 6): [float(r[f"q_B_{a}"]) for a in "wxyz"] for r in rows}, rows, wall


def run_basilisk(duration, dt):
    import numpy as np
    from Basilisk.architecture import messaging
    from Basilisk.fswAlgorithms import attTrackingError, inertial3D, mrpFeedback, rwMotorTorque
    from Basilisk.simulation import hingedRigidBodyStateEffector, reactionWheelStateEffector, simpleNav, spacecraft
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeRW

    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("dyn", macros.sec2nano(dt)), 200)  # dynamics first at a shared time
    proc.addTask(sim.CreateNewTask("fsw", macros.sec2nano(PERIOD)), 100)

    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sc"
    sc.hub.mHub = HUB_MASS
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = np.diag(HUB_I).tolist()
    sc.hub.sigma_BNInit = [[x] for x in SIGMA0]
    sc.hub.omega_BN_BInit = [[x] for x in OMEGA0]
    panels = []
    for k, (r, yaw_h) in enumerate(HINGES):
        p = hingedRigidBodyStateEffector.HingedRigidBodyStateEffector()
        p.ModelTag = f"panel{k + 1}"
        p.mass = PANEL_MASS
        p.IPntS_S = np.diag(PANEL_I).tolist()
        p.d = D
        p.k = K_HINGE
        p.c = C_HINGE
        p.r_HB_B = [[x] for x in r]
        cy, sy = math.cos(yaw_h), math.sin(yaw_h)
        p.dcm_HB = [[cy, sy, 0.0], [-sy, cy, 0.0], [0.0, 0.0, 1.0]]  # M3(yaw): [H B]
        p.thetaInit = THETA0[k]
        p.thetaDotInit = 0.0
        sc.addStateEffector(p)
        sim.AddModelToTask("dyn", p)
        panels.append(p)

    factory = simIncludeRW.rwFactory()
    for axis in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]):
        rw = factory.create("custom", axis, Js=WHEEL_JS, u_max=WHEEL_UMAX, Omega=0.0, Omega_max=1e5,
                            RWModel=messaging.BalancedWheels, rWB_B=[0.0, 0.0, 0.0])
    wheels = reactionWheelStateEffector.ReactionWheelStateEffector()
    wheels.ModelTag = "wheels"
    factory.addToSpacecraft("wheels", wheels, sc)
    sim.AddModelToTask("dyn", wheels, 2)
    sim.AddModelToTask("dyn", sc, 1)
    nav = simpleNav.SimpleNav()
    nav.scStateInMsg.subscribeTo(sc.scStateOutMsg)
    sim.AddModelToTask("dyn", nav, 0)

    ref = inertial3D.inertial3D()
    ref.sigma_R0N = [0.0, 0.0, 0.0]
    err = attTrackingError.attTrackingError()
    err.attNavInMsg.subscribeTo(nav.attOutMsg)
    err.attRefInMsg.subscribeTo(ref.attRefOutMsg)
    ctrl = mrpFeedback.mrpFeedback()
    ctrl.K = K_GAIN
    ctrl.P = P_GAIN
    ctrl.Ki = -1.0
    config = messaging.VehicleConfigMsgPayload()
    config.ISCPntB_B = np.diag(HUB_I).flatten().tolist()
    config_msg = messaging.VehicleConfigMsg().write(config)
    ctrl.guidInMsg.subscribeTo(err.attGuidOutMsg)
    ctrl.vehConfigInMsg.subscribeTo(config_msg)
    params = factory.getConfigMessage()
    motor = rwMotorTorque.rwMotorTorque()
    motor.controlAxes_B = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    motor.vehControlInMsg.subscribeTo(ctrl.cmdTorqueOutMsg)
    motor.rwParamsInMsg.subscribeTo(params)
    wheels.rwMotorCmdInMsg.subscribeTo(motor.rwMotorTorqueOutMsg)
    for i, m in enumerate((ref, err, ctrl, motor)):
        sim.AddModelToTask("fsw", m, 10 - i)

    log = sc.scStateOutMsg.recorder(macros.sec2nano(PERIOD))
    sim.AddModelToTask("dyn", log)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(duration))
    t0 = time.perf_counter()
    sim.ExecuteSimulation()
    wall = time.perf_counter() - t0
    times = log.times() * 1e-9
    return {round(float(t), 6): mrp_to_quat(s) for t, s in zip(times, log.sigma_BN)}, wall


def main():
    ensure_venv()
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=600.0)
    ap.add_argument("--dt", type=float, default=0.001, help="Basilisk's dynamics step (RK4), s")
    ap.add_argument("--tol", type=float, default=1e-12, help="foldsim's DOP853 tolerance")
    args = ap.parse_args()
    subprocess.check_call(["cargo", "build", "--release", "-q"], cwd=ROOT)
    ours, rows, wall_f = run_foldsim(args.duration, args.tol)
    theirs, wall_b = run_basilisk(args.duration, args.dt)
    common = sorted(set(ours) & set(theirs))
    diffs = [(angle_between(ours[t], theirs[t]), t) for t in common]
    worst, at = max(diffs)
    start = angle_between(ours[common[0]], [1.0, 0.0, 0.0, 0.0])
    end = angle_between(ours[common[-1]], [1.0, 0.0, 0.0, 0.0])
    print(f"hub attitude, foldsim against Basilisk over {args.duration} s at {len(common)} samples (10 Hz):")
    print(f"  largest difference {worst:.3e} rad at t = {at:.1f} s (pointing error {start:.4f} -> {end:.2e} rad)")
    print(f"  wall: foldsim {wall_f:.2f} s (DOP853 {args.tol:g}), Basilisk {wall_b:.2f} s (RK4 {args.dt} s); load {os.getloadavg()[0]:.2f}")
    print("  (not a speed comparison: Basilisk's fixed step is chosen for accuracy here)")


if __name__ == "__main__":
    main()
