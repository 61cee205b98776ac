#!/usr/bin/env python3
"""integrator = "auto" against DOP853, SDIRK4 and adaptive generalized-alpha on every example.

Each example in examples/ (those with rtol and atol: not the fixed-step ones) is run four
ways at its own tolerances: as "auto", "dop853", "sdirk4" and "generalized-alpha" (adaptive:
no step; the integrator line replaced, nothing else), the four alternated in each round,
--reps rounds, and the median wall time of each reported with the ratio auto / best of the
three fixed choices (the issue's bound: at most 1.2). A run longer than --timeout is stopped and shown as "> T s". Also reported:
the methods auto used (from its report) and the largest difference of auto's body
positions from the fixed method at the example's own choice, so that a faster auto is seen
to give the same answer to the tolerance. The machine load is printed before and after.

With --spread K each round runs every method at K tolerances spread evenly over 0.75–1.25
times the example's own (rtol and atol scaled together), and the medians are over all of
them: for examples whose impacts are chaotic (the thick flasher), where one run's time moves
by 1.7x with the tolerance's last digit (docs/contact.md, *Implicit integration*), so that a
ratio of single runs measures the rounding and not the method. The difference of positions
is then that of the runs at the middle scale (the example's own tolerance for K odd).

Usage (from the repository root, after `cargo build --release`):
    python3 bench/auto_examples.py [--reps 3] [--timeout 300] [--only flasher-small,...]
Only the Python standard library is needed.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDSIM = os.environ.get("FOLDSIM", os.path.join(ROOT, "target", "release", "foldsim"))
METHODS = ["auto", "dop853", "sdirk4", "generalized-alpha"]


def load():
    return open("/proc/loadavg").read().split()[:3] if os.path.exists("/proc/loadavg") else ["?"] * 3


def variant(text, method, scale=1.0):
    """The example's text with its integrator replaced (auto: the line removed) and its rtol
    and atol multiplied by `scale`."""
    line = re.compile(r'^integrator\s*=\s*"[a-z0-9-]+"\s*$', re.M)
    text = line.sub("", text) if method == "auto" else line.sub(f'integrator = "{method}"', text)
    if scale != 1.0:
        tol = re.compile(r'^(rtol|atol)(\s*=\s*)([0-9.eE+-]+)\s*$', re.M)
        text = tol.sub(lambda m: f"{m.group(1)}{m.group(2)}{float(m.group(3)) * scale:.6g}", text)
    return text


def run(path, csv_path, timeout):
    start = time.time()
    try:
        p = subprocess.run([FOLDSIM, "run", path, "--csv", csv_path, "--columns", "t,*_R_?"],
                           capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "", f"> {timeout} s"
    wall = time.time() - start
    if p.returncode != 0:
        return None, "", "failed: " + p.stderr.strip().splitlines()[0][:120]
    return wall, p.stdout, None


def positions(csv_path):
    with open(csv_path) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], [[float(x) for x in r] for r in rows[1:]]
    return head, body


def largest_difference(a, b):
    (ha, ra), (hb, rb) = positions(a), positions(b)
    idx = [hb.index(c) for c in ha]
    worst = 0.0
    for x, y in zip(ra, rb):
        y = [y[i] for i in idx]
        for k in range(1, len(ha), 3):
            worst = max(worst, sum((x[k + j] - y[k + j]) ** 2 for j in range(3)) ** 0.5)
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--only", default="")
    ap.add_argument("--spread", type=int, default=1)
    args = ap.parse_args()
    scales = [1.0] if args.spread <= 1 else [0.75 + 0.5 * i / (args.spread - 1) for i in range(args.spread)]
    names = sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "examples")) if f.endswith(".toml"))
    if args.only:
        names = [n for n in names if n in args.only.split(",")]
    tmp = tempfile.mkdtemp(prefix="foldsim-auto-")
    print(f"load before: {' '.join(load())}", flush=True)
    rows = []
    for name in names:
        src = os.path.join(ROOT, "examples", name + ".toml")
        text = open(src).read()
        m = re.search(r'^integrator\s*=\s*"([a-z0-9]+)"', text, re.M)
        own = m.group(1) if m else "auto"
        if own not in ("dop853", "sdirk4", "auto") or "rtol" not in text:
            continue
        paths = {}
        for method in METHODS:
            for k, scale in enumerate(scales):
                # Written beside the example, so that its table files resolve.
                p = os.path.join(ROOT, "examples", f".bench-{name}-{method}-{k}.toml")
                with open(p, "w") as f:
                    f.write(variant(text, method, scale))
                paths[method, k] = p
        walls = {k: [] for k in METHODS}
        notes = {}
        report = ""
        try:
            for _ in range(args.reps):
                for k in range(len(scales)):
                    for method in METHODS:
                        if method in notes:
                            continue
                        # The positions compared are those at the example's own tolerance.
                        own_scale = k == len(scales) // 2 or not os.path.exists(os.path.join(tmp, f"{name}-{method}.csv"))
                        out_csv = os.path.join(tmp, f"{name}-{method}" + ("" if own_scale else "-other") + ".csv")
                        wall, out, note = run(paths[method, k], out_csv, args.timeout)
                        if note:
                            notes[method] = note
                        else:
                            walls[method].append(wall)
                            if method == "auto" and own_scale:
                                report = out
        finally:
            for p in paths.values():
                os.remove(p)
        med = {k: statistics.median(v) for k, v in walls.items() if v and k not in notes}
        shown = {k: notes.get(k) or f"{med[k]:.2f} s" for k in METHODS}
        fixed = [med[k] for k in METHODS[1:] if k in med]
        ratio = f"{med['auto'] / min(fixed):.2f}" if "auto" in med and fixed else "-"
        spans = re.findall(r"(dop853|sdirk4|generalized-alpha) from t = ([0-9.]+) s", report)
        used = " ".join(f"{a}@{b}" for a, b in spans[:6])
        switches = len(re.findall(r"(?:dop853|sdirk4|generalized-alpha) from t =", report)) - 1
        more = re.search(r"\.\.\. (\d+) switches in all", report)
        if more:
            switches = int(more.group(1))
        ref = own if own != "auto" else "dop853"
        diff = "-"
        if "auto" in med and ref in med:
            diff = f"{largest_difference(os.path.join(tmp, f'{name}-{ref}.csv'), os.path.join(tmp, f'{name}-auto.csv')):.1e}"
        rows.append((name, own, shown["auto"], shown["dop853"], shown["sdirk4"], shown["generalized-alpha"], ratio,
                     f"{switches}", used, diff, ref))
        print(" | ".join(rows[-1]), flush=True)
    print(f"load after: {' '.join(load())}")
    print()
    print("| example | its own | auto | dop853 | sdirk4 | generalized-alpha | auto / best | switches | methods (first 6) | auto vs its own (m) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r[:10]) + " |")


if __name__ == "__main__":
    sys.exit(main())
