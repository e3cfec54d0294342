//! Stress stiffening K(Ω) = K + (Ω/Ω_ref)² ΔK of imported FE bodies (issue 23), against closed
//! forms: a thin ring spinning in its plane, modelled as an FE body off the axis (written as
//! Matrix Market files and read back by the importer, its rotating terms from its mass matrix
//! and node coordinates), whose n-lobe frequencies in the rotating frame are
//!
//! ```text
//! ω_b,f = √(ω₀² + S Ω²) ∓ 2nΩ/(n² + 1),   S = n²(n² − 1)²/(n² + 1)²,
//! ω₀² = E I n²(n² − 1)² / (ρ A R⁴ (n² + 1))
//! ```
//!
//! ω₀: the inextensional in-plane ring (Hoppe 1871; Blevins, *Formulas for Natural Frequency and
//! Mode Shape*, ch. 9, the in-plane ring). The rotating form (cf. Huang & Soedel, J. Sound Vib.
//! 115 (1987) 253–274, for a ring without foundation) follows from the inextensional mode
//! v = a cos nθ + b sin nθ, w = −∂v/∂θ with the kinetic energy ½ρAR∫[(ẇ − Ωv)² + (v̇ + Ω(R + w))²]dθ,
//! the bending energy ½EI/R³∫(w'' + w)²dθ and the hoop tension T = ρAR²Ω² acting on the rotation
//! (w' − v)/R (energy ½T/R∫(w' − v)²dθ); per ρARπ the Lagrange equations are
//! (n² + 1)ä − 4nΩḃ + [k₀ + Ω²((n² − 1)² − (n² + 1))]a = 0 and (n² + 1)b̈ + 4nΩȧ + […]b = 0,
//! k₀ = (n² + 1)ω₀², whose roots are those above. Without the hoop tension (no stress
//! stiffening) the same equations give S₀ = −(n² − 1)²/(n² + 1)²: the mean frequency would fall
//! with speed instead of rising. The split 4nΩ/(n² + 1) is Bryan's effect (G. H. Bryan, Proc.
//! Camb. Phil. Soc. 7 (1890) 101–111): the n-lobe pattern precesses against the ring at
//! 2Ω/(n² + 1), Bryan's factor.

use nalgebra::{DMatrix, SMatrix};
use rotorsweep::numerics::eigen;
use rotorsweep::rotor::import::body::{
    read_body, BodyFiles, Format, ReadBody, StressFiles, StressKind,
};
use rotorsweep::rotor::import::invariants::rotating_terms;
use rotorsweep::rotor::import::matrix_market::{format as mtx_format, Symmetry};
use rotorsweep::rotor::import::tables::Units;

use crate::support::{scratch, write_file};

const TAU: f64 = std::f64::consts::TAU;
/// Ring of steel (E, ρ), mean radius R = 0.5 m, rectangular section 20 mm wide (axial) and
/// 5 mm thick (radial): thin, h/R = 0.01, so extension and rotary inertia stay far below 1 %.
pub(crate) const E_MOD: f64 = 210e9;
pub(crate) const RHO: f64 = 7850.0;
pub(crate) const R: f64 = 0.5;
pub(crate) const WIDTH: f64 = 0.02;
pub(crate) const THICK: f64 = 0.005;
/// Straight beam elements round the ring.
pub(crate) const ELEMENTS: usize = 120;

pub(crate) fn area() -> f64 {
    WIDTH * THICK
}

/// In-plane bending second moment [m⁴].
pub(crate) fn inertia() -> f64 {
    WIDTH * THICK.powi(3) / 12.0
}

/// ω₀ of the n-lobe in-plane mode [rad/s] (module doc).
pub(crate) fn omega0(n: f64) -> f64 {
    let n2 = n * n;
    (E_MOD * inertia() * n2 * (n2 - 1.0).powi(2) / (RHO * area() * R.powi(4) * (n2 + 1.0))).sqrt()
}

/// The ring's node positions (x, y) [m]: `ELEMENTS` equally spaced round the circle of radius
/// `R` from +x.
pub(crate) fn ring_nodes() -> Vec<[f64; 2]> {
    (0..ELEMENTS)
        .map(|i| {
            let a = TAU * i as f64 / ELEMENTS as f64;
            [R * a.cos(), R * a.sin()]
        })
        .collect()
}

