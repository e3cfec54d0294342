//! Shared helpers for the physics tests: uniform tubes, constrained eigen-solutions, state matrices.
#![allow(dead_code)]

use nalgebra::DMatrix;
use rotorsweep::rotor::fe::{Material, RotorSpec, SectionSpec, SegmentSpec};

/// Structural steel of physics.md §10.
pub const STEEL: Material = Material {
    youngs_modulus: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A uniform tube of `length` [m], outer/inner diameter [m], `n` elements, from z = 0.
pub fn tube(length: f64, outer: f64, inner: f64, n: usize) -> RotorSpec {
    RotorSpec {
        z_start: 0.0,
        segments: vec![SegmentSpec {
            length,
            section: SectionSpec::Tube { outer, inner },
            elements: n,
            material: STEEL,
        }],
        disks: Vec::new(),
        point_masses: Vec::new(),
        named_points: Vec::new(),
        balancing: None,
    }
}

/// Keeps the rows and columns of `keep`.
pub fn restrict(a: &DMatrix<f64>, keep: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(keep.len(), keep.len(), |i, j| a[(keep[i], keep[j])])
}

/// Natural frequencies [Hz] of K, M restricted to the DOFs not in `fixed`, ascending.
pub fn frequencies(k: &DMatrix<f64>, m: &DMatrix<f64>, fixed: &[usize]) -> Vec<f64> {
    let keep: Vec<usize> = (0..k.nrows()).filter(|i| !fixed.contains(i)).collect();
    let eig = rotorsweep::numerics::eigen::generalized_symmetric(
        &restrict(k, &keep),
        &restrict(m, &keep),
    )
    .expect("eigen-solution");
    eig.values
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// First-order state matrix [[0, I], [−M⁻¹K, −M⁻¹C]].
pub fn state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let minv = m.clone().cholesky().expect("M positive definite").inverse();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-&minv * k));
    a.view_mut((n, n), (n, n)).copy_from(&(-&minv * c));
    a
}

/// Inverse of the state matrix, [[−K⁻¹C, −K⁻¹M], [I, 0]] (K must be non-singular).
pub fn inverse_state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let lu = k.clone().lu();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, 0), (n, n))
        .copy_from(&(-lu.solve(c).expect("K non-singular")));
    a.view_mut((0, n), (n, n))
        .copy_from(&(-lu.solve(m).expect("K non-singular")));
    a.view_mut((n, 0), (n, n)).fill_with_identity();
    a
}

/// A scene from TOML text; `name` anchors relative paths (a bare name: the crate root).
pub fn scene_from_text(name: &str, text: &str) -> rotorsweep::scene::Scene {
    rotorsweep::scene::Scene::from_text(std::path::Path::new(name), text, &[])
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The samples of the channel `name` of a job result.
pub fn channel<'a>(r: &'a rotorsweep::dynamics::simulation::JobResult, name: &str) -> &'a [f64] {
    &r.channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| {
            let names: Vec<&str> = r.channels.iter().map(|c| c.name.as_str()).collect();
            panic!("no channel `{name}` (have: {})", names.join(", "))
        })
        .data
}

/// Amplitude of the line at `f` [Hz] in `x` sampled at `fs` [Hz]: mean removed, periodic Hann
/// window, amplitude-correct scaling 2|Σ wₙ xₙ e^{−i2πf n/fs}| / Σ wₙ (physics.md §8). Exact for
/// a line on a bin of the record (record = whole number of its periods); Hann's sidelobes keep
/// the other lines' leakage small otherwise.
pub fn hann_amplitude(x: &[f64], fs: f64, f: f64) -> f64 {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let (mut re, mut im, mut wsum) = (0.0, 0.0, 0.0);
    for (i, xi) in x.iter().enumerate() {
        let w = 0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos());
        let ph = 2.0 * std::f64::consts::PI * f * i as f64 / fs;
        re += w * (xi - mean) * ph.cos();
        im -= w * (xi - mean) * ph.sin();
        wsum += w;
    }
    2.0 * (re * re + im * im).sqrt() / wsum
}

