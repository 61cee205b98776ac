"""foldsim inside other tools (docs/interop.md): the C library against the Python package's
stepping, and the FMU through FMPy (an independent FMI importer): its validation, its
simulation with an input signal against `foldsim run` with the same [[load]], and errors
through the FMI logger.

Needs `cargo build --release` at the repository's root (the CLI, libfoldsim_c.so,
libfoldsim_fmu.so; `.ci/run` has built them), a C compiler, and FMPy (the test extra).
"""

import csv
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]
RELEASE = ROOT / "target" / "release"
CLI = RELEASE / "foldsim"


def built(name: str) -> Path:
    """A build product of the workspace, brought up to date (cargo is where the repository
    is; a second or two when nothing changed): `cargo test` alone leaves the shared libraries
    only in target/release/deps, and a copy above may be older."""
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    return RELEASE / name


def read_csv(text: str) -> tuple[list[str], np.ndarray]:
    rows = list(csv.reader(text.splitlines()))
    return [c.strip() for c in rows[0]], np.array([[float(x) for x in r] for r in rows[1:]])


def test_c_library_equals_python_stepping(tmp_path):
    """capi/tests/c/stepping.c (hub_T_z = 0.5 N·m and hub_F_x = 1 N, hub_T_z = −0.25 from
    half way; 200 advances of 10 ms on the paper's three panels) against the same inputs
    through `Scenario.start()`: every output column to 1e-12 of its size. Both step the
    same run through different faces, so more than round-off would be a fault of a face."""
    built("libfoldsim_c.so")
    exe = tmp_path / "stepping"
    subprocess.run(
        ["cc", "-std=c99", "-I", str(ROOT / "include"), str(ROOT / "capi/tests/c/stepping.c"), "-L", str(RELEASE),
         "-lfoldsim_c", "-lm", f"-Wl,-rpath,{RELEASE}", "-o", str(exe)],
        check=True,
    )
    scenario = ROOT / "examples" / "paper-3panel.toml"
    ran = subprocess.run([str(exe), str(scenario), "200", "0.01"], capture_output=True, text=True)
    assert ran.returncode == 0, ran.stderr
    names, c_rows = read_csv(ran.stdout)

    sim = foldsim.load(scenario).start()
    sim.set_torque("hub", [0.0, 0.0, 0.5], frame="body")
    sim.set_force("hub", [1.0, 0.0, 0.0], frame="body")
    py_rows = []
    for k in range(201):
        state = sim.state
        py_rows.append([state[n] for n in names])
        if k == 200:
            break
        if k == 100:
            sim.set_torque("hub", [0.0, 0.0, -0.25], frame="body")
        sim.advance(0.01)
    py_rows = np.array(py_rows)
    size = np.maximum(1.0, np.abs(py_rows).max(axis=0))
    worst = (np.abs(c_rows - py_rows) / size).max()
    print(f"C library against Python stepping: {worst:.1e}")
    assert worst <= 1e-12


fmpy = pytest.importorskip("fmpy")


def export(tmp_path: Path, scenario: Path, name: str, *args: str) -> Path:
    built("libfoldsim_fmu.so")
    out = tmp_path / f"{name}.fmu"
    subprocess.run([str(CLI), "export", "fmu", str(scenario), "-o", str(out), *args], check=True, capture_output=True)
    return out


def test_fmu_validates_and_takes_a_torque(tmp_path):
    """The issue's case: `--outputs 'H_*,w_B_z'` of the radial spin, FMPy's validation finds
    nothing, and 2 N·m about the hub's z for 5 s adds 10 N·m·s to H_z (the hub spins about
    its z axis, which stays along N's z: H_z gains the whole impulse) to 1e-8 of |H|."""
    fmu = export(tmp_path, ROOT / "examples" / "radial-spin.toml", "spin", "--outputs", "H_*,w_B_z")
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []
    signal = np.array([(0.0, 2.0), (5.0, 2.0)], dtype=[("time", np.float64), ("hub_T_z", np.float64)])
    r = fmpy.simulate_fmu(str(fmu), stop_time=5.0, output_interval=0.01, input=signal, output=["H_x", "H_y", "H_z", "w_B_z"])
    h = np.sqrt(r["H_x"] ** 2 + r["H_y"] ** 2 + r["H_z"] ** 2).max()
    gained = r["H_z"][-1] - r["H_z"][0]
    print(f"H_z gained {gained!r} N·m·s; error {abs(gained - 10.0) / h:.1e} of |H|")
    assert abs(gained - 10.0) <= 1e-8 * h
    assert r["w_B_z"][-1] > r["w_B_z"][0]