/// The cubic beam element's bending stiffness per EI/L³ over (w₁, θ₁, w₂, θ₂), θ = dw/dx
/// (Przemieniecki, ch. 5).
pub(crate) fn bending(l: f64) -> [[f64; 4]; 4] {
    [
        [12.0, 6.0 * l, -12.0, 6.0 * l],
        [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
        [-12.0, -6.0 * l, 12.0, -6.0 * l],
        [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
    ]
}

/// The consistent geometric stiffness of an axial force T per T/(30L) over (w₁, θ₁, w₂, θ₂)
/// (Przemieniecki, ch. 15).
pub(crate) fn geometric(l: f64) -> [[f64; 4]; 4] {
    [
        [36.0, 3.0 * l, -36.0, 3.0 * l],
        [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
        [-36.0, -3.0 * l, 36.0, -3.0 * l],
        [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
    ]
}

/// The ring's M, K and ΔK (the geometric stiffness of the hoop tension at `omega_ref`) over
/// (u_x, u_y, θ_z) per node, written as a body with stress stiffening of `kind` (for `Total`
/// the file holds K + ΔK). Elements: straight 2-D Euler–Bernoulli frame elements (axial EA/L,
/// cubic bending), the consistent geometric stiffness T/(30L)[36, 3L, −36, 3L; …] of an axial
/// force T (Przemieniecki, *Theory of Matrix Structural Analysis*, ch. 15) with T = ρAR²Ω_ref²
/// (a polygon's node load m Ω²R = 2T sin(π/N) gives exactly this); lumped mass ρAL per node on
/// the translations and ρIL on θ_z.
fn ring_body(dir: &std::path::Path, omega_ref: f64, kind: StressKind) -> BodyFiles {
    let n = 3 * ELEMENTS;
    let mut m = DMatrix::zeros(n, n);
    let mut k = DMatrix::zeros(n, n);
    let mut dk = DMatrix::zeros(n, n);
    let pos = ring_nodes();
    let tension = RHO * area() * R * R * omega_ref * omega_ref;
    for i in 0..ELEMENTS {
        let j = (i + 1) % ELEMENTS;
        let d = [pos[j][0] - pos[i][0], pos[j][1] - pos[i][1]];
        let l = d[0].hypot(d[1]);
        let (c, s) = (d[0] / l, d[1] / l);
        // local (u1, v1, θ1, u2, v2, θ2) from global (ux1, uy1, θ1, ux2, uy2, θ2)
        let mut t = SMatrix::<f64, 6, 6>::zeros();
        for o in [0, 3] {
            t[(o, o)] = c;
            t[(o, o + 1)] = s;
            t[(o + 1, o)] = -s;
            t[(o + 1, o + 1)] = c;
            t[(o + 2, o + 2)] = 1.0;
        }
        let ea = E_MOD * area() / l;
        let ei = E_MOD * inertia() / l.powi(3);
        let bend = bending(l);
        let geo = geometric(l);
        let tr = [1, 2, 4, 5];
        let mut kl = SMatrix::<f64, 6, 6>::zeros();
        let mut gl = SMatrix::<f64, 6, 6>::zeros();
        for (a, &ra) in tr.iter().enumerate() {
            for (b, &rb) in tr.iter().enumerate() {
                kl[(ra, rb)] = ei * bend[a][b];
                gl[(ra, rb)] = tension / (30.0 * l) * geo[a][b];
            }
        }
        for (a, b, v) in [(0, 0, ea), (0, 3, -ea), (3, 0, -ea), (3, 3, ea)] {
            kl[(a, b)] = v;
        }
        let kg = t.transpose() * kl * t;
        let gg = t.transpose() * gl * t;
        let idx = [3 * i, 3 * i + 1, 3 * i + 2, 3 * j, 3 * j + 1, 3 * j + 2];
        for a in 0..6 {
            for b in 0..6 {
                k[(idx[a], idx[b])] += kg[(a, b)];
                dk[(idx[a], idx[b])] += gg[(a, b)];
            }
        }
        let mass = RHO * area() * l / 2.0;
        let rot = RHO * inertia() * l / 2.0;
        for node in [i, j] {
            m[(3 * node, 3 * node)] += mass;
            m[(3 * node + 1, 3 * node + 1)] += mass;
            m[(3 * node + 2, 3 * node + 2)] += rot;
        }
    }
    let stress = match kind {
        StressKind::Increment => dk,
        StressKind::Total => &k + dk,
    };
    let mtx = |a: &DMatrix<f64>| mtx_format(a, Symmetry::Symmetric, "SI", "ring");
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for (i, p) in pos.iter().enumerate() {
        nodes.push_str(&format!("{},{:e},{:e},0\n", i + 1, p[0], p[1]));
        for (d, name) in ["ux", "uy", "rz"].iter().enumerate() {
            dofs.push_str(&format!("{},{},{name}\n", 3 * i + d + 1, i + 1));
        }
    }
    BodyFiles {
        format: Format::MatrixMarket,
        mass: write_file(dir, "mass.mtx", &mtx(&m)),
        stiffness: write_file(dir, "stiffness.mtx", &mtx(&k)),
        nodes: write_file(dir, "nodes.csv", &nodes),
        dofs: Some(write_file(dir, "dofs.csv", &dofs)),
        names: Default::default(),
        units: Units::Si,
        rotating: None,
        stress: Some(StressFiles {
            stiffness: write_file(dir, "stress.mtx", &mtx(&stress)),
            kind,
            reference_hz: omega_ref / TAU,
        }),
    }
}

/// The rotating-frame frequencies [rad/s] of the `lobes`-lobe pair at spin `omega` [rad/s]:
/// the lowest two eigenvalues of M q̈ + 2Ω G_c q̇ + (K − Ω²E + Ω²K_σ) q = 0 whose radial motion
/// is at least 90 % that harmonic (the extensional modes of that harmonic lie 300 times higher).
fn lobe_pair(body: &ReadBody, omega: f64, lobes: i32, stressed: bool) -> Vec<f64> {
    let t = rotating_terms(&body.m, &body.k, &body.dofs, &body.positions);
    let n = body.m.nrows();
    let ks = match stressed {
        true => body.ks.clone().expect("the ring has stress stiffening"),
        false => DMatrix::zeros(n, n),
    };
    let minv = DMatrix::from_diagonal(&body.m.diagonal().map(|x| 1.0 / x));
    let (values, vectors) = body_frame_modes(&minv, &body.k, &t.gc, &t.e, &ks, omega);
    let nodes = n / 3;
    let mut out = Vec::new();
    for (col, l) in values.iter().enumerate() {
        if l.im <= 0.0 {
            continue;
        }
        // Radial displacement w_i = cos a_i u_x + sin a_i u_y (complex).
        let w: Vec<(f64, f64)> = (0..nodes)
            .map(|i| {
                let ang = TAU * i as f64 / nodes as f64;
                let (ux, uy) = (vectors[(3 * i, col)], vectors[(3 * i + 1, col)]);
                (
                    ang.cos() * ux.re + ang.sin() * uy.re,
                    ang.cos() * ux.im + ang.sin() * uy.im,
                )
            })
            .collect();
        if mostly_harmonic(&w, lobes) {
            out.push(l.im);
        }
    }
    out.sort_by(f64::total_cmp);
    out.truncate(2);
    out
}

/// The eigenvalues and eigenvectors (over (q, q̇)) of the body-frame equations
/// M q̈ + 2Ω G_c q̇ + (K − Ω²(E − K_σ)) q = 0 at spin `omega` [rad/s], `minv` = M⁻¹.
pub(crate) fn body_frame_modes(
    minv: &DMatrix<f64>,
    k: &DMatrix<f64>,
    gc: &DMatrix<f64>,
    e: &DMatrix<f64>,
    ks: &DMatrix<f64>,
    omega: f64,
) -> (Vec<faer::c64>, faer::Mat<faer::c64>) {
    let n = k.nrows();
    let keff = k - omega * omega * (e - ks);
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-minv * keff));
    a.view_mut((n, n), (n, n))
        .copy_from(&(-2.0 * omega * minv * gc));
    eigen::general(&a).unwrap()
}

/// Whether at least 90 % of the radial displacement `w` (complex, at equally spaced angles
/// round the ring) is the harmonic of order ±`lobes` (by the discrete Fourier sums: Parseval,
/// Σ_k |W_k|² = N Σ |w_i|²).
pub(crate) fn mostly_harmonic(w: &[(f64, f64)], lobes: i32) -> bool {
    let points = w.len() as f64;
    let total: f64 = w.iter().map(|(r, i)| r * r + i * i).sum::<f64>() * points;
    let harmonic = |k: f64| {
        let (mut re, mut im) = (0.0, 0.0);
        for (i, (wr, wi)) in w.iter().enumerate() {
            let (s, c) = (k * TAU * i as f64 / points).sin_cos();
            re += wr * c + wi * s;
            im += wi * c - wr * s;
        }
        re * re + im * im
    };
    let k = f64::from(lobes);
    harmonic(k) + harmonic(-k) >= 0.9 * total
}

/// The stress-stiffened mean frequency √(ω₀² + SΩ²) and Bryan's factor of the 2- and 3-lobe
/// modes of the spinning ring within 1 % of the closed forms (module doc), at two speeds, with
/// ΔK given at a third (so the (Ω/Ω_ref)² scaling is what is tested), and without the stress
/// stiffening the softening S₀; the same body with the file holding the total stiffness K + ΔK
/// gives the same K_σ. The test prints the errors.
#[test]
fn spinning_ring_has_the_stress_stiffened_frequencies_and_bryans_factor() {
    let dir = scratch("ring");
    let inc_dir = dir.join("increment");
    let tot_dir = dir.join("total");
    std::fs::create_dir_all(&inc_dir).unwrap();
    std::fs::create_dir_all(&tot_dir).unwrap();
    let reference = 0.7 * omega0(2.0);
    let body = read_body(&ring_body(&inc_dir, reference, StressKind::Increment)).unwrap();
    let total = read_body(&ring_body(&tot_dir, reference, StressKind::Total)).unwrap();
    let (a, b) = (body.ks.as_ref().unwrap(), total.ks.as_ref().unwrap());
    assert!(
        (a - b).amax() <= 1e-9 * a.amax(),
        "`total` gives K_σ = (file − K)/Ω_ref²: {:e} of {:e}",
        (a - b).amax(),
        a.amax()
    );
    for lobes in [2, 3] {
        let n = f64::from(lobes);
        let w0 = omega0(n);
        let s = n * n * (n * n - 1.0).powi(2) / (n * n + 1.0).powi(2);
        let s0 = -(n * n - 1.0).powi(2) / (n * n + 1.0).powi(2);
        for ratio in [0.0, 0.5, 1.0] {
            let omega = ratio * omega0(2.0);
            let soft = lobe_pair(&body, omega, lobes, false);
            let mean = 0.5 * (soft[0] + soft[1]);
            let want = (w0 * w0 + s0 * omega * omega).sqrt();
            println!("n = {lobes}, Ω/ω₀₂ = {ratio}, unstressed: mean {mean:.4} vs {want:.4}");
            assert!(
                (mean / want - 1.0).abs() < 0.01,
                "unstressed {mean} vs {want}"
            );
            let pair = lobe_pair(&body, omega, lobes, true);
            assert_eq!(pair.len(), 2, "{lobes} lobes at {omega} rad/s: {pair:?}");
            let mean = 0.5 * (pair[0] + pair[1]);
            let want = (w0 * w0 + s * omega * omega).sqrt();
            let err = mean / want - 1.0;
            println!(
                "n = {lobes}, Ω/ω₀₂ = {ratio}: mean {mean:.4} rad/s vs {want:.4} ({err:+.2e})"
            );
            assert!(
                err.abs() < 0.01,
                "stress-stiffened frequency {mean} vs {want}"
            );
            if omega > 0.0 {
                let factor = (pair[1] - pair[0]) / (2.0 * n * omega);
                let bryan = 2.0 / (n * n + 1.0);
                let err = factor / bryan - 1.0;
                println!("   Bryan's factor {factor:.5} vs {bryan:.5} ({err:+.2e})");
                assert!(err.abs() < 0.01, "Bryan's factor {factor} vs {bryan}");
            }
        }
    }
}

/// Steel shaft Ø30 × 700 mm (16 elements) on 1e9 N/m bearings at its ends (850 times its own
/// 48EI/L³), a 200 N·s/m stationary damper and 5 g at r = 15 mm at mid-span (it lowers the
/// first bending by about 0.13 %: ½ of its mass over the modal mass ρAL/2), no gravity:
/// nearly the pinned-pinned Euler–Bernoulli beam, ω_E = (π/L)²√(EI/ρA) (Blevins, ch. 8, the pinned-pinned beam).
const SHAFT: &str = r#"name = "stressed-shaft"
[materials.steel]
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
[rotor.nodes]
bearing_a = 0.0
bearing_b = 700.0
[[rotor.sensors]]
name = "mid"
z_mm = 350.0
[[rotor.masses]]
z_mm = 350.0
radius_mm = 15.0
angle_deg = 0.0
mass_g = 5.0
[[supports]]
node = "bearing_a"
type = "linear"
spring = { kx_n_per_m = 1e9, ky_n_per_m = 1e9 }
[[supports]]
node = "bearing_b"
type = "linear"
spring = { kx_n_per_m = 1e9, ky_n_per_m = 1e9 }
[[supports]]
node = "mid"
type = "linear"
spring = { kx_n_per_m = 0.0, ky_n_per_m = 0.0, cx_ns_per_m = 200.0, cy_ns_per_m = 200.0 }
[drive]
node = "bearing_a"
axial_stiffness_n_per_m = 1e7
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "8n+12st"
[damping]
bands = [{ below_hz = 1000.0, ratio = 0.0 }]
above_ratio = 1.0
[speed]
hz = 140.0
[simulation]
t_end_s = 0.4
settle_s = 0.2
sample_rate_hz = 5600.0
gravity_m_s2 = 0.0
[solver]
tolerance = 1e-10
hmax = 1e-4
"#;

const SHAFT_L: f64 = 0.7;
const SHAFT_D: f64 = 0.03;
/// The speed ΔK is given at [Hz], and the axial tension it stands for there, a quarter of the
/// Euler load: N_ref = ¼ π²EI/L².
pub(crate) const SHAFT_REF_HZ: f64 = 100.0;

fn shaft_ei() -> f64 {
    E_MOD * std::f64::consts::PI * SHAFT_D.powi(4) / 64.0
}

/// ω_E [rad/s] (`SHAFT`'s doc).
pub(crate) fn shaft_omega_e() -> f64 {
    let rho_a = RHO * std::f64::consts::PI * SHAFT_D * SHAFT_D / 4.0;
    (std::f64::consts::PI / SHAFT_L).powi(2) * (shaft_ei() / rho_a).sqrt()
}

/// The shaft exported as an FE body (`export --model full`) with a stress stiffness: the
/// consistent geometric stiffness N/(30l)[36, 3l, −36, 3l; …] (Przemieniecki, ch. 15) of the
/// axial tension N_ref in both bending planes of every element, given at `SHAFT_REF_HZ`. A
/// rotor spinning about its axis has no such tension (the `fe` module doc): this stands in for
/// a body whose FE code found one, so that the pinned-pinned beam under tension
/// N = N_ref (Ω/Ω_ref)², ω² = ω_E² (1 + N L²/(π²EI)) (Blevins, ch. 8, the beam under axial load), is the closed form.
pub(crate) fn stressed_shaft(dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    use rotorsweep::dynamics::model::Model;
    use rotorsweep::export::model::{write_model, Which};
    use rotorsweep::scene::source::Source;
    use rotorsweep::scene::with_overrides;
    let path = write_file(dir, "shaft.toml", SHAFT);
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), &[]).unwrap();
    let body = dir.join("body");
    write_model(&scene, &model, &table, Which::Full, &body).unwrap();
    let z = &model.rotor.node_z;
    let n = 6 * z.len();
    let tension = 0.25 * std::f64::consts::PI.powi(2) * shaft_ei() / (SHAFT_L * SHAFT_L);
    let mut dk = DMatrix::zeros(n, n);
    for e in 0..z.len() - 1 {
        let l = z[e + 1] - z[e];
        let geo = geometric(l);
        // x–z plane (u_x, θ_y = slope), y–z plane (u_y, θ_x = −slope): `fe`'s convention.
        for (w, rot, sign) in [(0, 4, 1.0), (1, 3, -1.0)] {
            let idx = [6 * e + w, 6 * e + rot, 6 * e + 6 + w, 6 * e + 6 + rot];
            let sg = [1.0, sign, 1.0, sign];
            for a in 0..4 {
                for b in 0..4 {
                    dk[(idx[a], idx[b])] += sg[a] * sg[b] * tension / (30.0 * l) * geo[a][b];
                }
            }
        }
    }
    write_file(
        &body,
        "stress.mtx",
        &mtx_format(&dk, Symmetry::Symmetric, "SI", "axial tension N_ref"),
    );
    let text = std::fs::read_to_string(body.join("scene.toml")).unwrap();
    let text = text.replacen(
        "[fe]\n",
        &format!(
            "[fe]\nstress_stiffness = \"stress.mtx\"\nstress_stiffness_kind = \"increment\"\n\
             stress_reference_hz = {SHAFT_REF_HZ:?}\n"
        ),
        1,
    );
    assert!(
        text.contains("stress_stiffness ="),
        "the export has an [fe] table"
    );
    (
        body.join("scene.toml"),
        write_file(&body, "stressed.toml", &text),
    )
}

