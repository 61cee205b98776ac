#!/usr/bin/env python3
"""Explicit against implicit at equal accuracy on the loop-heavy stiff grid (stiff-hinge issue).

Builds the issue's structure with `foldsim generate grid` (default 16 x 16 = 256 panels,
481 hinges of which 225 close loops; off-axis 1e7 N/m and 1e4 N·m/rad, fold 1 N·m/rad,
20 s), runs a tight DOP853 reference (rtol = atol = --reference-tol), then the implicit path
(SDIRK4) and the explicit path (DOP853) at each tolerance given, and prints for each the
wall time, the steps, the largest hinge-angle error over all output rows against the
reference, and the energy drift. It then names the cheapest explicit run at least as
accurate as the implicit one and the ratio of their wall times.

Usage (from the repository root; the default takes about 10 minutes on 2 cores):
    python3 bench/grid_accuracy.py [--rows 16 --cols 16 --duration 20]
        [--implicit-tols 1e-6] [--explicit-tols 1e-5,1e-6,1e-7,1e-8] [--reference-tol 1e-9]

Only the Python standard library is needed. Nothing here runs in CI: it is a measurement.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDSIM = os.path.join(ROOT, "target", "release", "foldsim")


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def hinge_names(scenario):
    """Names of the scenario's hinges, in order."""
    return re.findall(r'\[\[hinge\]\]\s*\nname = "([^"]+)"', open(scenario).read())


def hinge_angles(path, hinges):
    """Rows of (t, [every hinge's yaw, pitch, roll]) from a foldsim CSV."""
    with open(path) as f:
        reader = csv.reader(f)
        header = next(reader)
        wanted = {f"{h}_{a}" for h in hinges for a in ("yaw", "pitch", "roll")}
        cols = [i for i, h in enumerate(header) if h in wanted]
        assert len(cols) == 3 * len(hinges), "every hinge angle column present"
        return [(float(r[0]), [float(r[i]) for i in cols]) for r in reader]


def max_error(rows, ref):
    err = 0.0
    for (t, a), (tr, b) in zip(rows, ref):
        assert abs(t - tr) < 1e-9, "output rows must line up"
        err = max(err, max(abs(x - y) for x, y in zip(a, b)))
    return err


def run(scenario, integrator, tol, out_csv):
    text = open(scenario).read()
    text = re.sub(r'integrator = "\w+"', f'integrator = "{integrator}"', text)
    text = re.sub(r"rtol = [^\n]+", f"rtol = {tol:e}", text)
    text = re.sub(r"atol = [^\n]+", f"atol = {tol:e}", text)
    path = out_csv.replace(".csv", ".toml")
    with open(path, "w") as f:
        f.write(text)
    start = time.time()
    proc = subprocess.run([FOLDSIM, "run", path, "--csv", out_csv], capture_output=True, text=True)
    wall = time.time() - start
    if proc.returncode != 0:
        sys.exit(f"foldsim failed: {proc.stderr}")
    summary = proc.stdout + proc.stderr
    steps = re.search(r"steps\s+(\d+) accepted", summary).group(1)
    energy = re.search(r"energy E = T \+ V\s+\S+ J \((\S+) relative", summary)
    return wall, int(steps), energy.group(1) if energy else "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rows", type=int, default=16)
    ap.add_argument("--cols", type=int, default=16)
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--implicit-tols", default="1e-6")
    ap.add_argument("--explicit-tols", default="1e-5,1e-6,1e-7,1e-8")
    ap.add_argument("--reference-tol", type=float, default=1e-9)
    args = ap.parse_args()
    subprocess.check_call(["cargo", "build", "--release", "-q"], cwd=ROOT)
    print(f"load average before: {load()}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        scenario = os.path.join(tmp, "grid.toml")
        subprocess.check_call([FOLDSIM, "generate", "grid", "--rows", str(args.rows), "--cols", str(args.cols),
                               "--k-translation", "1e7", "--k-bending", "1e4", "--k-fold", "1",
                               "--duration", str(args.duration), "--tolerance", "1e-6", "-o", scenario])
        ref_csv = os.path.join(tmp, "ref.csv")
        wall, steps, energy = run(scenario, "dop853", args.reference_tol, ref_csv)
        print(f"reference: dop853 rtol = atol = {args.reference_tol:g}: {wall:.1f} s wall, {steps} steps, "
              f"energy drift {energy}", flush=True)
        hinges = hinge_names(scenario)
        ref = hinge_angles(ref_csv, hinges)
        print(f"{'method':>8} {'tol':>8} {'wall s':>9} {'steps':>8} {'max angle err rad':>18} {'energy drift':>13}")
        results = []
        for integrator, tols in (("sdirk4", args.implicit_tols), ("dop853", args.explicit_tols)):
            for tol in (float(t) for t in tols.split(",")):
                out = os.path.join(tmp, f"{integrator}-{tol:g}.csv")
                wall, steps, energy = run(scenario, integrator, tol, out)
                err = max_error(hinge_angles(out, hinges), ref)
                results.append((integrator, tol, wall, err))
                print(f"{integrator:>8} {tol:>8g} {wall:>9.1f} {steps:>8} {err:>18.2e} {energy:>13}", flush=True)
        for integrator, tol, wall, err in (r for r in results if r[0] == "sdirk4"):
            explicit = [r for r in results if r[0] == "dop853" and r[3] <= err]
            if explicit:
                best = min(explicit, key=lambda r: r[2])
                print(f"sdirk4 at {tol:g} (error {err:.1e} rad, {wall:.1f} s): the cheapest dop853 at least as "
                      f"accurate is rtol {best[1]:g} ({best[3]:.1e} rad), {best[2]:.1f} s: ratio {best[2] / wall:.1f}")
            else:
                print(f"sdirk4 at {tol:g} (error {err:.1e} rad): no dop853 run given is as accurate; "
                      "give tighter --explicit-tols")
    print(f"load average after: {load()}")


if __name__ == "__main__":
    main()
