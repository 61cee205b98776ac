//! Reduced state-space models for control design (docs/linear.md, *Reduced models*): the full
//! model of [`super::statespace`] (12 numbers per body) projected on a few modes, in the two
//! forms a controller designer uses (Hughes, *Spacecraft Attitude Dynamics*, §6; the
//! "hybrid coordinates" of Likins 1970):
//!
//! - **free-free**: the six rigid-body modes and the N lowest flexible free-free modes, as
//!   modal coordinates `q = Φ ξ` (Φ mass-normalised): `ξ̈ + Φᵀ C Φ ξ̇ + Ω² ξ = Φᵀ M B u`;
//! - **hub-held**: the hub's six coordinates and the N lowest modes with the hub held,
//!   `q = [x_hub; T x_hub + Φ_c η]` (T the appendages' rigid motion with the hub):
//!   `M_r ζ̈ + C_r ζ̇ + K_r ζ = Ψᵀ M B u` with `Ψ = [I 0; T Φ_c]`, `M_r = Ψᵀ M Ψ` (the
//!   whole spacecraft's mass and inertia about the hub, the modes' participation).
//!
//! In both the rigid-body motion has no stiffness and no damping by construction (the
//! internal forces neither resist nor damp a rigid motion): A's columns for the rigid
//! coordinates are exactly those of a free body (and in the free-free form their rows too),
//! so their poles are zero but for an eigen-solver's round-off on their 2×2 Jordan blocks,
//! not the round-off of the full model's stiffness (where some show as `Re λ ≈ +3e-5`).
//! Outputs and wheels' momenta carry over: `C_r = [C_q Ψ, C_v Ψ, C_h]`.

use super::Linearization;
use super::modes::Modes;
use super::statespace::{StateSpace, state_space};
use crate::kinematics::InitialConditions;
use crate::model::Model;
use crate::simulate::RunSettings;
use nalgebra::DMatrix;

/// Bodies up to which the modes for a reduction are taken densely (above: the `count` lowest
/// by Lanczos).
const DENSE_BODIES: usize = 200;

/// The state-space model of `model` at time `at` of its run (as
/// [`super::statespace::state_space`] takes it, `input_bodies` and `outputs` alike),
/// reduced to `count` modes in the form `kind`: what `foldsim linearize --modes` writes.
/// Fails unless the state is at rest and in balance.
#[allow(clippy::too_many_arguments)]
pub fn reduced_state_space(
    model: &Model,
    ic: &InitialConditions,
    settings: &RunSettings,
    at: f64,
    input_bodies: &[usize],
    outputs: &[String],
    count: usize,
    kind: Reduction,
) -> Result<StateSpace, String> {
    if count == 0 {
        return Err("keep at least one flexible mode".into());
    }
    let full = state_space(model, ic, settings, at, input_bodies, outputs)?;
    let (lin, here) = super::linearize_at(model, ic, settings, at)?;
    let apart = here.state.iter().zip(&full.state).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    if here.balanced.is_some() || here.unbalanced.is_some() || apart > 1e-9 {
        return Err("the state is out of balance; a reduced model is taken about an equilibrium (the design state, or a state from `foldsim equilibrium`)".into());
    }
    let modes = if lin.bodies <= DENSE_BODIES {
        Modes::of(&lin, &here.positions, &here.dcm_n_b)?
    } else {
        Modes::lowest(&lin, &here.positions, &here.dcm_n_b, count)?
    };
    reduce(&full, &lin, &modes, count, kind)
}

/// Which reduced form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reduction {
    /// The free-free rigid-body modes and the lowest flexible ones.
    FreeFree,
    /// The hub's coordinates and the lowest modes with the hub held.
    HubHeld,
}