/// The speed [Hz] of `follows_the_tensioned_beam`'s whirl.
const WHIRL_HZ: f64 = 100.0;

/// The body of the scene `path`, whose axial tension is `quarter` of the Euler load at
/// `SHAFT_REF_HZ`: `modes` at `WHIRL_HZ` has the mean of its first backward and forward whirl
/// at ω_E √(1 + quarter (Ω/Ω_ref)²) and its first critical speed at
/// ω_E / √(1 − quarter ω_E²/Ω_ref²), each within 1 % (the closed forms below); the scene,
/// model and `modes` report at `WHIRL_HZ`.
pub(crate) fn follows_the_tensioned_beam(
    path: &std::path::Path,
    quarter: f64,
) -> (
    rotorsweep::scene::Scene,
    rotorsweep::dynamics::model::Model,
    rotorsweep::linear::overview::ModesReport,
) {
    use rotorsweep::dynamics::model::Model;
    use rotorsweep::linear::overview::modes_report;
    let we = shaft_omega_e() / TAU;
    let (scene, model) = Model::load(path, &[], None).unwrap();
    let r = modes_report(&scene, &model, WHIRL_HZ, None).unwrap();
    let mean = 0.5 * (r.whirl_hz[0] + r.whirl_hz[1]);
    let want = we * (1.0 + quarter * (WHIRL_HZ / SHAFT_REF_HZ).powi(2)).sqrt();
    println!(
        "N/N_E = {quarter}: whirl at {WHIRL_HZ} Hz {:?}, mean {mean:.3} Hz vs {want:.3}",
        &r.whirl_hz[..2]
    );
    assert!((mean / want - 1.0).abs() < 0.01, "{mean} Hz vs {want} Hz");
    let c = modes_report(&scene, &model, 0.0, Some(200.0)).unwrap();
    let crit = c.critical_speeds_hz.unwrap();
    let want = we / (1.0 - quarter * (we / SHAFT_REF_HZ).powi(2)).sqrt();
    println!("   critical speeds {crit:?} vs {want:.3} Hz");
    assert!(
        (crit[0] / want - 1.0).abs() < 0.01,
        "critical {} Hz vs {want} Hz",
        crit[0]
    );
    (scene, model, r)
}

