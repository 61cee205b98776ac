"""The cost of a controller outside foldsim (issue: a 1 kHz control loop on the three-panel
case must not cost more than 2× the run without it). A benchmark, not a test.

    python python/bench/stepping.py          # from the repository root, package installed

On the paper's three-panel case (law 1, DOP853 at its scenario's tolerances, 5 s), medians
of alternated repeats, the machine's load printed beside:

1. `run()` with the built-in MRP PD law sampled at 1 kHz (steps end every 1 ms, as in the
   loop): the run without the loop;
2. the same law in Python: every 1 ms `state`, the law, `set_torque`, `advance(0.001)`;
3. the loop with `advance(0.001)` alone (the calls' own cost, no law);
4. `run()` with no control at all (steps as long as the accuracy allows).
"""

from __future__ import annotations

import os
import statistics
import time
from pathlib import Path

import foldsim

ROOT = Path(__file__).resolve().parents[2]
K, P, DT, DURATION = 30.0, 80.0, 1e-3, 5.0


def scenario(extra: str = "") -> foldsim.Scenario:
    text = (ROOT / "examples" / "paper-3panel.toml").read_text()
    s = foldsim.from_toml(text + "\n[initial.hub]\nomega = [0.05, -0.1, 0.3]\n" + extra, "bench.toml")
    return s.with_values({"run.duration": DURATION})


def law(state: dict) -> list[float]:
    """L = −K σ − P ω in plain Python (NumPy costs more than the law for three numbers)."""
    w, x, y, z = state["q_B_w"], state["q_B_x"], state["q_B_y"], state["q_B_z"]
    s = 1.0 if w >= 0.0 else -1.0
    c = s / (1.0 + s * w)
    return [-K * x * c - P * state["w_B_x"], -K * y * c - P * state["w_B_y"], -K * z * c - P * state["w_B_z"]]


def timed(f) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def main(repeats: int = 5) -> None:
    built_in = scenario(f'[control]\nlaw = "mrp_pd"\nk = {K}\np = {P}\ntarget = [1.0, 0.0, 0.0, 0.0]\nperiod = {DT}\n')
    free = scenario()
    steps = int(round(DURATION / DT))

    def python_loop():
        sim = free.start()
        for _ in range(steps):
            sim.set_torque("hub", law(sim.state), frame="body")
            sim.advance(DT)

    def bare_loop():
        sim = free.start()
        for _ in range(steps):
            sim.advance(DT)

    times = {"built-in 1 kHz": [], "Python 1 kHz loop": [], "advance() alone": [], "free run": []}
    loads = []
    for _ in range(repeats):
        times["built-in 1 kHz"].append(timed(built_in.run))
        times["Python 1 kHz loop"].append(timed(python_loop))
        times["advance() alone"].append(timed(bare_loop))
        times["free run"].append(timed(free.run))
        loads.append(os.getloadavg()[0])
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"three-panel case, {DURATION} s simulated, {steps} control periods; medians of {repeats}; load {min(loads):.2f}-{max(loads):.2f}")
    for k, v in med.items():
        print(f"  {k:<20} {v * 1e3:8.1f} ms   ({v / steps * 1e6:6.1f} µs per 1 ms period)")
    print(f"  Python loop / built-in 1 kHz: {med['Python 1 kHz loop'] / med['built-in 1 kHz']:.2f}  (bound 2)")
    print(f"  Python loop / free run:       {med['Python 1 kHz loop'] / med['free run']:.2f}")
    print(f"  calls alone / built-in 1 kHz: {med['advance() alone'] / med['built-in 1 kHz']:.2f}")


if __name__ == "__main__":
    main()