/// Least-squares slope of y against x.
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// The repository root.
pub fn repo() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh scratch folder for one test, unique per process.
pub fn scratch_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("rotorsweep-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
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
pub const JEFFCOTT_ROTOR: &str = r#"[materials.steel]
youngs_modulus_gpa = 210.0
poisson = 0.3
density_kg_m3 = 7850.0
[rotor]
[[rotor.segments]]
length_mm = 350.0
outer_diameter_mm = 30.0
elements = 8
material = "steel"
[[rotor.segments]]
length_mm = 350.0
outer_diameter_mm = 30.0
elements = 8
material = "steel"
[[rotor.disks]]
z_mm = 350.0
mass_kg = 12.331
polar_kg_m2 = 0.061654
diametral_kg_m2 = 0.033396
[rotor.nodes]
bearing_a = 0.0
bearing_b = 700.0
[[rotor.sensors]]
name = "disk"
z_mm = 350.0
[[rotor.masses]]
z_mm = 350.0
radius_mm = 100.0
angle_deg = 0.0
mass_g = 20.0
"#;

/// The first vertical and horizontal bending frequencies [Hz] of a scene's model on its
/// linearised supports at standstill, as `rotorsweep modes` reports them.
pub fn first_bending_hz(
    scene: &rotorsweep::scene::Scene,
    model: &rotorsweep::dynamics::model::Model,
) -> (f64, f64) {
    use rotorsweep::dynamics::LinearSystem;
    use rotorsweep::rotor::reduction::ModeKind;
    let modes = LinearSystem::of_scene(scene, model)
        .expect("linear supports")
        .standstill_modes()
        .expect("eigen-solution");
    let first = |k: ModeKind| {
        modes
            .iter()
            .find(|m| m.kind == k && m.freq_hz > 1.0)
            .expect("a bending mode")
            .freq_hz
    };
    (first(ModeKind::BendingY), first(ModeKind::BendingX))
}

/// The Jeffcott rotor's mounting (check 7): stiff isotropic bearings (1e9 N/m, 30 times the
/// shaft's 48EI/L³), a stationary damper `c` [Ns/m] at the disk, the drive's axial spring, the
/// reduction and the modal damping, as scene text.
pub fn jeffcott_mounting(c: f64) -> String {
    format!(
        r#"[[supports]]
node = "bearing_a"
type = "linear"
spring = {{ kx_n_per_m = 1e9, ky_n_per_m = 1e9 }}
[[supports]]
node = "bearing_b"
type = "linear"
spring = {{ kx_n_per_m = 1e9, ky_n_per_m = 1e9 }}
# The Jeffcott damper: stationary, at the disk, no stiffness.
[[supports]]
node = "disk"
type = "linear"
spring = {{ kx_n_per_m = 0.0, ky_n_per_m = 0.0, cx_ns_per_m = {c}, cy_ns_per_m = {c} }}
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1e7

[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "8n+12st"
# No modal damping below 1 kHz: modal damping acts in the rotating frame, where the synchronous
# unbalance response stands still, so it would not damp it (and above the critical speed it
# destabilises the forward whirl). The stiff modes above 1 kHz keep 100 % for the integrator.
[damping]
bands = [{{ below_hz = 1000.0, ratio = 0.0 }}]
above_ratio = 1.0
"#
    )
}

/// The Jeffcott rotor's damped mounting of tests/linear_consistency.rs and linear_study.rs as
/// scene text: bearings 2e7 N/m and 2000 N·s/m on 5 kg pedestals with anisotropic ground springs
/// (3e7 / 6e7 N/m, 3000 N·s/m: elliptic orbits with a backward part), a stationary 400 N·s/m
/// damper at the disk, the drive's axial spring, 8n+12st modes.
pub const JEFFCOTT_PEDESTALS: &str = r#"[[supports]]
node = "bearing_a"
type = "linear"
spring = { kx_n_per_m = 2.0e7, ky_n_per_m = 2.0e7, cx_ns_per_m = 2000.0, cy_ns_per_m = 2000.0 }
mass_kg = 5.0
ground = { kx_n_per_m = 3.0e7, ky_n_per_m = 6.0e7, cx_ns_per_m = 3000.0, cy_ns_per_m = 3000.0 }
[[supports]]
node = "bearing_b"
type = "linear"
spring = { kx_n_per_m = 2.0e7, ky_n_per_m = 2.0e7, cx_ns_per_m = 2000.0, cy_ns_per_m = 2000.0 }
mass_kg = 5.0
ground = { kx_n_per_m = 3.0e7, ky_n_per_m = 6.0e7, cx_ns_per_m = 3000.0, cy_ns_per_m = 3000.0 }
[[supports]]
node = "disk"
type = "linear"
spring = { kx_n_per_m = 0.0, ky_n_per_m = 0.0, cx_ns_per_m = 400.0, cy_ns_per_m = 400.0 }
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1e7
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "8n+12st"
"#;

/// Campaign options for a test: `out`, two threads, no resume, overwrite, shard or shared
/// references.
pub fn run_options(out: &std::path::Path) -> rotorsweep::study::campaign::RunOptions {
    rotorsweep::study::campaign::RunOptions {
        output: out.to_path_buf(),
        threads: 2,
        resume: false,
        overwrite: false,
        shard: None,
        command: "test".into(),
        references: Default::default(),
    }
}

/// The deterministic content of a results file: every dataset of every run (bit patterns) and
/// the runs' attributes other than timings, by path.
pub fn results_content(path: &std::path::Path) -> Vec<(String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap();
    let mut out = Vec::new();
    for group in ["jobs", "references"] {
        let Ok(g) = f.group(group) else { continue };
        let mut ids = g.member_names().unwrap();
        ids.sort();
        for id in ids {
            let run = g.group(&id).unwrap();
            fn walk(g: &hdf5::Group, prefix: &str, out: &mut Vec<(String, Vec<u64>)>) {
                let mut names = g.member_names().unwrap();
                names.sort();
                for n in names {
                    let p = format!("{prefix}/{n}");
                    if let Ok(ds) = g.dataset(&n) {
                        let v: Vec<f64> = ds.read_raw().unwrap();
                        out.push((p, v.iter().map(|x| x.to_bits()).collect()));
                    } else if let Ok(sub) = g.group(&n) {
                        walk(&sub, &p, out);
                    }
                }
            }
            walk(&run, &format!("{group}/{id}"), &mut out);
            let mut attrs = run.attr_names().unwrap();
            attrs.sort();
            for a in attrs {
                if a.starts_with("cpu_time_s") || a.starts_with("wall_time_s") {
                    continue;
                }
                let v = match rotorsweep::store::read_param(&run, &a).unwrap() {
                    rotorsweep::store::Param::Number(x) => vec![x.to_bits()],
                    rotorsweep::store::Param::Count(n) => vec![n],
                    rotorsweep::store::Param::Text(t) => t.bytes().map(u64::from).collect(),
                };
                out.push((format!("{group}/{id}@{a}"), v));
            }
        }
    }
    out
}

/// A fresh, empty directory of this test process under the system temp dir, named after the
/// test binary.
pub fn scratch(name: &str) -> std::path::PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "rotorsweep-{}-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
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

/// The stiff Jeffcott rotor of tests/linear_jeffcott.rs and tests/runup.rs as scene text: a
/// steel cylinder Ø200 × 400 mm (bending above 1 kHz) with 10 g at r = 100 mm, 30°, at its
/// centre, on two linear supports with `spring` (TOML inline-table body) and `extra` support
/// lines at both ends; `tail` is appended (further sections).
pub fn stiff_jeffcott(spring: &str, extra: &str, tail: &str) -> String {
    format!(
        r#"name = "stiff-jeffcott"
[materials.steel]
youngs_modulus_gpa = 210.0
poisson = 0.3
density_kg_m3 = 7850.0
[rotor]
[[rotor.segments]]
length_mm = 400.0
outer_diameter_mm = 200.0
elements = 4
material = "steel"
[rotor.nodes]
bearing_a = 0.0
bearing_b = 400.0
[[rotor.sensors]]
name = "centre"
z_mm = 200.0
[[rotor.masses]]
z_mm = 200.0
radius_mm = 100.0
angle_deg = 30.0
mass_g = 10.0
[[supports]]
node = "bearing_a"
type = "linear"
spring = {{ {spring} }}
{extra}
[[supports]]
node = "bearing_b"
type = "linear"
spring = {{ {spring} }}
{extra}
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1.0e7
[damping]
bands = []
above_ratio = 0.0
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "12n+12st"
{tail}
"#
    )
}

/// Runs the rotorsweep binary with `args` and returns its standard output; panics with its
/// standard error when it fails.
pub fn rotorsweep_ok(args: &[&str]) -> Vec<u8> {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rotorsweep {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// `rotorsweep report FILE --table NAME --format json`: the one table of that name.
pub fn report_table(file: &std::path::Path, name: &str) -> serde_json::Value {
    let out = rotorsweep_ok(&[
        "report",
        file.to_str().unwrap(),
        "--table",
        name,
        "--format",
        "json",
    ]);
    let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
    doc["tables"][0].clone()
}

/// The damped oscillator m q̈ = −m(ω² q + 2ζω q̇), ω = 2π·10 Hz, ζ = 2 %, of mass `mass` [kg]
/// (a mass other than 1 exercises M⁻¹): a smooth problem with a closed form
/// ([`Oscillator::exact`]), free of a rotor's stiff spectrum, for the integrator tests.
pub struct Oscillator {
    m: nalgebra::DMatrix<f64>,
    mass: f64,
    w: Vec<f64>,
}

impl Oscillator {
    pub const OMEGA: f64 = 2.0 * std::f64::consts::PI * 10.0;
    pub const ZETA: f64 = 0.02;

    pub fn new(mass: f64) -> Self {
        Self {
            m: nalgebra::DMatrix::from_element(1, 1, mass),
            mass,
            w: vec![1.0],
        }
    }

    /// Free decay from q(0) = q0, q̇(0) = 0: q = q0 e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t),
    /// ω_d = ω√(1 − ζ²) (any vibrations text, e.g. Rao, Mechanical Vibrations, §2.6).
    pub fn exact(q0: f64, t: f64) -> f64 {
        let (w, z) = (Self::OMEGA, Self::ZETA);
        let wd = w * (1.0 - z * z).sqrt();
        q0 * (-z * w * t).exp() * ((wd * t).cos() + z * w / wd * (wd * t).sin())
    }
}

impl rotorsweep::integrators::SecondOrder for Oscillator {
    fn n(&self) -> usize {
        1
    }
    fn mass(&self) -> &nalgebra::DMatrix<f64> {
        &self.m
    }
    fn force(
        &self,
        _t: f64,
        q: &nalgebra::DVector<f64>,
        v: &nalgebra::DVector<f64>,
        out: &mut nalgebra::DVector<f64>,
    ) {
        let (w, z) = (Self::OMEGA, Self::ZETA);
        out[0] = -self.mass * (w * w * q[0] + 2.0 * z * w * v[0]);
    }
    fn newton_matrix(
        &self,
        _t: f64,
        _q: &nalgebra::DVector<f64>,
        _v: &nalgebra::DVector<f64>,
        (a, b, c): (f64, f64, f64),
        out: &mut nalgebra::DMatrix<f64>,
    ) {
        let (m, w, z) = (self.mass, Self::OMEGA, Self::ZETA);
        out[(0, 0)] = a * m + b * m * w * w + c * m * 2.0 * z * w;
    }
    fn weights(&self) -> &[f64] {
        &self.w
    }
}

/// Solver settings for the integrator tests on small systems: `integrator` at `tolerance` [m]
/// and `hmax` [s], hmin 1e-12 s, h0 1e-6 s, orders up to 5, ρ∞ 0.8, error-controlled, 10⁶ steps,
/// no CPU budget, no event location.
pub fn solver(
    integrator: rotorsweep::integrators::IntegratorKind,
    tolerance: f64,
    hmax: f64,
) -> rotorsweep::integrators::SolverSettings {
    rotorsweep::integrators::SolverSettings {
        integrator,
        tolerance,
        hmax,
        hmin: 1e-12,
        h0: 1e-6,
        max_order: 5,
        rho_inf: 0.8,
        fixed_step: false,
        max_steps: 1_000_000,
        cpu_budget: None,
        contact_events: false,
    }
}