/// `modes` at speed and the Campbell sweep's critical speed of the body with stress stiffening
/// against the tensioned pinned-pinned beam (`stressed_shaft`), within 1 %: at 100 Hz the mean
/// of the first backward and forward whirl (the gyroscopic split cancels to first order) is
/// ω_E √(1 + ¼ (Ω/Ω_ref)²); the first critical speed solves Ω² = ω_E² (1 + ¼ Ω²/Ω_ref²), so
/// Ω_c = ω_E / √(1 − ¼ ω_E²/Ω_ref²) (159 Hz against the 124 Hz of the body without it). The
/// stressed body exported again (`stress_stiffness.mtx` at Ω_ref = 1 rad/s) and re-imported
/// has the same whirl frequencies (≤ 1e-8 relative).
#[test]
fn modes_and_campbell_of_a_stressed_body_follow_the_tensioned_beam() {
    use rotorsweep::dynamics::model::Model;
    use rotorsweep::linear::overview::modes_report;
    let dir = scratch("stressed-shaft");
    let (plain, stressed) = stressed_shaft(&dir);
    for (path, quarter) in [(&plain, 0.0), (&stressed, 0.25)] {
        let (scene, model, r) = follows_the_tensioned_beam(path, quarter);
        let speed = WHIRL_HZ;
        if quarter > 0.0 {
            use rotorsweep::export::model::{write_model, Which};
            use rotorsweep::scene::source::Source;
            use rotorsweep::scene::with_overrides;
            let (table, _) = with_overrides(&Source::load(path).unwrap(), &[]).unwrap();
            let again = dir.join("again");
            write_model(&scene, &model, &table, Which::Full, &again).unwrap();
            let (s2, m2) = Model::load(&again.join("scene.toml"), &[], None).unwrap();
            let r2 = modes_report(&s2, &m2, speed, None).unwrap();
            for (a, b) in r2.whirl_hz.iter().zip(&r.whirl_hz) {
                assert!(
                    (a - b).abs() <= 1e-8 * b,
                    "re-exported whirl {a} Hz vs {b} Hz"
                );
            }
        }
    }
}

