//! Fixtures: scene and study texts the tests build on (the Jeffcott rotor and its mountings as
//! files in tests/fixtures/, the stiff Jeffcott rotor, a study on the reference roll), the
//! repository root, and small text helpers.

/// The repository root.
pub fn repo() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scene from TOML text; `name` anchors relative paths (a bare name: the crate root).
pub fn scene_from_text(name: &str, text: &str) -> rotorsweep::scene::Scene {
    rotorsweep::scene::Scene::from_text(std::path::Path::new(name), text, &[])
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A study text on the reference roll with the given body (short runs: these test the engine).
pub fn study_text(body: &str) -> String {
    let scene = repo().join("studies/scenes/reference-roll.toml");
    format!(
        "name = \"t\"\nscene = {:?}\n[set]\n\"simulation.t_end_s\" = 0.1\n\"simulation.settle_s\" = 0.05\n{body}",
        scene.display().to_string()
    )
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write_file(dir: &std::path::Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The Jeffcott rotor of studies/scenes/jeffcott.toml as scene text: steel shaft Ø30 × 700 mm in
/// 16 elements, central disk 12.331 kg (Ø200 × 50 mm), bearings named at both ends, a sensor at
/// the disk and a 20 g unbalance at 100 mm on it; the tests add supports and run keys.
pub const JEFFCOTT_ROTOR: &str = include_str!("../../fixtures/jeffcott-rotor.toml");

/// The Jeffcott rotor's mounting (check 7): stiff isotropic bearings (1e9 N/m, 30 times the
/// shaft's 48EI/L³), a stationary damper `c` [Ns/m] at the disk, the drive's axial spring, the
/// reduction and the modal damping, as scene text.
pub fn jeffcott_mounting(c: f64) -> String {
    include_str!("../../fixtures/jeffcott-mounting.toml").replace("{c}", &c.to_string())
}

/// The Jeffcott rotor's damped mounting of tests/it/linear_consistency.rs and linear_study.rs as
/// scene text: bearings 2e7 N/m and 2000 N·s/m on 5 kg pedestals with anisotropic ground springs
/// (3e7 / 6e7 N/m, 3000 N·s/m: elliptic orbits with a backward part), a stationary 400 N·s/m
/// damper at the disk, the drive's axial spring, 8n+12st modes.
pub const JEFFCOTT_PEDESTALS: &str = include_str!("../../fixtures/jeffcott-pedestals.toml");

/// The stiff Jeffcott rotor of tests/it/linear_jeffcott.rs and tests/it/runup.rs as scene text: a
/// steel cylinder Ø200 × 400 mm (bending above 1 kHz) with 10 g at r = 100 mm, 30°, at its
/// centre, on two linear supports with `spring` (TOML inline-table body) and `extra` support
/// lines at both ends; `tail` is appended (further sections).
pub fn stiff_jeffcott(spring: &str, extra: &str, tail: &str) -> String {
    include_str!("../../fixtures/stiff-jeffcott.toml")
        .replace("{spring}", spring)
        .replace("{extra}", extra)
        .replace("{tail}", tail)
}

/// 1-based line of the one line that reads exactly `line` (after trimming).
pub fn line_number(text: &str, line: &str) -> usize {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == line)
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(hits.len(), 1, "`{line}` must occur on exactly one line");
    hits[0]
}