def spin_scenarios(tmp_path: Path) -> tuple[Path, Path]:
    """The radial spin over 5 s, and the same with a [[load]]: 0.5 N·m about x and 2 N·m about
    z in the hub's frame during [1, 3) s."""
    text = (ROOT / "examples" / "radial-spin.toml").read_text().replace("duration = 20.0", "duration = 5.0")
    plain, loaded = tmp_path / "spin.toml", tmp_path / "spin_load.toml"
    plain.write_text(text)
    loaded.write_text(
        text + '\n[[load]]\nname = "torque"\nbody = "hub"\ntorque = [0.5, 0.0, 2.0]\ntorque_frame = "body"\non = [[1.0, 3.0]]\n'
    )
    return plain, loaded


def drive(fmu: Path, dt: float, steps: int, inputs) -> tuple[list[str], np.ndarray]:
    """Steps an FMU through FMPy's FMI 2.0 wrapper: `inputs(t)` gives {name: value} before each
    step; the outputs are read at every communication point."""
    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outs = [v.name for v in md.modelVariables if v.causality == "output"]
    f = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="test")
    f.instantiate()
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    rows = []
    for k in range(steps + 1):
        t = k * dt
        rows.append([t] + f.getReal([vr[o] for o in outs]))
        if k == steps:
            break
        u = inputs(t)
        f.setReal([vr[n] for n in u], list(u.values()))
        f.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
    f.terminate()
    f.freeInstance()
    return outs, np.array(rows)


def test_fmu_equals_foldsim_run_with_the_same_load(tmp_path):
    """The FMU driven with the load's torque as its input signal (on at the communication
    point 1 s, off at 3 s) against `foldsim run` of the scenario with the [[load]], at every
    communication point (the run's rows, 20 ms): each piece restarts DOP853 at the
    communication point, so the two differ by the integration error (rtol 1e-10); bound
    1e-9 of each column's size."""
    plain, loaded = spin_scenarios(tmp_path)
    columns = "H_*,w_B_*,q_B_*,panel1_yaw,panel1_R_*"
    fmu = export(tmp_path, plain, "spin", "--outputs", columns, "--parameters", "none")
    subprocess.run([str(CLI), "run", str(loaded), "--csv", str(tmp_path / "run.csv"), "-q", "--columns", "t," + columns],
                   check=True)
    names, run = read_csv((tmp_path / "run.csv").read_text())

    def torque(t):
        on = 1.0 - 1e-9 <= t < 3.0 - 1e-9
        return {"hub_T_x": 0.5 if on else 0.0, "hub_T_z": 2.0 if on else 0.0}

    outs, rows = drive(fmu, 0.02, 250, torque)
    assert len(rows) == len(run)
    worst = 0.0
    for j, o in enumerate(outs):
        col = run[:, names.index(o)]
        worst = max(worst, np.abs(rows[:, j + 1] - col).max() / max(1.0, np.abs(col).max()))
    print(f"FMU against foldsim run: largest difference {worst:.1e}")
    assert worst <= 1e-9


def test_fmu_parameters_and_errors_through_the_logger(tmp_path):
    """A parameter set by key path changes the run as the same change in the file does; a
    step past the scenario's horizon, a non-finite input and a bad parameter come back as
    fmi2Error with the reason in the host's log, never a crash."""
    plain, _ = spin_scenarios(tmp_path)
    # A vector's components are not parameters: refused, saying what is offered.
    refused = subprocess.run([str(CLI), "export", "fmu", str(plain), "-o", str(tmp_path / "x.fmu"), "--parameters",
                              "body.hub.inertia.*"], capture_output=True, text=True)
    assert refused.returncode != 0 and "matches no number" in refused.stderr, refused.stderr
    fmu = export(tmp_path, plain, "spin", "--outputs", "w_B_z", "--parameters", "body.hub.mass")
    md = fmpy.read_model_description(str(fmu))
    names = [v.name for v in md.modelVariables if v.causality == "parameter"]
    assert names == ["body.hub.mass"], names
    # The hub lighter by a tenth: the same run as the file so changed.
    r = fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.1, start_values={"body.hub.mass": 180.0})
    changed = tmp_path / "changed.toml"
    changed.write_text(plain.read_text().replace("mass = 200.0", "mass = 180.0", 1))
    subprocess.run([str(CLI), "run", str(changed), "--csv", str(tmp_path / "c.csv"), "-q", "--columns", "t,w_B_z"], check=True)
    _, c = read_csv((tmp_path / "c.csv").read_text())
    assert abs(r["w_B_z"][-1] - c[50, 1]) <= 1e-9

    messages = []

    def logger(component, instance, status, category, message):
        messages.append((status, message.decode()))

    from fmpy.fmi1 import FMICallException

    with pytest.raises(FMICallException):
        fmpy.simulate_fmu(str(fmu), stop_time=1.0, start_values={"body.hub.mass": -5.0}, logger=logger)
    assert any("mass must be a finite number > 0" in m for _, m in messages), messages
    messages.clear()
    with pytest.raises(FMICallException):
        # 5 s is the scenario's horizon unless the host sets a stop time: here it steps on.
        drive_past = fmpy.instantiate_fmu(fmpy.extract(str(fmu)), md, fmi_type="CoSimulation", logger=logger)
        drive_past.setupExperiment(startTime=0.0)
        drive_past.enterInitializationMode()
        drive_past.exitInitializationMode()
        drive_past.doStep(currentCommunicationPoint=0.0, communicationStepSize=6.0)
    assert any("passes run.duration" in m for _, m in messages), messages


