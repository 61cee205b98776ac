//! A hinge law on its own (docs/fit.md, *A law alone*): a TOML file whose `law` key holds a
//! law table exactly as a hinge's `law` does, its table files relative to the file. What
//! `foldsim fit --law` fits to a bench test; checked as a scenario's law would be, with errors
//! located in the file's own lines.

use super::error::{Ctx, ScenarioError};
use super::laws::law;
use super::raw::RawLaw;
use crate::law::HingeLaw;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLawFile {
    /// A label (optional).
    #[allow(dead_code)]
    title: Option<String>,
    law: Spanned<RawLaw>,
}

/// The law in `text` (labelled `file` in errors, its table files read from `base`), and the
/// files it read (the tables).
pub fn law_from_toml(text: &str, file: &str, base: &Path) -> Result<(Box<dyn HingeLaw>, Vec<PathBuf>), ScenarioError> {
    let ctx = Ctx { file, text, base, inputs: Default::default(), warnings: Default::default() };
    let raw: RawLawFile = super::build::parse_toml(&ctx)?;
    let name = Path::new(file).file_stem().map_or_else(|| "law".to_string(), |s| s.to_string_lossy().into_owned());
    let built = law(&ctx, &name, &raw.law)?;
    let inputs = ctx.inputs.borrow().clone();
    Ok((built, inputs))
}
