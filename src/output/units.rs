//! The unit of each output column (docs/outputs.md), for plots and the viewer's legend.

/// The unit of an output column, from its name (the catalogue's naming: docs/outputs.md);
/// empty if the name is not one of foldsim's.
pub fn unit_of(column: &str) -> &'static str {
    let ends = |suffixes: &[&str]| suffixes.iter().any(|s| column.ends_with(s));
    let xyz = |stem: &str| ["x", "y", "z"].iter().any(|a| column.ends_with(&format!("{stem}_{a}")));
    if column == "t" {
        "s"
    } else if ends(&["_yaw", "_pitch", "_roll"]) {
        "rad"
    } else if xyz("_F") && !column.starts_with("R_") {
        "N"
    } else if xyz("_M") {
        "N·m"
    } else if xyz("_delta_rate") || xyz("_v") {
        "m/s"
    } else if xyz("_wrel") || xyz("_w") || (column.starts_with("w_B_") && xyz("w_B")) {
        "rad/s"
    } else if xyz("_delta") || xyz("_R") || xyz("R_B") || xyz("Rc") {
        "m"
    } else if xyz("P") && column.len() == 3 {
        "kg·m/s"
    } else if xyz("H") && column.len() == 3 {
        "kg·m²/s"
    } else if ["T", "V", "E", "D"].contains(&column) {
        "J"
    } else if column == "spin_rate" {
        "rad/s"
    } else if column == "I_spin" {
        "kg·m²"
    } else if column == "radius" || column == "penetration_max" {
        "m"
    } else if column == "contact_force_max" {
        "N"
    } else if column == "contacts" {
        "pairs"
    } else if column == "deployed" {
        "of the design radius"
    } else if column == "W" {
        "J"
    } else if column == "pointing_error" {
        "rad"
    } else if xyz("L_req") || (xyz("L") && column.len() == 3) || column.ends_with("_torque") {
        "N·m"
    } else if column.ends_with("_speed") {
        "rad/s"
    } else if column.ends_with("_h") {
        "N·m·s"
    } else if column.ends_with("_effort") {
        "N·m (N along x, y, z)"
    } else {
        ""
    }
}
