//! `foldsim export fmu` (docs/interop.md): what the archive holds, and every refusal in words
//! that name the argument or file. The FMU's behaviour in a host is checked through FMPy
//! (python/tests/test_interop.py) and its functions directly (fmu/tests/).

mod common;

use common::{foldsim, repo, tmp};
use std::io::Read;

fn entries(path: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    (0..zip.len())
        .map(|i| {
            let mut f = zip.by_index(i).unwrap();
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).unwrap();
            (f.name().expect("a UTF-8 name").to_string(), bytes)
        })
        .collect()
}

#[test]
fn the_archive_holds_description_binary_scenario_and_variables() {
    let dir = tmp("export", "archive");
    let out = dir.join("spin.fmu");
    let r = foldsim()
        .args(["export", "fmu"])
        .arg(repo("examples/radial-spin.toml"))
        .arg("-o")
        .arg(&out)
        .args(["--outputs", "H_*,w_B_z", "--inputs", "hub,panel1_T_z", "--parameters", "body.*.mass,hinge.*.law.*"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let files = entries(&out);
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["modelDescription.xml", "binaries/linux64/spin.so", "resources/scenario.toml", "resources/foldsim-fmu.toml"]
    );
    let text = |n: &str| String::from_utf8(files.iter().find(|(f, _)| f == n).unwrap().1.clone()).unwrap();
    let description = text("modelDescription.xml");
    let variables: foldsim::export::fmu::Variables = toml::from_str(&text("resources/foldsim-fmu.toml")).unwrap();
    assert!(description.contains(&format!("guid=\"{}\"", variables.guid)));
    assert!(description.contains("modelIdentifier=\"spin\""));
    assert_eq!(variables.outputs, ["w_B_z", "H_x", "H_y", "H_z"]);
    assert_eq!(variables.inputs, ["hub_F_x", "hub_F_y", "hub_F_z", "hub_T_x", "hub_T_y", "hub_T_z", "panel1_T_z"]);
    // Every body's mass (a body names itself in its key path) and the laws' numbers.
    assert!(variables.parameters.iter().any(|p| p.path == "body.hub.mass" && p.start == 200.0));
    assert!(variables.parameters.iter().all(|p| p.path.starts_with("body.") || p.path.starts_with("hinge.")));
    for v in variables.outputs.iter().chain(&variables.inputs) {
        assert!(description.contains(&format!("name=\"{v}\"")), "{v} is not in the description");
    }
    // The scenario travels as written; the binary is the fmu crate's library.
    assert_eq!(text("resources/scenario.toml"), std::fs::read_to_string(repo("examples/radial-spin.toml")).unwrap());
    assert!(files[1].1.starts_with(b"\x7fELF"));
}

#[test]
fn refusals_name_the_argument() {
    let dir = tmp("export", "refusals");
    let scenario = repo("examples/radial-spin.toml");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["-o".into(), dir.join("x.zip").display().to_string()], ".fmu"),
        (vec!["-o".into(), scenario.display().to_string()], "-o"),
        (
            vec!["-o".into(), dir.join("x.fmu").display().to_string(), "--inputs".into(), "nobody".into()],
            "--inputs \"nobody\"",
        ),
        (vec!["-o".into(), dir.join("x.fmu").display().to_string(), "--outputs".into(), "zz_*".into()], "--outputs"),
        (vec!["-o".into(), dir.join("x.fmu").display().to_string(), "--outputs".into(), "t".into()], "only t"),
        (
            vec!["-o".into(), dir.join("x.fmu").display().to_string(), "--parameters".into(), "run.*".into()],
            "--parameters",
        ),
        (
            vec![
                "-o".into(),
                dir.join("x.fmu").display().to_string(),
                "--library".into(),
                scenario.display().to_string(),
            ],
            "not a Linux shared library",
        ),
        (vec!["-o".into(), dir.join("no/such/dir/x.fmu").display().to_string()], "does not exist"),
    ];
    for (args, words) in cases {
        let r = foldsim().args(["export", "fmu"]).arg(&scenario).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success() && err.contains(words), "{args:?}: expected an error with {words:?}, got {err}");
        assert!(!dir.join("x.fmu").exists() && !dir.join("x.fmu.partial").exists(), "{args:?} left a file");
    }
}

#[test]
fn table_files_travel_in_the_resources_and_one_outside_is_refused() {
    let dir = tmp("export", "tables");
    let out = dir.join("latch.fmu");
    let r = foldsim()
        .args(["export", "fmu"])
        .arg(repo("examples/zfold-tape-latch.toml"))
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let files = entries(&out);
    for table in ["tape-spring-increasing.csv", "tape-spring-decreasing.csv"] {
        let (_, bytes) =
            files.iter().find(|(n, _)| *n == format!("resources/tables/{table}")).expect("the table is packed once");
        assert_eq!(bytes, &std::fs::read(repo(&format!("examples/tables/{table}"))).unwrap());
        assert_eq!(files.iter().filter(|(n, _)| n.ends_with(table)).count(), 1);
    }
    // A scenario reading a table from outside its own directory: refused, naming the file.
    std::fs::create_dir_all(dir.join("s")).unwrap();
    std::fs::create_dir_all(dir.join("tables")).unwrap();
    for table in ["tape-spring-increasing.csv", "tape-spring-decreasing.csv"] {
        std::fs::copy(repo(&format!("examples/tables/{table}")), dir.join("tables").join(table)).unwrap();
    }
    let text =
        std::fs::read_to_string(repo("examples/zfold-tape-latch.toml")).unwrap().replace("\"tables/", "\"../tables/");
    std::fs::write(dir.join("s/latch.toml"), text).unwrap();
    let r = foldsim()
        .args(["export", "fmu"])
        .arg(dir.join("s/latch.toml"))
        .arg("-o")
        .arg(dir.join("x.fmu"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && err.contains("outside its directory") && err.contains("tape-spring"), "{err}");
}
