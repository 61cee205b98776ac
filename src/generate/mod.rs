//! Structure generators: scenario files for families of structures (docs/architecture.md: generators
//! write scenarios; nothing downstream knows who wrote one).
//!
//! - [`zfold()`]: a z-folded chain of N panels off the hub, stowed with alternating folds.
//! - [`sheet::sheet_scenario`]: any folded sheet from its nodes in the deployed and stowed
//!   states and its panels (the flasher's builder).
//! - [`flasher::flasher_scenario`]: a flasher (a disc wrapped round a polygonal hub) from its
//!   gores and rings, through the sheet builder.
//! - [`flasher_report`]: the flasher generator's report.
//! - [`crease`]: a crease's hinge law as the sheet builder writes it (a thick crease's stop at
//!   flat).
//! - [`options`]: the generators' options, defaults and checks, shared by the command line
//!   and the Python package.
//! - [`grid()`]: an R × C grid of panels, each hinged to its neighbours along both grid
//!   directions, the corner panel to the hub: (R−1)(C−1) hinges close loops.
//!
//! Every hinge uses law 2 (Euler potential) about its fold axis (A's z axis): stiff in the
//! five other directions, soft in the fold, as real hinges are.

pub mod crease;
mod cuts;
pub mod flasher;
pub mod flasher_report;
pub mod grid;
pub mod options;
pub mod params;
pub mod sheet;
pub mod zfold;

pub use grid::grid;
pub use params::{MAX_PANELS, Params, RunText};
pub use zfold::zfold;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    #[test]
    fn generated_scenarios_parse_with_the_expected_topology() {
        let p = Params::default();
        let z = Scenario::from_toml(&zfold(16, &p), "zfold").unwrap();
        assert_eq!(z.model.bodies.len(), 17);
        assert!(z.model.is_tree_hinge.iter().all(|t| *t));
        let g = Scenario::from_toml(&grid(4, 5, &p), "grid").unwrap();
        assert_eq!(g.model.bodies.len(), 21);
        let loops = g.model.is_tree_hinge.iter().filter(|t| !**t).count();
        assert_eq!(loops, 3 * 4, "(rows−1)(cols−1) loop hinges");
    }
}
