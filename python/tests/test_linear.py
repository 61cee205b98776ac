"""The linear model and the modes from Python (docs/linear.md): the same numbers as the
command line's, arrays python-control takes as they are."""

import subprocess
from pathlib import Path

import numpy as np
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "foldsim"


def test_linearize_equals_the_command_line(tmp_path):
    """Scenario.linearize gives bit for bit the matrices `foldsim linearize` writes, and
    python-control builds a state-space system of them."""
    control = pytest.importorskip("control")
    example = ROOT / "examples" / "paper-3panel.toml"
    m = foldsim.load(example).linearize(at=0.5, outputs="q_B_*,w_B_*,h1_yaw", inputs=["hub", "p1"])
    out = tmp_path / "m.npz"
    subprocess.run(
        [str(CLI), "linearize", str(example), "--at", "0.5", "--outputs", "q_B_*,w_B_*,h1_yaw", "--inputs", "hub,p1", "-q", "-o", str(out)],
        check=True,
    )
    saved = np.load(out)
    for key in ("A", "B", "C", "D", "y0"):
        assert np.array_equal(m[key], saved[key]), key
    for key in ("states", "inputs", "outputs"):
        assert list(saved[key]) == m[key], key
    assert m["A"].shape == (48, 48) and m["B"].shape == (48, 12) and m["C"].shape == (8, 48)
    sys = control.ss(m["A"], m["B"], m["C"], m["D"])
    assert (sys.nstates, sys.ninputs, sys.noutputs) == (48, 12, 8)
    # The hub's torque inputs turn it by I⁻¹ τ (hub inertia from the scenario): B's entries.
    inertia = foldsim.load(example).get("body.hub.inertia")
    j = m["inputs"].index("hub_T_z")
    k = m["states"].index("hub_dw_z (rad/s, body)")
    assert m["B"][k, j] == pytest.approx(1.0 / inertia[2], rel=1e-12)


def test_modes_match_the_command_line(tmp_path):
    """Scenario.modes' frequencies are the `foldsim modes` table's; the 20 lowest by
    Lanczos equal the dense ones to 1e-8 (the dense solver's own round-off, docs/linear.md);
    shapes are mass-normalised columns, 6 per body."""
    example = ROOT / "examples" / "flasher-small.toml"
    s = foldsim.load(example)
    dense = s.modes(deployed=True)
    lowest = s.modes(deployed=True, count=20)
    out = tmp_path / "m.csv"
    subprocess.run([str(CLI), "modes", str(example), "--deployed", "-q", "-o", str(out)], check=True)
    table = np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding="utf-8")
    free = table[table["kind"] != "hub_fixed"]["frequency_hz"]
    assert np.array_equal(free, dense["free"]["frequency_hz"])
    assert np.allclose(lowest["free"]["frequency_hz"][6:26], dense["free"]["frequency_hz"][6:26], rtol=1e-8, atol=0)
    assert lowest["free"]["rigid"][:6] == [True] * 6 and not any(lowest["free"]["rigid"][6:])
    assert dense["free"]["shapes"].shape == (6 * len(s.bodies), 6 * len(s.bodies))
    assert lowest["hub_fixed"]["effective"].shape == (20, 6)


def test_bad_requests_say_what_is_valid():
    s = foldsim.load(ROOT / "examples" / "paper-3panel.toml")
    with pytest.raises(ValueError, match="sigma_B_x"):
        s.linearize(outputs="nonsense_*")
    with pytest.raises(ValueError, match="no body 'nobody'"):
        s.linearize(inputs=["nobody"])
    with pytest.raises(ValueError, match="run.duration"):
        s.modes(at=1e3)


def test_reduced_models_have_their_rigid_poles_at_zero():
    """linearize(modes=N): the free-free and hub-held reductions (docs/linear.md); their
    twelve rigid-body poles are zero (NumPy's eigvals, no tolerance needed beyond 1e-12),
    the flexible ones stable, 2 (6 + N) states."""
    s = foldsim.load(ROOT / "examples" / "flasher-small.toml")
    for hub_held in (False, True):
        m = s.linearize(deployed=True, modes=6, hub_held=hub_held)
        assert m["A"].shape == (24, 24)
        poles = np.linalg.eigvals(m["A"])
        assert (np.abs(poles) <= 1e-12).sum() == 12
        assert poles.real.max() <= 1e-12
    for bad in (0, -1, 2.5, "x", True):
        with pytest.raises((ValueError, TypeError)):
            s.linearize(deployed=True, modes=bad)
    with pytest.raises(ValueError, match="modes"):
        s.linearize(deployed=True, hub_held=True)