def test_fmu_motor_inputs_replace_their_drives(tmp_path):
    """`--inputs mid,tip`: the z-fold's two constant-effort motors become FMU inputs (their
    drives replaced from the start). Driven with the scenario's own efforts (±0.05 N·m on
    [3, 9) s) they give `foldsim run`'s rows at every 10-ms communication point (the servo
    motor `root` stays the scenario's) to the integration error: DOP853 at rtol 1e-8, each
    piece restarted and the latches' events located anew in it; measured 1.4e-7 of each
    column's size, bound 1e-6. Held at 0 instead, the middle fold opens differently."""
    scenario = ROOT / "examples" / "zfold-motor-deploy.toml"
    columns = "h1_yaw,h2_yaw,h3_yaw,H_*"
    fmu = export(tmp_path, scenario, "motors", "--inputs", "mid,tip", "--outputs", columns, "--parameters", "none")
    md = fmpy.read_model_description(str(fmu))
    assert [v.name for v in md.modelVariables if v.causality == "input"] == ["mid_effort", "tip_effort"]
    subprocess.run([str(CLI), "run", str(scenario), "--csv", str(tmp_path / "run.csv"), "-q", "--columns", "t," + columns],
                   check=True)
    names, run = read_csv((tmp_path / "run.csv").read_text())
    dt = run[1, 0] - run[0, 0]
    steps = len(run) - 1

    def efforts(t):
        on = 3.0 - 1e-9 <= t < 9.0 - 1e-9
        return {"mid_effort": 0.05 if on else 0.0, "tip_effort": -0.05 if on else 0.0}

    outs, rows = drive(fmu, dt, steps, efforts)
    worst = max(np.abs(rows[:, j + 1] - run[:, names.index(o)]).max() / max(1.0, np.abs(run[:, names.index(o)]).max())
                for j, o in enumerate(outs))
    print(f"FMU with motor inputs against foldsim run: {worst:.1e}")
    assert worst <= 1e-6
    _, idle = drive(fmu, dt, steps, lambda t: {"mid_effort": 0.0, "tip_effort": 0.0})
    mid = outs.index("h2_yaw") + 1
    assert np.abs(idle[:, mid] - rows[:, mid]).max() > 0.05  # the efforts mattered


def test_fmu_runs_a_host_horizon_longer_than_the_scenario(tmp_path):
    """A host's stop time past the scenario's `run.duration` (here 30 s of the radial spin
    written for 20 s with 20-ms rows, and a day's horizon given at setup) is the run's
    horizon: the FMU steps to it."""
    fmu = export(tmp_path, ROOT / "examples" / "radial-spin.toml", "spin", "--outputs", "w_B_z", "--parameters", "none")
    r = fmpy.simulate_fmu(str(fmu), stop_time=30.0, output_interval=1.0)
    assert r["time"][-1] == 30.0 and np.isfinite(r["w_B_z"]).all()
    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(str(fmu))
    f = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)), modelIdentifier="spin", instanceName="day")
    f.instantiate()
    f.setupExperiment(startTime=0.0, stopTime=86400.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    f.doStep(currentCommunicationPoint=0.0, communicationStepSize=1.0)
    f.terminate()
    f.freeInstance()