/// The time simulation at 140 Hz (between the critical speeds without and with stress
/// stiffening, `modes_and_campbell_…`) has the unbalance response of `linear` at that speed on
/// the stressed body, 1× line within 1 % in amplitude and 1° in phase; without its stress
/// stiffening the body runs above its critical speed instead (`linear`'s response differs by
/// more than half of itself).
#[test]
fn simulation_of_a_stressed_body_has_the_linear_unbalance_response() {
    let dir = scratch("stressed-run");
    let (plain, stressed) = stressed_shaft(&dir);
    simulation_has_the_linear_unbalance_response(&plain, &stressed, false);
}

/// The checks of `simulation_of_a_stressed_body_has_the_linear_unbalance_response` on the
/// scenes `plain` and `stressed` (the same body without and with its stress stiffness),
/// `solid` whether they attach it as a solid body; the stressed body's `linear` response at
/// the sensor [m] (vertical, complex).
pub(crate) fn simulation_has_the_linear_unbalance_response(
    plain: &std::path::Path,
    stressed: &std::path::Path,
    solid: bool,
) -> nalgebra::Complex<f64> {
    use rotorsweep::dynamics::model::Model;
    use rotorsweep::dynamics::LinearSystem;
    use rotorsweep::linear::response::sensor_response;
    let hz = 140.0;
    let w = TAU * hz;
    let response = |path: &std::path::Path| {
        let (scene, model) = Model::load(path, &[], None).unwrap();
        let sys = LinearSystem::of_scene(&scene, &model).unwrap();
        (
            scene,
            model,
            sensor_response(&sys, w, &sys.unbalance).unwrap()[0].vertical,
        )
    };
    let (_, _, free) = response(plain);
    let (scene, model, lin) = response(stressed);
    assert_eq!(
        scene.body.as_ref().is_some_and(|b| b.solid.is_some()),
        solid,
        "attached as a solid body: {solid}"
    );
    let change = (lin - free).norm() / lin.norm();
    println!(
        "linear at {hz} Hz: stressed {:.3e} m at {:.1}°, plain {:.3e} m at {:.1}°",
        lin.norm(),
        lin.arg().to_degrees(),
        free.norm(),
        free.arg().to_degrees()
    );
    assert!(
        change > 0.5,
        "stress stiffening changes the response by {change} only"
    );
    let res = rotorsweep::dynamics::simulation::run(&scene, &model);
    assert_eq!(
        res.stats.status,
        rotorsweep::integrators::Status::Ok,
        "{}",
        res.stats.cause
    );
    let x = crate::support::channel(&res, "runout/mid/vertical");
    let got = rotorsweep::signal::lines(x, &res.time, &[hz])[0];
    let want_um = 1e6 * lin.norm();
    let dphi = (got.arg() - lin.arg()).to_degrees();
    let dphi = (dphi + 180.0).rem_euclid(360.0) - 180.0;
    println!(
        "simulated {:.4} um at {:.2}°, linear {want_um:.4} um at {:.2}°",
        got.norm(),
        got.arg().to_degrees(),
        lin.arg().to_degrees()
    );
    assert!(
        (got.norm() / want_um - 1.0).abs() < 0.01,
        "{} vs {want_um} um",
        got.norm()
    );
    assert!(dphi.abs() < 1.0, "phase off by {dphi}°");
    lin
}

