//! Embeds the default model, basis and depth lifter from `fixtures/` when they exist; otherwise embeds empty
//! files so that the crate still builds (the library then reports that no default is embedded).

use std::path::Path;

fn main() {
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR for build scripts");
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    for name in [
        "default-model.bin",
        "default-basis.bin",
        "default-lifter.bin",
        "default-lifter-midpoints.bin",
    ] {
        let source = Path::new(&manifest).join("../../fixtures").join(name);
        println!("cargo:rerun-if-changed={}", source.display());
        let bytes = std::fs::read(&source).unwrap_or_default();
        std::fs::write(Path::new(&out).join(name), bytes).expect("OUT_DIR is writable");
    }
}