/// `full` (at a state at rest, with its linearisation `lin` and modes `modes` there) reduced
/// to `count` flexible modes in the form `kind`. Fails for a state in motion (the reduction
/// is about rest) or when fewer modes are known than asked for.
pub fn reduce(
    full: &StateSpace,
    lin: &Linearization,
    modes: &Modes,
    count: usize,
    kind: Reduction,
) -> Result<StateSpace, String> {
    let n6 = 6 * lin.bodies;
    if lin.omega_in_body.iter().any(|w| w.norm() > 0.0) || lin.frame_rate.norm() > 0.0 {
        return Err("a reduced model is taken about a state at rest (--deployed, or an equilibrium)".into());
    }
    let wheels = full.a.nrows() - 2 * n6;
    // Ψ: the reduced coordinates' shapes in the full positions; `rigid` of them carry no
    // stiffness or damping.
    let (psi, frequencies, rigid, names): (DMatrix<f64>, Vec<f64>, usize, Vec<String>) = match kind {
        Reduction::FreeFree => {
            let flexible: Vec<_> = modes.free.iter().filter(|m| !m.rigid).collect();
            if flexible.len() < count {
                return Err(format!("--modes {count}: the structure has {} flexible free-free modes", flexible.len()));
            }
            let chosen: Vec<_> =
                modes.free.iter().filter(|m| m.rigid).chain(flexible.into_iter().take(count)).collect();
            let psi = DMatrix::from_fn(n6, chosen.len(), |r, c| chosen[c].shape[r]);
            let names = (0..chosen.len())
                .map(|k| if k < 6 { format!("rigid{k} (kg^½·m)") } else { format!("mode{} (kg^½·m)", k - 6) })
                .collect();
            (psi, chosen.iter().map(|m| if m.rigid { 0.0 } else { m.eigenvalue }).collect(), 6, names)
        }
        Reduction::HubHeld => {
            if modes.hub_fixed.len() < count {
                return Err(format!(
                    "--modes {count}: the structure has {} modes with the hub held",
                    modes.hub_fixed.len()
                ));
            }
            let mut psi = DMatrix::zeros(n6, 6 + count);
            for a in 0..6 {
                psi[(a, a)] = 1.0;
            }
            psi.view_mut((6, 0), (n6 - 6, 6)).copy_from(&modes.hub_rigid_influence);
            for (k, m) in modes.hub_fixed.iter().take(count).enumerate() {
                psi.view_mut((6, 6 + k), (n6 - 6, 1)).copy_from(&m.shape);
            }
            let mut names: Vec<String> =
                ["x (m)", "y (m)", "z (m)", "rx (rad)", "ry (rad)", "rz (rad)"].map(|s| format!("hub_{s}")).to_vec();
            names.extend((0..count).map(|k| format!("hub_held_mode{k} (kg^½·m)")));
            let mut f = vec![0.0; 6];
            f.extend(modes.hub_fixed.iter().take(count).map(|m| m.eigenvalue));
            (psi, f, 6, names)
        }
    };
    let m = psi.ncols();
    let mut mass = DMatrix::zeros(n6, n6);
    for i in 0..lin.bodies {
        mass.view_mut((6 * i, 6 * i), (6, 6)).copy_from(&lin.mass_block(i));
    }
    let project = psi.transpose() * &mass; // Ψᵀ M
    // Free-free: Φᵀ M Φ is I by the shapes' normalisation, taken exactly (its round-off,
    // 1e-15, times the stiffest mode's ω² would couple the rigid coordinates to the modes).
    let m_r_inv = match kind {
        Reduction::FreeFree => DMatrix::identity(m, m),
        Reduction::HubHeld => (&project * &psi).try_inverse().ok_or("the reduced mass matrix is singular")?,
    };
    // Stiffness: the modes' own (Ω², zero for the rigid coordinates); damping: the full
    // model's projected, none on the rigid coordinates.
    let mut k_r = DMatrix::zeros(m, m);
    for (j, w2) in frequencies.iter().enumerate().skip(rigid) {
        k_r[(j, j)] = *w2;
    }
    // Hub-held: the modes are mass-normalised among the appendages, and their stiffness in
    // Ψ's coordinates is exactly Ω² (T carries no strain).
    let j_v = full.a.view((n6, n6), (n6, n6)).into_owned();
    let mut c_r = -(&project * j_v * &psi);
    for r in 0..m {
        for c in 0..m {
            if r < rigid || c < rigid {
                c_r[(r, c)] = 0.0;
            }
        }
    }
    let size = 2 * m + wheels;
    let mut a = DMatrix::zeros(size, size);
    a.view_mut((0, m), (m, m)).copy_from(&DMatrix::identity(m, m));
    a.view_mut((m, 0), (m, m)).copy_from(&(-(&m_r_inv * &k_r)));
    a.view_mut((m, m), (m, m)).copy_from(&(-(&m_r_inv * &c_r)));
    if wheels > 0 {
        let a_vh = full.a.view((n6, 2 * n6), (n6, wheels)).into_owned();
        a.view_mut((m, 2 * m), (m, wheels)).copy_from(&(&m_r_inv * &project * a_vh));
        a.view_mut((2 * m, 2 * m), (wheels, wheels)).copy_from(&full.a.view((2 * n6, 2 * n6), (wheels, wheels)));
    }
    let inputs = full.b.ncols();
    let mut b = DMatrix::zeros(size, inputs);
    b.view_mut((m, 0), (m, inputs)).copy_from(&(&m_r_inv * &project * full.b.view((n6, 0), (n6, inputs))));
    if wheels > 0 {
        b.view_mut((2 * m, 0), (wheels, inputs)).copy_from(&full.b.view((2 * n6, 0), (wheels, inputs)));
    }
    let p = full.c.nrows();
    let mut c = DMatrix::zeros(p, size);
    c.view_mut((0, 0), (p, m)).copy_from(&(full.c.view((0, 0), (p, n6)) * &psi));
    c.view_mut((0, m), (p, m)).copy_from(&(full.c.view((0, n6), (p, n6)) * &psi));
    if wheels > 0 {
        c.view_mut((0, 2 * m), (p, wheels)).copy_from(&full.c.view((0, 2 * n6), (p, wheels)));
    }
    let mut states = names.clone();
    states.extend(names.iter().map(|s| format!("d/dt {s}")));
    states.extend(full.states[2 * n6..].iter().cloned());
    Ok(StateSpace { a, b, c, states, ..full.clone() })
}
