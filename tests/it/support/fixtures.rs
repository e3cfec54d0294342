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

/// The trial-mass study of tests/it/balancing.rs written into `dir` (`scene.toml` and
/// `study.toml`, named `name`): the stiff Jeffcott rotor on 1e5 N/m, 450 N·s/m supports with
/// sensors at `sensor_z_mm` (named a, b, …), its own 10 g at r = 100 mm, 30°, z = 200 mm; a
/// reference run and trials of 50 g at 0° at z = 100 and 300 mm; 5 and 9 Hz; 1× analysed
/// against the reference. Returns the study's path.
pub fn trial_mass_study(
    dir: &std::path::Path,
    name: &str,
    sensor_z_mm: &[f64],
) -> std::path::PathBuf {
    let spring = "kx_n_per_m = 1e5, ky_n_per_m = 1e5, cx_ns_per_m = 450.0, cy_ns_per_m = 450.0";
    let run_keys = "[speed]\nhz = 5.0\n[simulation]\nt_end_s = 6.0\nsettle_s = 3.0\n\
                    sample_rate_hz = 500.0\ngravity_m_s2 = 0.0\nstatic_start = false\n\
                    [solver]\nhmax = 1e-3\ntolerance = 1e-9\n";
    // Sensors belong to [rotor], so before the first support.
    let text = stiff_jeffcott(spring, "", run_keys);
    let (head, rest) = text.split_once("[[supports]]").unwrap();
    let sensors: String = sensor_z_mm
        .iter()
        .zip('a'..)
        .map(|(z, n)| format!("[[rotor.sensors]]\nname = \"{n}\"\nz_mm = {z:?}\n"))
        .collect();
    write_file(
        dir,
        "scene.toml",
        &format!("{head}{sensors}[[supports]]{rest}"),
    );
    let own = "{ z_mm = 200.0, radius_mm = 100.0, angle_deg = 30.0, mass_g = 10.0 }";
    let trial =
        |z: u32| format!("{{ z_mm = {z}.0, radius_mm = 100.0, angle_deg = 0.0, mass_g = 50.0 }}");
    let study = format!(
        "name = \"{name}\"\nscene = \"scene.toml\"\n[[axes]]\nkey = \"rotor.masses\"\n\
         values = [[{own}], [{own}, {}], [{own}, {}]]\n\
         labels = [\"reference\", \"trial a\", \"trial b\"]\n[[axes]]\nkey = \"speed.hz\"\n\
         values = [5.0, 9.0]\n[analysis]\nbaseline = \"reference\"\norders = [1.0]\n",
        trial(100),
        trial(300)
    );
    write_file(dir, "study.toml", &study)
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

/// Asserts that the input error `e` names the file `path`, the key `key`, the line of `text`
/// that reads `line`, and a reason containing `reason`.
pub fn assert_error_at(
    e: &rotorsweep::error::InputError,
    path: &std::path::Path,
    text: &str,
    (key, line, reason): (&str, &str, &str),
) {
    assert_eq!(e.file, path, "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert_eq!(e.line, Some(line_number(text, line)), "{e}");
    assert!(e.reason.contains(reason), "{e}");
}

/// The lobed two-roll machine of tests/it/nip_runout.rs: two stiff Jeffcott rotors
/// ([`stiff_jeffcott`]), one above the other (200 mm apart), each on two supports of stiffness
/// `k` [N/m] and damping `c` [Ns/m], coupled over 400 mm by a linear nip of total stiffness
/// `kc` [N/m] and damping `cn` [Ns/m] in 10 segments; roll a at `fa` [Hz] with 3 lobes of
/// 10 µm (phase 0.4 rad), roll b at its own `fb` [Hz] with 2 lobes of 6 µm (phase −1.1 rad); no
/// gravity; 1 s recorded from 1.5 s at 2000 Hz, tolerance 1e-10, hmax 2e-4.
pub struct LobedNip {
    pub k: f64,
    pub c: f64,
    pub kc: f64,
    pub cn: f64,
    pub fa: f64,
    pub fb: f64,
}

/// The values of tests/it/nip_runout.rs.
pub const LOBED_NIP: LobedNip = LobedNip {
    k: 1.0e6,
    c: 1.0e3,
    kc: 1.0e6,
    cn: 2.0e3,
    fa: 5.0,
    fb: 9.0,
};

impl LobedNip {
    /// Writes its rolls' scenes and the machine file into `dir`; the machine file's path.
    pub fn write(&self, dir: &std::path::Path) -> std::path::PathBuf {
        let (k, c) = (self.k, self.c);
        let spring = format!(
            "kx_n_per_m = {k:e}, ky_n_per_m = {k:e}, cx_ns_per_m = {c:e}, cy_ns_per_m = {c:e}"
        );
        // Record 1 s from 1.5 s: the start's transient decays at c/m ≈ 10 1/s (e^−15 by then).
        let run_keys = "[simulation]\nt_end_s = 2.5\nsettle_s = 1.5\nsample_rate_hz = 2000.0\n\
                        gravity_m_s2 = 0.0\n[solver]\ntolerance = 1e-10\nhmax = 2e-4\n";
        let a = format!("[speed]\nhz = {}\n{run_keys}", self.fa);
        write_file(dir, "a.toml", &stiff_jeffcott(&spring, "", &a));
        let b = format!("[speed]\nhz = {}\n", self.fb);
        write_file(dir, "b.toml", &stiff_jeffcott(&spring, "", &b));
        // k_c and c_n over the 400 mm, per length.
        let text = format!(
            "name = \"runout\"\n\
             [[rolls]]\nname = \"a\"\nscene = \"a.toml\"\nposition_mm = [0.0, 0.0]\n\
             roundness = [{{ order = 3, amplitude_um = 10.0, phase_rad = 0.4 }}]\n\
             [[rolls]]\nname = \"b\"\nscene = \"b.toml\"\nposition_mm = [0.0, 200.0]\n\
             roundness = [{{ order = 2, amplitude_um = 6.0, phase_rad = -1.1 }}]\n\
             [[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\n\
             to_mm = 400.0\nsegments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = {:e}\n\
             damping_ns_per_m2 = {:e}\n",
            self.kc / 0.4,
            self.cn / 0.4
        );
        write_file(dir, "machine.toml", &text)
    }
}
