//! The generators (`foldsim.generate.zfold`, `grid`, `flasher`): the command line's options,
//! defaults and checks (`foldsim::generate::options`), returning a scenario.

use crate::scenario::Scenario;
use foldsim::generate::Params;
use foldsim::generate::options::{FlasherOptions, grid_checked, hinge_axes, panel_model, zfold_checked};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// An option's key as Python spells it.
fn key(k: &str) -> String {
    k.to_string()
}

fn scenario(text: String, name: &str) -> PyResult<Scenario> {
    Scenario::from_toml_text(&text, name)
}

/// Applies keyword `options` one by one with `set` (which says whether it knows the key);
/// an unknown key is refused with the known ones.
fn apply(
    options: Option<&Bound<'_, PyDict>>,
    known: &[&str],
    mut set: impl FnMut(&str, &Bound<'_, PyAny>) -> PyResult<bool>,
) -> PyResult<()> {
    for (k, v) in options.into_iter().flat_map(|d| d.iter()) {
        let k: String = k.extract()?;
        // A value of the wrong type or shape: the error names the option (pyo3's says only
        // what it expected).
        let known_key = set(&k, &v).map_err(|e| {
            Python::attach(|py| {
                let message = format!("option {k}: {}", e.value(py));
                if e.is_instance_of::<pyo3::exceptions::PyTypeError>(py) {
                    pyo3::exceptions::PyTypeError::new_err(message)
                } else {
                    PyValueError::new_err(message)
                }
            })
        })?;
        if !known_key {
            return Err(PyValueError::new_err(format!("unknown option '{k}': the options are {}", known.join(", "))));
        }
    }
    Ok(())
}

/// The z-fold and grid options over the library's defaults (`Params::default()`).
fn params(options: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
    const KNOWN: [&str; 10] = [
        "panel_mass",
        "panel_length",
        "panel_width",
        "k_translation",
        "k_bending",
        "k_fold",
        "fold_deg",
        "duration",
        "output_step",
        "tolerance",
    ];
    let mut p = Params::default();
    apply(options, &KNOWN, |k, v| {
        let slot = match k {
            "panel_mass" => &mut p.panel_mass,
            "panel_length" => &mut p.panel_length,
            "panel_width" => &mut p.panel_width,
            "k_translation" => &mut p.k_translation,
            "k_bending" => &mut p.k_bending,
            "k_fold" => &mut p.k_fold,
            "fold_deg" => &mut p.fold_deg,
            "duration" => &mut p.duration,
            "output_step" => &mut p.output_step,
            "tolerance" => &mut p.tolerance,
            _ => return Ok(false),
        };
        *slot = v.extract()?;
        Ok(true)
    })?;
    Ok(p)
}

/// A z-folded chain of `panels` panels off the hub, stowed with alternating folds; keyword
/// options as `foldsim generate zfold` takes them (SI units).
#[pyfunction]
#[pyo3(signature = (panels, **options))]
pub fn zfold(panels: usize, options: Option<&Bound<'_, PyDict>>) -> PyResult<Scenario> {
    let text = zfold_checked(panels, &params(options)?, &key).map_err(PyValueError::new_err)?;
    scenario(text, "zfold")
}

/// A `rows` × `cols` grid of panels hinged to their neighbours (many loops).
#[pyfunction]
#[pyo3(signature = (rows, cols, **options))]
pub fn grid(rows: usize, cols: usize, options: Option<&Bound<'_, PyDict>>) -> PyResult<Scenario> {
    let text = grid_checked(rows, cols, &params(options)?, &key).map_err(PyValueError::new_err)?;
    scenario(text, "grid")
}

/// A flasher of `gores` gores and `rings` rings (docs/flasher.md) over the library's defaults
/// (`FlasherOptions::default()`); returns the scenario and the generator's report
/// (diameters, counts, checks, stowed strain) as text.
#[pyfunction]
#[pyo3(signature = (gores, rings, **options))]
pub fn flasher(gores: usize, rings: usize, options: Option<&Bound<'_, PyDict>>) -> PyResult<(Scenario, String)> {
    const KNOWN: [&str; 25] = [
        "hub_radius",
        "thickness",
        "hinge_axes",
        "areal_density",
        "hub_mass",
        "hub_inertia",
        "panels",
        "k_fold",
        "c_fold",
        "k_panel_bending",
        "c_panel_bending",
        "k_translation",
        "c_translation",
        "k_bending",
        "c_rotation",
        "k_stop",
        "membrane_bending",
        "membrane_width",
        "membrane_damping_ratio",
        "spin_rpm",
        "duration",
        "output_step",
        "tolerance",
        "integrator",
        "release_at",
    ];
    let mut o = FlasherOptions { gores, rings, ..FlasherOptions::default() };
    apply(options, &KNOWN, |k, v| {
        let number = match k {
            "hub_radius" => &mut o.hub_radius,
            "thickness" => &mut o.thickness,
            "areal_density" => &mut o.areal_density,
            "hub_mass" => &mut o.hub_mass,
            "k_fold" => &mut o.laws.k_fold,
            "c_fold" => {
                o.laws.c_fold = Some(v.extract()?);
                return Ok(true);
            }
            "k_panel_bending" => &mut o.laws.k_bending,
            "c_panel_bending" => &mut o.laws.c_bending,
            "k_translation" => &mut o.laws.k_translation,
            "c_translation" => &mut o.laws.c_translation,
            "k_bending" => &mut o.laws.k_rotation,
            "c_rotation" => &mut o.laws.c_rotation,
            "k_stop" => &mut o.laws.k_stop,
            "membrane_bending" => &mut o.laws.membrane_bending,
            "membrane_damping_ratio" => &mut o.laws.membrane_damping_ratio,
            "membrane_width" => {
                o.laws.membrane_width = v.extract()?;
                return Ok(true);
            }
            "spin_rpm" => &mut o.spin_rpm,
            "duration" => &mut o.duration,
            "tolerance" => {
                o.tolerance = Some(v.extract()?);
                return Ok(true);
            }
            "hub_inertia" => {
                o.hub_inertia = v.extract()?;
                return Ok(true);
            }
            "panels" => {
                o.panels = panel_model(&v.extract::<String>()?).map_err(PyValueError::new_err)?;
                return Ok(true);
            }
            "hinge_axes" => {
                o.hinge_axes = hinge_axes(&v.extract::<String>()?).map_err(PyValueError::new_err)?;
                return Ok(true);
            }
            "integrator" => {
                o.integrator = Some(v.extract()?);
                return Ok(true);
            }
            "output_step" => {
                o.output_step = v.extract()?;
                return Ok(true);
            }
            "release_at" => {
                o.release_at = v.extract()?;
                return Ok(true);
            }
            _ => return Ok(false),
        };
        *number = v.extract()?;
        Ok(true)
    })?;
    let (text, report) = o.scenario(&key).map_err(PyValueError::new_err)?;
    Ok((scenario(text, "flasher")?, report.text(false)))
}