/// Bad stress-stiffness input: a matrix not symmetric (the entry and its node DOFs named), of
/// the wrong size, in other units than the scene's, each an error naming the file; in a scene,
/// a stress key without the others (naming the missing keys) and a reference speed ≤ 0.
#[test]
fn bad_stress_stiffness_is_refused_naming_file_and_entry() {
    let dir = scratch("bad-stress");
    let header = "%%MatrixMarket matrix coordinate real general\n% units: SI\n";
    let body = |stress: &str| {
        BodyFiles {
        format: Format::MatrixMarket,
        mass: write_file(
            &dir,
            "m.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 2\n1 1 2.0\n2 2 2.0\n",
        ),
        stiffness: write_file(
            &dir,
            "k.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 3\n1 1 2000.0\n2 1 -1000.0\n2 2 1000.0\n",
        ),
        nodes: write_file(&dir, "nodes.csv", "id,x,y,z\n1,0,0,0\n2,0,0,1\n"),
        dofs: Some(write_file(&dir, "dofs.csv", "index,node,dof\n1,1,ux\n2,2,ux\n")),
        names: Default::default(),
        units: Units::Si,
        rotating: None,
        stress: Some(StressFiles {
            stiffness: write_file(&dir, "stress.mtx", stress),
            kind: StressKind::Increment,
            reference_hz: 10.0,
        }),
    }
    };
    let err = |stress: &str| format!("{}", read_body(&body(stress)).unwrap_err());
    let e = err(&format!("{header}2 2 3\n1 1 1.0\n2 1 0.5\n1 2 0.25\n"));
    assert!(
        e.contains("stress.mtx") && e.contains("not symmetric") && e.contains("node 2 ux"),
        "{e}"
    );
    let e = err(&format!("{header}3 3 1\n1 1 1.0\n"));
    assert!(
        e.contains("stress.mtx") && e.contains("3 × 3") && e.contains("2 DOFs"),
        "{e}"
    );
    let e =
        err("%%MatrixMarket matrix coordinate real symmetric\n% units: mm-t-s\n2 2 1\n1 1 1.0\n");
    assert!(e.contains("stress.mtx") && e.contains("mm-t-s"), "{e}");
    // The scene keys: the shaft's export with one key of three, and with a speed of 0 Hz.
    let (plain, _) = stressed_shaft(&dir);
    let text = std::fs::read_to_string(&plain).unwrap();
    for (keys, want) in [
        (
            "stress_stiffness = \"stress.mtx\"\n",
            "missing: fe.stress_stiffness_kind, fe.stress_reference_hz",
        ),
        (
            "stress_stiffness = \"stress.mtx\"\nstress_stiffness_kind = \"increment\"\nstress_reference_hz = 0.0\n",
            "fe.stress_reference_hz",
        ),
    ] {
        let path = write_file(
            plain.parent().unwrap(),
            "bad.toml",
            &text.replacen("[fe]\n", &format!("[fe]\n{keys}"), 1),
        );
        let e = format!("{}", rotorsweep::scene::Scene::load(&path, &[]).unwrap_err());
        assert!(e.contains(want) && e.contains("bad.toml"), "{e}");
    }
}

