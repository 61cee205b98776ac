//! The flasher generator's report as text: what was built, the checks of its geometry, the stowed
//! strain and, with thick panels, the layers, the hinges' accommodation of the thickness and
//! the creases' stops (docs/flasher.md, *Parameters and report*).

use super::flasher::FlasherReport;
use super::sheet::HingeAxes;
use std::fmt::Write;

impl FlasherReport {
    /// The report as text, one fact per line; with `all_folds`, every hinge's stowed fold.
    pub fn text(&self, all_folds: bool) -> String {
        let (g, s) = (&self.geometry, &self.sheet);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "flasher: {} gores, {} rings, hub radius {} m, panel model '{}'",
            self.shape.gores,
            self.shape.rings,
            self.shape.hub_radius,
            self.shape.model.name()
        );
        let _ = writeln!(
            out,
            "deployed diameter {:.6} m; stowed diameter {:.6} m, height {:.6} m",
            g.deployed_diameter, g.stowed_diameter, g.stowed_height
        );
        let _ = writeln!(out, "panels {} (hub included), hinges {}, independent loops {}", s.panels, s.hinges, s.loops);
        let _ = writeln!(
            out,
            "checks: edge lengths agree to {:.1e} (relative), unfolding closes to {:.1e} m, deployed flat to {:.1e} m, {}-fold symmetric to {:.1e} m, overlap {:.1e}, stowed nodes on the prism to {:.1e} m",
            g.edge_mismatch, g.closure, g.flatness, self.shape.gores, g.symmetry, g.overlap, g.off_prism
        );
        let worst = s.strains.iter().max_by(|a, b| a.off_axis().total_cmp(&b.off_axis()));
        match worst {
            Some(w) if w.off_axis() > 1e-9 => {
                let _ = writeln!(
                    out,
                    "stowed strain: largest hinge deflection off its fold axis {:.3e} m / {:.3e} rad ({}), strain energy {:.6e} J; panels are off their rigid stowed pose by up to {:.3e} m",
                    w.delta.norm(),
                    w.pitch.abs().max(w.roll.abs()),
                    w.hinge,
                    self.strain_energy,
                    s.panel_strain
                );
            }
            _ => {
                let _ = writeln!(
                    out,
                    "stowed strain: none (every hinge is on its fold axis to {:.1e}; strain energy {:.1e} J)",
                    worst.map_or(0.0, |w| w.off_axis()),
                    self.strain_energy
                );
            }
        }
        if let Some((h, outer)) = self.layers {
            let _ = writeln!(
                out,
                "thickness {h} m: stowed in nested layers 0 to {outer} out from the prism walls, face to face (gap 0 between layers), the package {:.6} m across",
                self.geometry.stowed_diameter
                    + 2.0 * (outer as f64 + 1.0) * h / (std::f64::consts::PI / self.shape.gores as f64).cos()
            );
            let shift = s.strains.iter().max_by(|a, b| a.axis_shift.norm().total_cmp(&b.axis_shift.norm()));
            match (self.hinge_axes, shift) {
                (HingeAxes::Shifted, Some(w)) => {
                    let moved = s.strains.iter().filter(|f| f.axis_shift.norm() > 1e-9 * h).count();
                    let _ = writeln!(
                        out,
                        "hinge axes shifted (thickness accommodation): {moved} of {} hinge axes moved off their creases so that each stowed fold is a pure turn, by up to {:.3} thicknesses ({}: {:.3} across, {:.3} along the parent's normal); the deployed sheet is the thin pattern's, panels edge to edge (no gaps, diameter {:.6} m as without thickness; only the vertex cut-outs differ)",
                        s.strains.len(),
                        w.axis_shift.norm() / h,
                        w.hinge,
                        w.axis_shift.x / h,
                        w.axis_shift.y / h,
                        g.deployed_diameter
                    );
                    if let Some((m, count)) = &self.membrane {
                        let _ = writeln!(
                            out,
                            "membrane hinges: {count} folding creases bonded by a membrane {} m wide across the fold line (bending stiffness {:.3e} N·m): their panels' edges move across it (A0's x and y) against {:.3e} N/m per metre of crease (12 D / w³), damped at {} of critical, while it is slack, and meet the hinges' translational stiffness beyond ±{} m (taut), damped there for restitution {} on each crease's panels",
                            m.width,
                            m.bending,
                            m.stiffness(1.0),
                            m.damping_ratio,
                            m.width,
                            super::crease::RESTITUTION
                        );
                    }
                    if let Some((_, first)) = s.stops.first() {
                        let (lo, hi) = s.stops.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), (_, st)| {
                            (lo.min(st.damping), hi.max(st.damping))
                        });
                        let _ = writeln!(
                            out,
                            "crease stops: {} of {} hinges fold one way only, their panels' edges meeting at flat: a stop there at {:e} N·m/rad, damping {:.3}–{:.3} N·m·s/rad (restitution {} for each crease's panels)",
                            s.stops.len(),
                            s.strains.len(),
                            first.stiffness,
                            lo,
                            hi,
                            super::crease::RESTITUTION
                        );
                    }
                }
                _ => {
                    // The layers' offsets, and so the hinges' stowed deflections, grow in
                    // proportion to the thickness: the limit on the thickness is the hinges'.
                    let offset = worst.map_or(0.0, |w| w.delta.norm());
                    let _ = writeln!(
                        out,
                        "hinge axes in the mid-plane: the hinges take up the layers' offsets (the stowed strain above), the largest {:.3} thicknesses, so hinges that take an offset d stow panels up to d / {:.3} thick (for this hub and pattern)",
                        offset / h,
                        offset / h
                    );
                }
            }
        }
        if !self.thick_defaults.is_empty() {
            let _ = writeln!(
                out,
                "thick panels' defaults (not given): {}; hardware deploys through damped hinges, and lightly damped thick sheets ring against their stops and neighbours for seconds after reaching flat, at several times the cost (docs/flasher.md, Damped folds)",
                self.thick_defaults.join(", ")
            );
        }
        let mut folds: Vec<f64> = s.strains.iter().map(|f| f.fold.to_degrees()).collect();
        folds.sort_by(f64::total_cmp);
        folds.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        let shown: Vec<String> = folds.iter().map(|f| format!("{f:.4}")).collect();
        let _ = writeln!(out, "stowed fold angles (distinct, degrees): {}", shown.join(", "));
        if all_folds {
            for f in &s.strains {
                let _ = writeln!(out, "  {} {:.6}°", f.hinge, f.fold.to_degrees());
            }
        }
        out
    }
}
