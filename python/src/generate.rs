//! The generators (`foldsim.generate.zfold`, `grid`, `flasher`): the command line's options,
//! defaults and checks (`foldsim::generate::options`), returning a scenario.

use crate::scenario::Scenario;
use foldsim::generate::Params;
use foldsim::generate::options::{FlasherOptions, grid_checked, panel_model, zfold_checked};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An option's key as Python spells it.
fn key(k: &str) -> String {
    k.to_string()
}

fn scenario(text: String, name: &str) -> PyResult<Scenario> {
    Scenario::from_toml_text(&text, name)
}

/// The z-fold and grid options (SI units; see `foldsim generate --help`).
#[allow(clippy::too_many_arguments)]
fn params(
    panel_mass: f64,
    panel_length: f64,
    panel_width: f64,
    k_translation: f64,
    k_bending: f64,
    k_fold: f64,
    fold_deg: f64,
    duration: f64,
    output_step: f64,
    tolerance: f64,
) -> Params {
    Params {
        panel_mass,
        panel_length,
        panel_width,
        k_translation,
        k_bending,
        k_fold,
        fold_deg,
        duration,
        output_step,
        tolerance,
    }
}

/// A z-folded chain of `panels` panels off the hub, stowed with alternating folds.
#[pyfunction]
#[pyo3(signature = (panels, *, panel_mass = 2.0, panel_length = 1.0, panel_width = 0.6, k_translation = 1e6, k_bending = 1e3, k_fold = 1.0, fold_deg = 30.0, duration = 10.0, output_step = 0.01, tolerance = 1e-8))]
#[allow(clippy::too_many_arguments)]
pub fn zfold(
    panels: usize,
    panel_mass: f64,
    panel_length: f64,
    panel_width: f64,
    k_translation: f64,
    k_bending: f64,
    k_fold: f64,
    fold_deg: f64,
    duration: f64,
    output_step: f64,
    tolerance: f64,
) -> PyResult<Scenario> {
    let p = params(
        panel_mass,
        panel_length,
        panel_width,
        k_translation,
        k_bending,
        k_fold,
        fold_deg,
        duration,
        output_step,
        tolerance,
    );
    scenario(zfold_checked(panels, &p, &key).map_err(PyValueError::new_err)?, "zfold")
}

/// A `rows` × `cols` grid of panels hinged to their neighbours (many loops).
#[pyfunction]
#[pyo3(signature = (rows, cols, *, panel_mass = 2.0, panel_length = 1.0, panel_width = 0.6, k_translation = 1e6, k_bending = 1e3, k_fold = 1.0, fold_deg = 30.0, duration = 10.0, output_step = 0.01, tolerance = 1e-8))]
#[allow(clippy::too_many_arguments)]
pub fn grid(
    rows: usize,
    cols: usize,
    panel_mass: f64,
    panel_length: f64,
    panel_width: f64,
    k_translation: f64,
    k_bending: f64,
    k_fold: f64,
    fold_deg: f64,
    duration: f64,
    output_step: f64,
    tolerance: f64,
) -> PyResult<Scenario> {
    let p = params(
        panel_mass,
        panel_length,
        panel_width,
        k_translation,
        k_bending,
        k_fold,
        fold_deg,
        duration,
        output_step,
        tolerance,
    );
    scenario(grid_checked(rows, cols, &p, &key).map_err(PyValueError::new_err)?, "grid")
}

/// A flasher of `gores` gores and `rings` rings (docs/flasher.md); returns the scenario and
/// the generator's report (diameters, counts, checks, stowed strain) as text.
#[pyfunction]
#[pyo3(signature = (gores, rings, *, hub_radius = 1.0, thickness = 0.0, areal_density = 1.0, hub_mass = 100.0, hub_inertia = None, panels = "triangles", k_fold = 1.0, c_fold = 0.0, k_panel_bending = 1e3, c_panel_bending = 0.0, k_translation = 1e6, c_translation = 0.0, k_bending = 1e3, c_rotation = 0.0, spin_rpm = 0.0, duration = 10.0, output_step = None, tolerance = 1e-8, integrator = "dop853", release_at = None))]
#[allow(clippy::too_many_arguments)]
pub fn flasher(
    gores: usize,
    rings: usize,
    hub_radius: f64,
    thickness: f64,
    areal_density: f64,
    hub_mass: f64,
    hub_inertia: Option<[f64; 3]>,
    panels: &str,
    k_fold: f64,
    c_fold: f64,
    k_panel_bending: f64,
    c_panel_bending: f64,
    k_translation: f64,
    c_translation: f64,
    k_bending: f64,
    c_rotation: f64,
    spin_rpm: f64,
    duration: f64,
    output_step: Option<f64>,
    tolerance: f64,
    integrator: &str,
    release_at: Option<f64>,
) -> PyResult<(Scenario, String)> {
    let options = FlasherOptions {
        gores,
        rings,
        hub_radius,
        thickness,
        areal_density,
        hub_mass,
        hub_inertia,
        panels: panel_model(panels).map_err(PyValueError::new_err)?,
        laws: foldsim::generate::flasher::FlasherLaws {
            k_fold,
            c_fold,
            k_bending: k_panel_bending,
            c_bending: c_panel_bending,
            k_translation,
            c_translation,
            k_rotation: k_bending,
            c_rotation,
        },
        spin_rpm,
        duration,
        output_step,
        tolerance,
        integrator: integrator.to_string(),
        release_at,
    };
    let (text, report) = options.scenario(&key).map_err(PyValueError::new_err)?;
    Ok((scenario(text, "flasher")?, report.text(false)))
}
