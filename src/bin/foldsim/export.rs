//! `foldsim export fmu`: an FMI 2.0 co-simulation FMU of a scenario (docs/interop.md).

use foldsim::export::fmu::{Request, archive, model_description, model_identifier, table_files, variables};
use foldsim::output::paths::{check_extension, check_outputs, write_atomically};
use foldsim::scenario::ScenarioText;
use std::path::{Path, PathBuf};

/// The FMU's library beside this program, as `cargo build --release` leaves it.
fn default_library() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program's own path: {e}"))?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    // `cargo build` leaves it beside this program; `cargo test` only in deps/ below it: the
    // newer of the two is the one built with this program.
    let candidates = [dir.join("libfoldsim_fmu.so"), dir.join("deps").join("libfoldsim_fmu.so")];
    let modified = |p: &PathBuf| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    candidates.iter().filter(|p| p.is_file()).max_by_key(|p| modified(p)).cloned().ok_or_else(|| {
        format!(
            "the FMU's library libfoldsim_fmu.so is not beside this program ({}): build it with `cargo build --release` at the repository's root (it builds the fmu crate), or give --library",
            dir.display()
        )
    })
}

/// Writes the FMU of `scenario` to `output`.
pub fn fmu(scenario: &Path, output: &Path, request: &Request, library: Option<PathBuf>) -> Result<(), String> {
    check_extension("-o", output, "fmu", "an FMU")?;
    let text = ScenarioText::from_file(scenario).map_err(|e| e.to_string())?;
    let built = text.build().map_err(|e| e.to_string())?;
    check_outputs(&built.inputs, &[("-o", output)])?;
    let library = match library {
        Some(p) => p,
        None => default_library()?,
    };
    let bytes = std::fs::read(&library).map_err(|e| format!("--library {}: {e}", library.display()))?;
    if !bytes.starts_with(b"\x7fELF") {
        return Err(format!("--library {} is not a Linux shared library (ELF)", library.display()));
    }
    let vars = variables(&text, request)?;
    let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("foldsim");
    let id = model_identifier(stem);
    let title = built.title.clone().unwrap_or_else(|| stem.to_string());
    let description = model_description(&vars, &id, &title, built.settings.duration, built.settings.output_step);
    let base = scenario.parent().unwrap_or(Path::new(""));
    let tables = table_files(&built.inputs, base)?;
    let zip = archive(&description, &id, &bytes, &text.text(), &tables, &vars)?;
    write_atomically(output, &zip)?;
    eprintln!(
        "wrote {} ({} outputs, {} inputs, {} parameters; model identifier {id})",
        output.display(),
        vars.outputs.len(),
        vars.inputs.len(),
        vars.parameters.len()
    );
    Ok(())
}
