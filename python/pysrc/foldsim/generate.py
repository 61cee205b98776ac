"""The structure generators, as ``foldsim generate`` has them (SI units; the same defaults
and checks): each returns a :class:`foldsim.Scenario`."""

from __future__ import annotations

from . import _foldsim
from ._checks import count


def _wrap(native):
    from . import Scenario

    return Scenario(native)


def zfold(panels: int, **options) -> "Scenario":
    """A z-folded chain of `panels` panels off the hub. Options: panel_mass (kg),
    panel_length, panel_width (m), k_translation (N/m), k_bending, k_fold (N·m/rad),
    fold_deg, duration (s), output_step (s), tolerance."""
    return _wrap(_foldsim.zfold(count(panels, "panels"), **options))


def grid(rows: int, cols: int, **options) -> "Scenario":
    """A rows × cols grid of panels hinged to their neighbours; options as :func:`zfold`."""
    return _wrap(_foldsim.grid(count(rows, "rows"), count(cols, "cols"), **options))


def flasher(gores: int, rings: int, **options) -> tuple["Scenario", str]:
    """A flasher (a disc of panels wrapped round a polygonal hub): the scenario and the
    generator's report. Options as ``foldsim generate flasher`` takes them, with _ for -:
    hub_radius, thickness, areal_density, hub_mass, hub_inertia, panels ("triangles",
    "quads", "ring-quads"), k_fold, c_fold, k_panel_bending, c_panel_bending, k_translation,
    c_translation, k_bending, c_rotation, k_stop, spin_rpm, duration, output_step, tolerance,
    integrator, release_at. As there, thick panels (thickness > 0) default to c_fold = 1 and
    SDIRK4 at tolerance 1e-5 (thin: 0.05, DOP853 at 1e-8), and the report names the defaults
    it took."""
    native, report = _foldsim.flasher(count(gores, "gores"), count(rings, "rings"), **options)
    return _wrap(native), report
