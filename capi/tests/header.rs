//! include/foldsim.h is what cbindgen writes from the library's source today: a change to
//! the C API that did not regenerate the header fails here. `FOLDSIM_WRITE_HEADER=1 cargo
//! test -p foldsim-c --test header` writes it.

use std::path::Path;

#[test]
fn header_is_current() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("capi/cbindgen.toml reads");
    let mut written = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen reads capi/src")
        .write(&mut written);
    let header = crate_dir.join("../include/foldsim.h");
    if std::env::var_os("FOLDSIM_WRITE_HEADER").is_some() {
        std::fs::write(&header, &written).expect("include/foldsim.h is writable");
    }
    let committed = std::fs::read(&header).unwrap_or_default();
    assert!(
        committed == written,
        "include/foldsim.h is not what cbindgen writes from capi/src/lib.rs: run FOLDSIM_WRITE_HEADER=1 cargo test -p foldsim-c --test header"
    );
}
