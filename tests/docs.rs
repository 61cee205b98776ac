//! The repository stands on its own: what a user reads (README, docs/, the examples, the
//! code's messages and comments) names no file a clone lacks, and every relative link in the
//! README and docs/ leads to a file that exists.

mod common;

use std::path::{Path, PathBuf};

/// Every file under `dir` with one of `exts`.
fn files(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            files(&p, exts, out);
        } else if p.extension().is_some_and(|x| exts.iter().any(|e| x == *e)) {
            out.push(p);
        }
    }
}

fn read_files() -> Vec<(PathBuf, String)> {
    let mut paths = vec![common::repo("README.md")];
    files(&common::repo("docs"), &["md"], &mut paths);
    files(&common::repo("src"), &["rs"], &mut paths);
    files(&common::repo("examples"), &["toml"], &mut paths);
    paths.into_iter().map(|p| (p.clone(), std::fs::read_to_string(&p).unwrap())).collect()
}

/// The design notes the project grew from live outside the repository; users never see them.
#[test]
fn nothing_points_outside_the_repository() {
    let mut found = Vec::new();
    for (path, text) in read_files() {
        for (n, line) in text.lines().enumerate() {
            // Upper case: the repository's own account is docs/model.md.
            let outside =
                ["MODEL.md", "DESIGN.md", "FLASHER.md", "CRATES.md", "../shared", "shared/reference", "shared/tools"];
            if outside.iter().any(|o| line.contains(o)) {
                found.push(format!("{}:{}: {line}", path.display(), n + 1));
            }
        }
    }
    assert!(found.is_empty(), "references to files outside the repository:\n{}", found.join("\n"));
}

/// Markdown links `[…](relative/path)` and image links in the README and docs/ resolve.
#[test]
fn relative_links_resolve() {
    let mut broken = Vec::new();
    for (path, text) in read_files().into_iter().filter(|(p, _)| p.extension().is_some_and(|e| e == "md")) {
        let dir = path.parent().unwrap();
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            let target = &after[..end];
            rest = &after[end..];
            if target.starts_with("http") || target.starts_with('#') || target.contains(' ') {
                continue;
            }
            let file = target.split('#').next().unwrap();
            if !dir.join(file).exists() {
                broken.push(format!("{}: {target}", path.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}
