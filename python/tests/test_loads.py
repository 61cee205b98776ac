"""External loads from Python: the report gives what they added (docs/loads.md)."""

from pathlib import Path

import numpy as np

import foldsim

ROOT = Path(__file__).resolve().parents[2]


def test_report_gives_the_loads_impulse_and_work():
    text = (ROOT / "examples" / "paper-3panel-euler.toml").read_text()
    text = text.replace("duration = 20.0", "duration = 1.0")
    text += (
        '\n[[load]]\nname = "push"\nbody = "hub"\nforce = [3.0, -2.0, 1.0]\n'
        'force_frame = "inertial"\n'
    )
    r = foldsim.from_toml(text, "loaded.toml").run()
    loads = r.report["loads"]
    # A constant force at the hub's centre for 1 s: the impulse is F t (1e-10 relative).
    assert np.allclose(loads["impulse"], [3.0, -2.0, 1.0], rtol=1e-10, atol=0)
    # The work column ends at the report's work, and P gained the impulse.
    assert r["W"][-1] == loads["work"]
    dp = np.array([r[f"P_{a}"][-1] - r[f"P_{a}"][0] for a in "xyz"])
    assert np.allclose(dp, [3.0, -2.0, 1.0], rtol=1e-10, atol=0)
    assert foldsim.load(ROOT / "examples" / "paper-1panel.toml").run().report["loads"] is None