/// A run-up stiffens at every instant's speed: the stressed shaft ramped from 100 to 180 Hz in
/// 4 s (20 Hz/s) has its largest mid-span runout within 2 % of the tensioned beam's critical
/// speed (158.8 Hz, `modes_and_campbell_…`; the ramp delays the peak a little past the
/// critical speed), far from the 124 Hz of the body without stress stiffening. Measured: 159.8
/// Hz (+0.65 %); `rotorsweep simulate` of the same run-up: its 1× order resonance at 160.0 Hz,
/// and at 125.3 Hz for the body without stress stiffening.
#[test]
fn run_up_of_a_stressed_body_peaks_at_the_stiffened_critical_speed() {
    use rotorsweep::dynamics::model::Model;
    let dir = scratch("stressed-runup");
    let (_, stressed) = stressed_shaft(&dir);
    let text = std::fs::read_to_string(&stressed).unwrap();
    let ramp = "[speed]\nprofile = \"ramp\"\nfrom_hz = 100.0\nto_hz = 180.0\nramp_start_s = 0.2\n\
                ramp_end_s = 4.2\n";
    let text = text.replacen("[speed]\nhz = 140.0\n", ramp, 1).replacen(
        "t_end_s = 0.4\n",
        "t_end_s = 4.2\n",
        1,
    );
    assert!(text.contains("ramp_end_s") && text.contains("t_end_s = 4.2"));
    let path = write_file(stressed.parent().unwrap(), "runup.toml", &text);
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let res = rotorsweep::dynamics::simulation::run(&scene, &model);
    assert_eq!(
        res.stats.status,
        rotorsweep::integrators::Status::Ok,
        "{}",
        res.stats.cause
    );
    let x = crate::support::channel(&res, "runout/mid/vertical");
    let peak = (0..x.len())
        .max_by(|&a, &b| x[a].abs().total_cmp(&x[b].abs()))
        .unwrap();
    let hz = 100.0 + (res.time[peak] - 0.2) / 4.0 * 80.0;
    let we = shaft_omega_e() / TAU;
    let critical = we / (1.0 - 0.25 * (we / SHAFT_REF_HZ).powi(2)).sqrt();
    println!(
        "run-up peak at {:.3} s: {hz:.2} Hz vs {critical:.2} Hz",
        res.time[peak]
    );
    assert!(
        (hz / critical - 1.0).abs() < 0.02,
        "{hz} Hz vs {critical} Hz"
    );
}

