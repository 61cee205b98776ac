#!/usr/bin/env python3
"""foldsim against MuJoCo on a z-folded chain of panels with six-direction spring hinges.

The same structure in both (foldsim's `generate zfold`: docs/model.md law 2, the hinge as slides
x, y, z then hinges z, y, x with joint stiffness in MuJoCo, which is exactly law 2 in joint
coordinates). A tight foldsim run (DOP853, rtol = atol = 1e-12) is the reference. For each
simulator the script finds the cheapest setting whose largest hinge-angle error over the run
is within --accuracy (foldsim: the loosest tolerance; MuJoCo RK4: the largest step), and
prints the wall times and their ratio, with the machine load.

Usage (from the repository root):
    python3 bench/peers/mujoco_zfold.py --panels 64 --duration 10 --accuracy 1e-6

It creates bench/peers/.venv with MuJoCo and NumPy from PyPI on first use, and builds
foldsim with cargo. Nothing here runs in CI: it is a measurement, not a test.
"""
import argparse
import csv
import io
import os
import re
import subprocess
import sys
import time
import venv

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VENV = os.path.join(HERE, ".venv")


def ensure_venv():
    """Re-executes this script inside bench/peers/.venv, creating it if needed."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        print("creating", VENV, "with mujoco and numpy from PyPI ...", flush=True)
        venv.create(VENV, with_pip=True)
        subprocess.check_call([py, "-m", "pip", "install", "-q", "mujoco", "numpy"])
    os.execv(py, [py] + sys.argv)


def load():
    try:
        with open("/proc/loadavg") as f:
            return " ".join(f.read().split()[:3])
    except OSError:
        return "?"


def foldsim_bin():
    subprocess.check_call(["cargo", "build", "--release", "-q"], cwd=ROOT)
    return os.path.join(ROOT, "target", "release", "foldsim")


def scenario_text(exe, args, tolerance):
    text = subprocess.check_output(
        [exe, "generate", "zfold", "--panels", str(args.panels), "--duration", str(args.duration),
         "--tolerance", repr(tolerance), "--k-translation", repr(args.k_translation),
         "--k-bending", repr(args.k_bending), "--k-fold", repr(args.k_fold), "--fold-deg", repr(args.fold_deg)],
        text=True)
    return re.sub(r"output_step = [0-9.e+-]+", f"output_step = {args.sample!r}", text)


def run_foldsim(exe, args, tolerance, tmp):
    """Returns (angles per sample: list of rows of 3N angles, integration wall time in s)."""
    path = os.path.join(tmp, f"zfold-{tolerance:g}.toml")
    with open(path, "w") as f:
        f.write(scenario_text(exe, args, tolerance))
    out_csv = path.replace(".toml", ".csv")
    report = subprocess.check_output([exe, "run", path, "--csv", out_csv], text=True)
    wall = float(re.search(r"wall time\s+([0-9.e+-]+) s", report).group(1))
    with open(out_csv) as f:
        rows = list(csv.reader(f))
    head = rows[0]
    cols = [head.index(f"h{k}_{a}") for k in range(1, args.panels + 1) for a in ("yaw", "pitch", "roll")]
    t_col = head.index("t")
    data = [[float(r[t_col])] + [float(r[c]) for c in cols] for r in rows[1:]]
    return data, wall


def mjcf(args, dt):
    m, l, w, t = 2.0, 1.0, 0.6, 0.02
    ix, iy, iz = m / 12 * (t * t + w * w), m / 12 * (l * l + w * w), m / 12 * (l * l + t * t)
    out = io.StringIO()
    out.write('<mujoco model="zfold">\n<compiler angle="radian"/>\n')
    out.write(f'<option timestep="{dt!r}" integrator="RK4" gravity="0 0 0"/>\n<worldbody>\n')
    out.write('<body name="hub" pos="0 0 0">\n<freejoint/>\n<inertial pos="0 0 0" mass="500" diaginertia="400 400 400"/>\n')
    for k in range(1, args.panels + 1):
        # The body frame is A (the hinge point); A0 sits at the parent's far edge: 1 m from
        # the hub CoM, or 0.5 + 0.5 m from the previous panel's hinge point.
        out.write(f'<body name="p{k}" pos="1.0 0 0">\n')
        for axis, name in (("1 0 0", "x"), ("0 1 0", "y"), ("0 0 1", "z")):
            out.write(f'<joint name="h{k}_{name}" type="slide" axis="{axis}" stiffness="{args.k_translation!r}"/>\n')
        for axis, name, kk in (("0 0 1", "yaw", args.k_fold), ("0 1 0", "pitch", args.k_bending),
                               ("1 0 0", "roll", args.k_bending)):
            out.write(f'<joint name="h{k}_{name}" type="hinge" axis="{axis}" stiffness="{kk!r}"/>\n')
        out.write(f'<inertial pos="0.5 0 0" mass="{m!r}" diaginertia="{ix!r} {iy!r} {iz!r}"/>\n')
    out.write("</body>\n" * args.panels)
    out.write("</body>\n</worldbody>\n</mujoco>\n")
    return out.getvalue()


def run_mujoco(args, dt, times):
    import mujoco
    mujoco.set_mju_user_warning(lambda msg: None)  # instability is detected from the samples
    model = mujoco.MjModel.from_xml_string(mjcf(args, dt))
    data = mujoco.MjData(model)
    import math
    addr = {}
    for k in range(1, args.panels + 1):
        for a in ("yaw", "pitch", "roll"):
            addr[(k, a)] = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"h{k}_{a}")]
    for k in range(1, args.panels + 1):
        data.qpos[addr[(k, "yaw")]] = math.radians(args.fold_deg if k % 2 == 1 else -args.fold_deg)
    mujoco.mj_forward(model, data)
    samples = []
    steps_per_sample = round(args.sample / dt)
    start = time.perf_counter()
    sample = [[0.0] + [data.qpos[addr[(k, a)]] for k in range(1, args.panels + 1) for a in ("yaw", "pitch", "roll")]]
    n_samples = len(times) - 1
    for i in range(n_samples):
        for _ in range(steps_per_sample):
            mujoco.mj_step(model, data)
        sample.append([data.time] + [data.qpos[addr[(k, a)]] for k in range(1, args.panels + 1) for a in ("yaw", "pitch", "roll")])
    wall = time.perf_counter() - start
    samples = sample
    return samples, wall


def max_error(ref, other):
    """Largest angle difference over all samples; infinite if the run went unstable (MuJoCo
    resets its state and time when it does)."""
    err = 0.0
    for r, o in zip(ref, other):
        if abs(r[0] - o[0]) > 1e-6:
            return float("inf")
        err = max(err, max(abs(a - b) for a, b in zip(r[1:], o[1:])))
    return err


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--panels", type=int, default=64)
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--accuracy", type=float, default=1e-6, help="max hinge-angle error, rad")
    ap.add_argument("--sample", type=float, default=0.1, help="comparison interval, s")
    ap.add_argument("--k-translation", type=float, default=1e6)
    ap.add_argument("--k-bending", type=float, default=1e3)
    ap.add_argument("--k-fold", type=float, default=1.0)
    ap.add_argument("--fold-deg", type=float, default=30.0)
    ap.add_argument("--mujoco-steps", default="4e-3,2e-3,1e-3,5e-4,2.5e-4,1.25e-4,6.25e-5",
                    help="RK4 steps to try, largest first (each must divide --sample)")
    # Parse first: --help and bad options answer without installing anything.
    args = ap.parse_args()
    ensure_venv()
    import tempfile
    tmp = tempfile.mkdtemp(prefix="foldsim-peers-")
    exe = foldsim_bin()
    print(f"z-fold chain, {args.panels} panels, {args.duration} s, accuracy {args.accuracy:g} rad; load {load()}", flush=True)
    ref, ref_wall = run_foldsim(exe, args, 1e-12, tmp)
    print(f"reference: foldsim DOP853 rtol=atol=1e-12, {ref_wall:.3f} s", flush=True)

    best_fs = None
    for tol in (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        data, wall = run_foldsim(exe, args, tol, tmp)
        err = max_error(ref, data)
        print(f"  foldsim DOP853 tol {tol:g}: max angle error {err:.3e} rad, wall {wall:.3f} s", flush=True)
        if err <= args.accuracy:
            best_fs = (tol, err, wall)
            break

    best_mj = None
    for dt in [float(x) for x in args.mujoco_steps.split(",")]:
        data, wall = run_mujoco(args, dt, [row[0] for row in ref])
        err = max_error(ref, data)
        print(f"  MuJoCo RK4 dt {dt:g}: max angle error {err:.3e} rad, wall {wall:.3f} s", flush=True)
        if err == err and err <= args.accuracy:  # NaN (an unstable step) never qualifies
            best_mj = (dt, err, wall)
            break

    print(f"load after: {load()}")
    if best_fs and best_mj:
        print(f"RESULT foldsim (tol {best_fs[0]:g}) {best_fs[2]:.3f} s vs MuJoCo RK4 (dt {best_mj[0]:g}) "
              f"{best_mj[2]:.3f} s at max angle error <= {args.accuracy:g} rad: MuJoCo/foldsim = {best_mj[2] / best_fs[2]:.1f}")
    else:
        print("RESULT: no setting reached the accuracy for", "foldsim" if not best_fs else "MuJoCo")


if __name__ == "__main__":
    main()
