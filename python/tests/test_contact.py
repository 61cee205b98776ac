"""Contact from Python (docs/contact.md): the report's contact figures and the columns.

Run from the repository root after `maturin develop --release` in python/: `pytest python/tests`.
"""

from pathlib import Path

import numpy as np

import foldsim

ROOT = Path(__file__).resolve().parents[2]


def test_contact_report_and_columns():
    """The panel thrown onto the hub: the report names the pair and gives the first touch,
    the deepest penetration (a small fraction of the 2-cm panel) and the largest force; the
    contact columns are there and agree with the report's figures at the rows."""
    r = foldsim.load(ROOT / "examples" / "contact-panel-hub.toml").run()
    c = r.report["contact"]
    t_first, a, b = c["first"]
    assert {a, b} == {"panel", "hub"}
    assert 0.8 < t_first < 0.9
    depth, t_deep, _, _ = c["deepest"]
    assert 0.0 < depth < 0.1 * 0.02
    assert t_deep >= t_first
    force, _, _, _ = c["force_max"]
    assert force > 0.0
    assert c["dissipated"] > 0.0
    # Every episode is the panel on the hub it is hinged to: a neighbour, not a strike.
    assert c["episodes"] and all(e["joined"] and set(e["bodies"]) == {"panel", "hub"} for e in c["episodes"])
    rows = r.columns
    for name in ("contacts", "penetration_max", "contact_force_max"):
        assert name in rows
    # The rows see no more than the accepted steps did.
    assert max(r["penetration_max"]) <= depth * (1 + 1e-12)
    assert max(r["contacts"]) >= 1


def test_no_contact_table_means_no_contact():
    """Without [contact] the report says None and no contact column is written."""
    r = foldsim.load(ROOT / "examples" / "paper-1panel.toml").run()
    assert r.report["contact"] is None
    assert "contacts" not in r.columns


def test_overlaps_of_a_run_and_of_its_csv(tmp_path):
    """`Scenario.overlaps` (docs/contact.md §3): the panel-hub example's swing back, measured
    from its poses apart from the contact code, gives the same pairs from the run's Result as
    from the CSV `foldsim run` would write (the same numbers: 1e-12 m); as sharp prisms its
    corner enters the hub by 0.44 mm (2.2 % of the 2-cm panel, below the 10 % bound), and
    with the rim rounded as the samples describe it less."""
    s = foldsim.load(ROOT / "examples" / "contact-panel-hub.toml")
    r = s.run()
    sharp = s.overlaps(r, sharp=True)
    assert sharp and {sharp[0]["body_a"], sharp[0]["body_b"]} == {"hub", "panel"}
    assert 1e-4 < sharp[0]["depth"] < 0.1 * 0.02
    assert abs(sharp[0]["of_thickness"] - sharp[0]["depth"] / 0.02) < 1e-12
    rounded = s.overlaps(r)
    assert not rounded or rounded[0]["depth"] < sharp[0]["depth"]
    csv = tmp_path / "run.csv"
    np.savetxt(csv, np.column_stack([r[c] for c in r.columns]), delimiter=",", header=",".join(r.columns), comments="", fmt="%.17g")
    again = s.overlaps(csv, sharp=True)
    assert len(again) == len(sharp)
    for a, b in zip(again, sharp):
        assert abs(a["depth"] - b["depth"]) < 1e-12 and a["t"] == b["t"]
