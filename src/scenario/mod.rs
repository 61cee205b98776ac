//! Scenario files (TOML): bodies, hinges, laws, initial state and run settings.
//!
//! Every key, its unit and its frame are documented in `docs/scenario.md`. Errors name the
//! file, the line and column, and the key, and say what would be valid.
//!
//! - [`build`]: [`Scenario`], read and checked into a model, initial conditions and settings;
//! - `raw`: the file's structure as read; `values` and `laws`: its values and hinge laws;
//! - [`edit`]: [`ScenarioText`], a scenario's values changed by key path before it is built;
//! - [`error`]: [`ScenarioError`], located by file, line, column and key.

mod actuators;
mod bodies;
pub mod build;
mod contact;
pub mod edit;
pub mod error;
mod law_file;
mod laws;
mod loads;
mod raw;
mod values;

pub use build::Scenario;
pub use edit::{ScenarioText, SetValue};
pub use error::ScenarioError;
pub use law_file::law_from_toml;

#[cfg(test)]
use std::path::Path;

/// The shipped example `file` (in `examples/`) with the lines whose key is in `keys` replaced
/// by `key = value`: for tests that vary one example.
#[cfg(test)]
pub(crate) fn example_with(file: &str, keys: &[&str], value: &str) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join(file)).expect("example exists");
    let text: String = text
        .lines()
        .map(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            if keys.contains(&key) { format!("{key} = {value}") } else { l.to_string() }
        })
        .collect::<Vec<_>>()
        .join("\n");
    Scenario::from_toml_in(&text, file, &dir).expect("variant is valid")
}
