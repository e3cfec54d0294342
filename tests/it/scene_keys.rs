//! The key reference: `docs/scene-keys.md` lists every key the scene parser accepts and nothing
//! else, and is the current output of `rotorsweep keys` (regenerate it with
//! `rotorsweep keys > docs/scene-keys.md` after adding a key and its line in
//! `src/scene/keys_docs.rs`).

use std::path::Path;
use std::process::Command;

use rotorsweep::scene::keys;

#[test]
fn every_accepted_key_is_documented_and_every_documented_key_accepted() {
    let missing = keys::undocumented();
    assert!(
        missing.is_empty(),
        "keys the parser accepts without a line in src/scene/keys_docs.rs: {missing:?}"
    );
    let unknown = keys::unknown_docs();
    assert!(
        unknown.is_empty(),
        "lines in src/scene/keys_docs.rs for keys the parser does not accept: {unknown:?}"
    );
    // The schema walk finds the keys a user meets first, the cross-coupled springs and the
    // speed-dependent ones among them.
    let accepted: Vec<String> = keys::accepted().into_iter().map(|(k, _)| k).collect();
    for k in [
        "extends",
        "roll.shell.length_mm",
        "roll.sensors[].z_mm",
        "supports[].spring.kxy_n_per_m",
        "supports[].spring.cyx_ns_per_m",
        "supports[].spring_by_speed[].spring.kyx_n_per_m",
        "supports[].ground.cxy_ns_per_m",
        "damping.bands[].ratio",
        "materials.<name>.poisson",
    ] {
        assert!(
            accepted.iter().any(|a| a == k),
            "{k} not found by the schema walk"
        );
    }
}

#[test]
fn the_shipped_reference_is_current() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shipped =
        std::fs::read_to_string(root.join("docs/scene-keys.md")).expect("docs/scene-keys.md");
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("keys")
        .output()
        .expect("run rotorsweep keys");
    assert!(out.status.success());
    let printed = String::from_utf8(out.stdout).unwrap();
    assert_eq!(printed, keys::markdown());
    assert!(
        shipped == printed,
        "docs/scene-keys.md is not what `rotorsweep keys` prints: regenerate it with \
         `rotorsweep keys > docs/scene-keys.md`"
    );
    // Every row names a type from the schema (no key without one).
    let rows: Vec<&str> = shipped.lines().filter(|l| l.starts_with("| `")).collect();
    assert_eq!(rows.len(), keys::DOCS.len() + keys::MACHINE_DOCS.len());
    assert!(rows.iter().all(|r| !r.contains("| ? |")));
}
