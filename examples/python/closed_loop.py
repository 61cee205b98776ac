# %% [markdown]
# # Your own attitude controller in the loop
#
# The z-folded array of `examples/zfold-tape-latch.toml` deploys from its hub; three
# reaction wheels on the hub take their torques from a controller written here in Python,
# not from foldsim's built-in laws: an MRP proportional-derivative law with a feed-forward
# of the wheels' gyroscopic torque (Schaub & Junkins §8.4), run at 10 Hz with a zero-order
# hold, as a flight computer would. foldsim integrates the flexible structure between
# samples (`advance`), and the controller reads the hub's attitude and rates from `state`.
#
# Run it after installing the package (README), naming the figure to write:
#
#     python examples/python/closed_loop.py closed_loop.png
#
# About a second. Cells are marked `# %%` for editors that run them one by one.

# %%
import math
import sys
from pathlib import Path

import foldsim

if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
    sys.exit("usage: python closed_loop.py FIGURE.png  (where to write the figure)")
out = sys.argv[1]
foldsim._foldsim.check_outputs([], [("the figure", out)])

ROOT = Path(__file__).resolve().parents[2]
base = ROOT / "examples" / "zfold-tape-latch.toml"
# Three wheels along the hub's axes, their torques given by this script (law "none"); the
# hub's inertia in the scenario includes them.
wheels = "".join(
    f'\n[[control.wheel]]\nname = "rw_{a}"\naxis = {axis}\ninertia = 0.02\nmax_torque = 1.0\nmax_momentum = 4.0\n'
    for a, axis in zip("xyz", ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]))
)
scenario = foldsim.from_toml(base.read_text() + '\n[control]\nlaw = "none"\n' + wheels, "closed-loop.toml", base=base.parent)

# %% The controller: L = −K σ − P ω + ω × (h_wheels), wheel torques u = −L (axes = hub axes).
K, P, PERIOD = 80.0, 150.0, 0.1  # N·m, N·m·s, s


def controller(x: dict) -> list[float]:
    w, q = x["q_B_w"], [x["q_B_x"], x["q_B_y"], x["q_B_z"]]
    s = 1.0 if w >= 0.0 else -1.0  # the short way round
    sigma = [s * v / (1.0 + s * w) for v in q]
    omega = [x["w_B_x"], x["w_B_y"], x["w_B_z"]]
    h = [x["rw_x_h"], x["rw_y_h"], x["rw_z_h"]]
    gyro = [omega[1] * h[2] - omega[2] * h[1], omega[2] * h[0] - omega[0] * h[2], omega[0] * h[1] - omega[1] * h[0]]
    torque = [-K * sg - P * om + g for sg, om, g in zip(sigma, omega, gyro)]
    return [-t for t in torque]  # a wheel's motor torque u gives the hub −u about its axis


sim = scenario.start(columns="t,q_B_*,rw_*_h,rw_*_torque,deployed")
duration = scenario.get("run.duration")
while sim.t < duration - 1e-9:
    sim.set_wheel_torque(controller(sim.state))
    sim.advance(PERIOD)
r = sim.result()

# %% What it did: the hub's angle from its start attitude (the target), 2 atan2(|q_v|, |q_w|).
def pointing(res) -> list[float]:
    return [2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))
            for w, x, y, z in zip(res["q_B_w"], res["q_B_x"], res["q_B_y"], res["q_B_z"])]


error = pointing(r)
worst = max(error)
print(f"pointing error: at most {math.degrees(worst):.2f}° (at t = {r.t[error.index(worst)]:.2f} s), "
      f"{math.degrees(error[-1]):.3f}° at {r.t[-1]:.0f} s")
for name, a in r.report["actuators"].items():
    limit = f", torque limit from t = {a['torque_limit_from']:.2f} s" if a["torque_limit_from"] is not None else ""
    print(f"{name}: |torque| up to {a['torque_max']:.3f} N·m, |J_s Ω| up to {a['momentum_max']:.3f} N·m·s{limit}")
uncontrolled = foldsim.load(base).run()
free = pointing(uncontrolled)
print(f"without control the hub turns by up to {math.degrees(max(free)):.2f}°")

# %% The figure: pointing error with and without the controller, and the wheel momenta.
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
a1.plot(uncontrolled.t, [math.degrees(e) for e in free], label="no control")
a1.plot(r.t, [math.degrees(e) for e in error], label="Python MRP PD, 10 Hz")
a1.set_ylabel("hub pointing error, °")
a1.legend()
for a in "xyz":
    a2.plot(r.t, r[f"rw_{a}_h"], label=f"rw_{a}")
a2.set_ylabel("wheel momentum h, N·m·s")
a2.set_xlabel("t, s")
a2.legend()
fig.tight_layout()
fig.savefig(out, dpi=100)
print(f"figure: {out}")
