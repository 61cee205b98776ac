//! Output paths, checked before anything runs and written atomically.
//!
//! One check for every command and for Python ([`check_outputs`]): no output may be one of
//! the inputs (the scenario, its table files, the CSV read back) or another output of the
//! same command, compared as canonical paths (`./run.csv`, `sub/../run.csv` and a symbolic
//! link to it are one file); every output's directory must exist and take a new file. Files
//! are then written through `<path>.partial` and renamed ([`write_atomically`],
//! [`partial_path`]), so a command that stops part-way leaves no file that looks complete.
//! A target that exists and is not a regular file (`/dev/null`, a named pipe) is written to
//! directly and may be named more than once.

use std::path::{Path, PathBuf};

/// `<path>.partial`: where an output is written until it is complete.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    PathBuf::from(partial)
}

/// The animation's extension and format, for [`check_extension`].
pub const GLB: (&str, &str) = ("glb", "binary glTF");
/// The viewer page's.
pub const HTML: (&str, &str) = ("html", "a viewer page (HTML)");

/// Refuses an output whose name says another format than the one written (`ext`, without
/// the dot; `format` names it): `model.csv` for a NumPy archive, `out.gltf` for binary glTF.
/// A name without an extension (a device, a pipe) is taken as it is.
pub fn check_extension(flag: &str, path: &Path, ext: &str, format: &str) -> Result<(), String> {
    match path.extension().map(|e| e.to_string_lossy().to_lowercase()) {
        Some(e) if e != ext => Err(format!(
            "{flag} {}: this writes {format}, which a .{e} file is not{}; name it .{ext}",
            path.display(),
            if e == "gltf" { " (glTF JSON with its buffers apart)" } else { "" }
        )),
        _ => Ok(()),
    }
}

/// Whether `path` exists and is neither a regular file nor a directory (a device or a pipe).
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// The canonical form of a path that may not exist yet: its directory made canonical and its
/// file name appended. Errors name the path and say what is wrong with it.
fn canonical(path: &Path, what: &str) -> Result<PathBuf, String> {
    if let Ok(c) = std::fs::canonicalize(path) {
        return Ok(c);
    }
    let name = path.file_name().ok_or_else(|| format!("{what} {}: name a file, not a directory", path.display()))?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match std::fs::canonicalize(parent) {
        Ok(dir) if dir.is_dir() => Ok(dir.join(name)),
        Ok(_) => Err(format!("{what} {}: {} is not a directory", path.display(), parent.display())),
        Err(_) => Err(format!(
            "{what} {}: the directory {} does not exist (create it first, or write elsewhere)",
            path.display(),
            parent.display()
        )),
    }
}

/// Checks a command's outputs before it runs: each `(what, path)` of `outputs` (`what` names
/// it in messages, such as `--animation`) must name a file in an existing directory that can
/// be written, must not be one of `inputs`, and must not be another output. Nothing is left
/// behind by the check.
pub fn check_outputs(inputs: &[PathBuf], outputs: &[(&str, &Path)]) -> Result<(), String> {
    let inputs: Vec<(PathBuf, &PathBuf)> =
        inputs.iter().filter_map(|p| std::fs::canonicalize(p).ok().map(|c| (c, p))).collect();
    let mut seen: Vec<(PathBuf, &str, &Path)> = Vec::with_capacity(outputs.len());
    for &(what, path) in outputs {
        if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
            return Err(format!("{what} {} is a directory: name a file in it", path.display()));
        }
        let c = canonical(path, what)?;
        if let Some((_, input)) = inputs.iter().find(|(i, _)| *i == c) {
            return Err(format!(
                "{what} {} is an input of this command ({}): write the output to another file",
                path.display(),
                input.display()
            ));
        }
        if is_special(path) {
            continue;
        }
        if let Some((_, other, other_path)) = seen.iter().find(|(s, _, _)| *s == c) {
            return Err(format!(
                "{what} {} and {other} {} are the same file: give each output its own name",
                path.display(),
                other_path.display()
            ));
        }
        probe_writable(path, what)?;
        seen.push((c, what, path));
    }
    Ok(())
}

/// Creates and removes `<path>.partial` to learn, before a long run, that the file could be
/// written (permissions, a read-only file system).
fn probe_writable(path: &Path, what: &str) -> Result<(), String> {
    let partial = partial_path(path);
    let existed = partial.exists();
    match std::fs::OpenOptions::new().write(true).create(true).truncate(false).open(&partial) {
        Ok(_) => {
            if !existed {
                let _ = std::fs::remove_file(&partial);
            }
            Ok(())
        }
        Err(e) => Err(format!("{what} {}: cannot write {}: {e}", path.display(), partial.display())),
    }
}

/// Writes `bytes` to `<path>.partial`, then renames it to `path`; a device or pipe is written
/// directly. A full disk or any other write error is returned with the file's name, and the
/// partial file is removed.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), String> {
    if is_special(path) {
        return std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()));
    }
    let partial = partial_path(path);
    if let Err(e) = std::fs::write(&partial, bytes) {
        let _ = std::fs::remove_file(&partial);
        return Err(format!("cannot write {}: {e}", partial.display()));
    }
    std::fs::rename(&partial, path)
        .map_err(|e| format!("cannot rename {} to {}: {e}", partial.display(), path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_say_the_format() {
        assert!(check_extension("-o", Path::new("m.npz"), "npz", "a NumPy archive").is_ok());
        assert!(check_extension("-o", Path::new("M.NPZ"), "npz", "a NumPy archive").is_ok());
        assert!(check_extension("-o", Path::new("/dev/null"), "npz", "a NumPy archive").is_ok());
        let e = check_extension("--animation", Path::new("a.gltf"), "glb", "binary glTF").unwrap_err();
        assert!(e.contains("a.gltf") && e.contains(".glb"), "{e}");
        assert!(check_extension("-o", Path::new("model.csv"), "npz", "a NumPy archive").is_err());
    }

    #[test]
    fn spellings_of_one_file_are_one_output() {
        let dir = std::env::temp_dir().join(format!("foldsim-paths-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let input = dir.join("run.csv");
        std::fs::write(&input, "t\n0\n").unwrap();
        let other = dir.join("sub/../run.csv");
        let e = check_outputs(std::slice::from_ref(&input), &[("-o", &other)]).unwrap_err();
        assert!(e.contains("is an input"), "{e}");
        let a = dir.join("a.glb");
        let b = dir.join("sub/../a.glb");
        let e = check_outputs(&[], &[("--animation", &a), ("--view", &b)]).unwrap_err();
        assert!(e.contains("same file"), "{e}");
        let e = check_outputs(&[], &[("--animation", &dir.join("nodir/x.glb"))]).unwrap_err();
        assert!(e.contains("does not exist"), "{e}");
        let e = check_outputs(&[], &[("-o", &dir)]).unwrap_err();
        assert!(e.contains("is a directory"), "{e}");
        assert!(
            check_outputs(&[], &[("-o", &a), ("--csv", Path::new("/dev/null")), ("x", Path::new("/dev/null"))]).is_ok()
        );
        assert!(!partial_path(&a).exists(), "the check leaves nothing behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
