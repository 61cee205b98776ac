//! A grid of panels whose hinges mostly close loops.

use super::params::{Params, header, hinge, panel};
use std::fmt::Write;

/// A hub and an `rows` × `cols` grid of panels in the hub's x–y plane: panel (i, j) is hinged
/// to (i, j+1) along y and to (i+1, j) along x; panel (0, 0) hangs from the hub. Loop hinges
/// are assembled (stress-free). The hub hinge starts folded by `fold_deg` so the grid moves.
pub fn grid(rows: usize, cols: usize, p: &Params) -> String {
    let mut s = String::new();
    header(&mut s, &format!("{rows} x {cols} grid of panels, {} loop hinges", (rows - 1) * (cols - 1)), p);
    // Square panels here: length = width = panel_length.
    let q = Params { panel_width: p.panel_length, ..p.clone() };
    let name = |i: usize, j: usize| format!("p{i}_{j}");
    for i in 0..rows {
        for j in 0..cols {
            panel(&mut s, &name(i, j), &q);
        }
    }
    let half = 0.5 * p.panel_length;
    hinge(&mut s, "hub_p0_0", "hub", &name(0, 0), "{ position = [1.0, 0.0, 0.0] }", [half, 0.0, 0.0], p);
    let mut loops = 0;
    for i in 0..rows {
        for j in 0..cols {
            // Along x (next row): fold axis z, A0 at the panel's +x edge.
            if i + 1 < rows {
                let a0 = if j == 0 { format!("{{ position = [{half:?}, 0.0, 0.0] }}") } else { "\"assembled\"".into() };
                loops += usize::from(j > 0);
                hinge(&mut s, &format!("hx{i}_{j}"), &name(i, j), &name(i + 1, j), &a0, [half, 0.0, 0.0], p);
            }
            // Along y (next column): fold axis x, frames yawed 90° so the fold is still A's z.
            if j + 1 < cols {
                let a0 = format!("{{ position = [0.0, {half:?}, 0.0], yaw_deg = 90.0 }}");
                let body = format!(
                    "[[hinge]]\nname = \"hy{i}_{j}\"\nparent = \"{}\"\nchild = \"{}\"\na0 = {}\na = {{ child_com = [{half:?}, 0.0, 0.0], yaw_deg = -90.0 }}\nlaw = {{ type = \"euler-potential\", k_f = {:e}, k_theta = [{:e}, {:e}, {:e}] }}\n",
                    name(i, j),
                    name(i, j + 1),
                    a0,
                    p.k_translation,
                    p.k_bending,
                    p.k_bending,
                    p.k_fold
                );
                s.push_str(&body);
                s.push('\n');
            }
        }
    }
    debug_assert_eq!(loops, (rows - 1) * (cols - 1));
    let _ = writeln!(s, "[initial.hinge.hub_p0_0]\nyaw_deg = {:?}\n", p.fold_deg);
    s
}
