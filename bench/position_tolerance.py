#!/usr/bin/env python3
"""run.position_tolerance on every example: the error delivered against the error asked.

For each example in examples/ with rtol and atol (not the fixed-step ones): a reference run
(DOP853 at rtol = atol = 1e-12, or --ref-rtol), the structure's size (the largest diagonal
of the box around every body's centre of mass over the reference's rows), and then runs
with rtol and atol replaced by `position_tolerance = f × size` for f = 1e-2 ... 1e-6, with
the example's own integrator ("own") and with the integrator line removed ("auto"). Per
run: the largest distance of any body's centre of mass from the reference over every row,
divided by what was asked (the issue's bound: at most 3), the estimate the run reported,
its wall time and its number of runs. A run longer than --timeout is stopped and shown as
"> T s". The machine load is printed before and after.

Usage (from the repository root, after `cargo build --release`):
    python3 bench/position_tolerance.py [--only flasher-small,...] [--methods own,auto]
        [--fractions 1e-2,1e-3,1e-4,1e-5,1e-6] [--timeout 600] [--ref-rtol 1e-12]
Only the Python standard library is needed.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

from auto_examples import largest_difference, load, positions  # same directory

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDSIM = os.environ.get("FOLDSIM", os.path.join(ROOT, "target", "release", "foldsim"))


TOL = re.compile(r"^(rtol|atol)\s*=.*$", re.M)
INTEGRATOR = re.compile(r'^integrator\s*=\s*"[a-z0-9-]+"\s*$', re.M)


def with_tolerance(text, tolerance, method):
    """The example with rtol, atol replaced by the position tolerance (and, for "auto", no
    integrator line)."""
    text = TOL.sub("", text)
    text = re.sub(r"^\[run\]\s*$", f"[run]\nposition_tolerance = {tolerance:.6e}", text, count=1, flags=re.M)
    if method == "auto":
        text = INTEGRATOR.sub("", text)
    return text


def reference_text(text, rtol):
    text = TOL.sub("", text)
    text = INTEGRATOR.sub("", text)
    return re.sub(r"^\[run\]\s*$", f'[run]\nintegrator = "dop853"\nrtol = {rtol:e}\natol = {rtol:e}', text,
                  count=1, flags=re.M)


def run(path, csv_path, timeout):
    start = time.time()
    try:
        p = subprocess.run([FOLDSIM, "run", path, "--csv", csv_path, "--columns", "t,*_R_?"],
                           capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "", f"> {timeout:.0f} s"
    wall = time.time() - start
    if p.returncode != 0:
        return None, "", "failed: " + ([l for l in p.stderr.splitlines() if "error" in l] or ["?"])[0][:300]
    return wall, p.stdout, None


def size(csv_path):
    head, rows = positions(csv_path)
    worst = 0.0
    for r in rows:
        lo = [min(r[k + j] for k in range(1, len(head), 3)) for j in range(3)]
        hi = [max(r[k + j] for k in range(1, len(head), 3)) for j in range(3)]
        worst = max(worst, sum((h - l) ** 2 for h, l in zip(hi, lo)) ** 0.5)
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", default="")
    ap.add_argument("--methods", default="own,auto")
    ap.add_argument("--fractions", default="1e-2,1e-3,1e-4,1e-5,1e-6")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--ref-rtol", type=float, default=1e-12)
    args = ap.parse_args()
    fractions = [float(f) for f in args.fractions.split(",")]
    methods = args.methods.split(",")
    names = sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "examples")) if f.endswith(".toml"))
    if args.only:
        names = [n for n in names if n in args.only.split(",")]
    tmp = tempfile.mkdtemp(prefix="foldsim-ptol-")
    print(f"load before: {' '.join(load())}", flush=True)
    print("| example | size m | method | asked / size | asked m | error m | error / asked | estimated m | runs | wall |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    worst = 0.0
    for name in names:
        text = open(os.path.join(ROOT, "examples", name + ".toml")).read()
        if "rtol" not in text or re.search(r"^step\s*=", text, re.M) or name.startswith("sweep"):
            continue
        # Written beside the example, so that its table files resolve.
        ref_path = os.path.join(ROOT, "examples", f".ptol-{name}-ref.toml")
        ref_csv = os.path.join(tmp, f"{name}-ref.csv")
        # The tightest DOP853 run that reaches the end (a latch's events can hold the
        # steps below the run's floor at 1e-12).
        for ref_rtol in (args.ref_rtol, 10 * args.ref_rtol, 100 * args.ref_rtol):
            with open(ref_path, "w") as f:
                f.write(reference_text(text, ref_rtol))
            try:
                _, _, note = run(ref_path, ref_csv, args.timeout)
            finally:
                os.remove(ref_path)
            if not note:
                break
        if note:
            print(f"| {name} | – | reference | – | – | {note} | | | | |", flush=True)
            continue
        L = size(ref_csv)
        print(f"| {name} | {L:.3g} | reference | dop853 at rtol = atol = {ref_rtol:.0e} | | | | | | |", flush=True)
        for method in methods:
            for frac in fractions:
                asked = frac * L
                path = os.path.join(ROOT, "examples", f".ptol-{name}-{method}.toml")
                with open(path, "w") as f:
                    f.write(with_tolerance(text, asked, method))
                out_csv = os.path.join(tmp, f"{name}-{method}.csv")
                try:
                    wall, out, note = run(path, out_csv, args.timeout)
                finally:
                    os.remove(path)
                if note:
                    print(f"| {name} | {L:.3g} | {method} | {frac:.0e} | {asked:.2e} | {note} | | | | |", flush=True)
                    continue
                err = largest_difference(ref_csv, out_csv)
                m = re.search(r"position error\s+estimated ([0-9.e+-]+) m", out)
                n = re.search(r"(\d+) runs:", out)
                worst = max(worst, err / asked)
                print(f"| {name} | {L:.3g} | {method} | {frac:.0e} | {asked:.2e} | {err:.2e} | {err / asked:.2f} | "
                      f"{m.group(1) if m else '?'} | {n.group(1) if n else '?'} | {wall:.2f} s |", flush=True)
    print(f"largest error / asked: {worst:.2f}")
    print(f"load after: {' '.join(load())}")


if __name__ == "__main__":
    sys.exit(main())