/// An Abaqus body in mm-t-s with a stress stiffness: the two-mass chain of
/// `fe_import::abaqus_chain_…` (2e-3 t, 1 N/mm) and ΔK = 0.5 N/mm on node 1 DOF 1 at 10 Hz give
/// K_σ = 500 N/m / (2π · 10 rad/s)² (1 N/mm = 1000 N/m, the unit conversion); an entry on a DOF
/// the mass and stiffness lack is refused naming the file and line.
#[test]
fn abaqus_stress_stiffness_in_millimetres_is_scaled_to_si() {
    let dir = scratch("abaqus-stress");
    let body = |stress: &str| BodyFiles {
        format: Format::Abaqus,
        mass: write_file(&dir, "m.mtx", "** MASS\n1,1, 1,1, 2e-3\n2,1, 2,1, 2e-3\n"),
        stiffness: write_file(
            &dir,
            "k.mtx",
            "** STIFFNESS\n1,1, 1,1, 2.0\n2,1, 1,1, -1.0\n2,1, 2,1, 1.0\n",
        ),
        nodes: write_file(&dir, "nodes.csv", "id,x,y,z\n1,0,0,0\n2,0,0,100\n"),
        dofs: None,
        names: Default::default(),
        units: Units::MmTonne,
        rotating: None,
        stress: Some(StressFiles {
            stiffness: write_file(&dir, "s.mtx", stress),
            kind: StressKind::Increment,
            reference_hz: 10.0,
        }),
    };
    let read = read_body(&body("** STRESS\n1,1, 1,1, 0.5\n")).unwrap();
    let ks = read.ks.unwrap();
    let want = 500.0 / (TAU * 10.0).powi(2);
    assert!(
        (ks[(0, 0)] / want - 1.0).abs() < 1e-14,
        "{} vs {want}",
        ks[(0, 0)]
    );
    assert_eq!(ks[(1, 1)], 0.0);
    let e = format!(
        "{}",
        read_body(&body("** STRESS\n1,1, 1,1, 0.5\n2,2, 2,2, 0.5\n")).unwrap_err()
    );
    assert!(e.contains("s.mtx:3:") && e.contains("node 2 dof 2"), "{e}");
}
