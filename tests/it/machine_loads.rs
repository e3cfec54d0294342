//! A machine's loads in time (scene/machine_loads.rs, dynamics/bodies.rs) against closed forms.
//! - Web tension: a tension T wrapped over θ presses a roll with 2T sin(θ/2) per unit length
//!   along the wrap's bisector (the frictionless capstan resultant; Meriam & Kraige,
//!   *Engineering Mechanics: Statics*, §6/9). Over the whole span of a simply supported uniform
//!   tube this line load w deflects its middle by 5wL⁴/(384EI) (Roark & Young, *Formulas for
//!   Stress and Strain*, 7th ed., Table 8.1 case 2e; Timoshenko & Gere, *Mechanics of
//!   Materials*) plus the shear deflection wL²/(8κGA) (Roark & Young §8.10) with Cowper's shear
//!   factor of a hollow circle κ = 6(1+ν)(1+m²)²/((7+6ν)(1+m²)² + (20+12ν)m²), m = R_i/R_o
//!   (Cowper, *J. Appl. Mech.* 33, 1966, Table 1), plus the supports' own compression wL/(2k).
//! - Harmonic loads on the rigid cylinder Ø200 × 400 mm (tests/fixtures/stiff-jeffcott.toml,
//!   bending above 1 kHz) on two supports k, c: its bounce mode is a single-DOF oscillator
//!   m ÿ + 2c ẏ + 2k y = F sin ωt, whose steady amplitude is F/√((2k − mω²)² + (2cω)²)
//!   (Thomson & Dahleh, *Theory of Vibration with Applications*, 5th ed., §3.1), about the
//!   static deflection of the steady load F₀/(2k). The loading arms' harmonic force (F = 2A on
//!   the two journals) and a web's harmonic tension (F = 2A sin(θ/2) L) both; measured within
//!   2.5e-5 of it (the test allows 2e-4).
//! - A table of arm forces ramps to a held load: the cylinder settles at its static deflection.
//! - Bad input: each a clear error naming the file, key and line.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::{run, JobResult};
use rotorsweep::scene::Scene;

fn machine(dir: &Path, roll_extra: &str, tail: &str) -> PathBuf {
    let text = format!(
        "name = \"loads\"\n[[rolls]]\nname = \"r\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 0.0]\n\
         {roll_extra}\n{tail}"
    );
    support::write_file(dir, "machine.toml", &text)
}

fn simulate(path: &Path) -> JobResult {
    let scene = Scene::load(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).unwrap();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    r
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

#[test]
fn web_line_load_deflects_a_simply_supported_tube_as_the_beam_closed_form() {
    let dir = support::scratch("loads-web-static");
    let (l, d_o, d_i, k): (f64, f64, f64, f64) = (4.0, 0.2, 0.16, 1.0e10);
    let (e, nu) = (210e9, 0.3);
    let roll = format!(
        "name = \"tube\"\n[materials.steel]\nyoungs_modulus_gpa = 210.0\npoisson = 0.3\n\
         density_kg_m3 = 7850.0\n[rotor]\n[[rotor.segments]]\nlength_mm = 4000.0\n\
         outer_diameter_mm = 200.0\ninner_diameter_mm = 160.0\nelements = 160\nmaterial = \"steel\"\n\
         [rotor.nodes]\na = 0.0\nb = 4000.0\n[[rotor.sensors]]\nname = \"centre\"\nz_mm = 2000.0\n\
         [[supports]]\nnode = \"a\"\ntype = \"linear\"\nspring = {{ kx_n_per_m = {k:e}, ky_n_per_m = {k:e} }}\n\
         [[supports]]\nnode = \"b\"\ntype = \"linear\"\nspring = {{ kx_n_per_m = {k:e}, ky_n_per_m = {k:e} }}\n\
         [drive]\nnode = \"a\"\naxial_stiffness_n_per_m = 1.0e7\n[reduction]\nboundary = [\"a\", \"b\"]\n\
         modes = \"30n+12st\"\n[simulation]\nt_end_s = 0.005\nsettle_s = 0.0\nsample_rate_hz = 1000.0\n\
         gravity_m_s2 = 0.0\n"
    );
    support::write_file(&dir, "roll.toml", &roll);
    // T = 2 kN/m over 120°, resultant 60° below +x: w = 2T sin 60° = 3464.1 N/m.
    let (t, wrap, dir_deg) = (2.0e3, 120.0f64, -60.0f64);
    let webs = "[[webs]]\nname = \"felt\"\nroll = \"r\"\nfrom_mm = 0.0\nto_mm = 4000.0\n\
                tension_kn_per_m = 2.0\nwrap_deg = 120.0\nresultant_deg = -60.0\n";
    let r = simulate(&machine(&dir, "", webs));
    let w = 2.0 * t * (0.5 * wrap.to_radians()).sin();
    let i = PI / 64.0 * (d_o.powi(4) - d_i.powi(4));
    let a = PI / 4.0 * (d_o * d_o - d_i * d_i);
    let (m, g) = (d_i / d_o, e / (2.0 * (1.0 + nu)));
    let m2 = (1.0 + m * m).powi(2);
    let kappa = 6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * m * m);
    let bending = 5.0 * w * l.powi(4) / (384.0 * e * i);
    let shear = w * l * l / (8.0 * kappa * g * a);
    let springs = w * l / (2.0 * k);
    let total = bending + shear + springs;
    let y = mean(support::channel(&r, "runout/r.centre/vertical"));
    let x = mean(support::channel(&r, "runout/r.centre/horizontal"));
    let (want_x, want_y) = (
        total * dir_deg.to_radians().cos(),
        total * dir_deg.to_radians().sin(),
    );
    // Runout in µm. Measured 4e-5 below the closed form at 160 elements (4.8e-4 at 40: the
    // linear sharing of the load between each element's two nodes, O(h²); 80 normal modes
    // instead of 30 change it by 6e-6). Shear is 1.6 % of the deflection.
    let (x, y) = (1e-6 * x, 1e-6 * y);
    assert!((y / want_y - 1.0).abs() < 1e-4, "{y} vs {want_y} m");
    assert!((x / want_x - 1.0).abs() < 1e-4, "{x} vs {want_x} m");
}

/// The rigid cylinder on k = 1e5 N/m, c = 222.1 N·s/m per support (ζ = 0.05 of the bounce
/// mode), speed 0, no gravity, 6 s from the static start at 1 kHz, the last 2 s recorded.
fn damped_cylinder(dir: &Path) {
    let spring = "kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5, cx_ns_per_m = 222.1, cy_ns_per_m = 222.1";
    let tail = "[simulation]\nt_end_s = 6.0\nsettle_s = 4.0\nsample_rate_hz = 1000.0\n\
                gravity_m_s2 = 0.0\n[solver]\ntolerance = 1e-10\nhmax = 1e-3\n";
    support::write_file(dir, "roll.toml", &support::stiff_jeffcott(spring, "", tail));
}

/// The cylinder's mass [kg]: ρ π R² L (its 10 g unbalance mass included by the model; the
/// closed form takes the model's mass, which differs from ρπR²L by that 10 g).
fn cylinder_mass(path: &Path) -> f64 {
    let scene = Scene::load(path, &[]).unwrap();
    Model::build(&scene, None).unwrap().rotor.mass()
}

fn steady_amplitude(f_amp: f64, m: f64, freq: f64) -> f64 {
    let (k2, c2, w) = (2.0e5, 2.0 * 222.1, 2.0 * PI * freq);
    f_amp / ((k2 - m * w * w).powi(2) + (c2 * w).powi(2)).sqrt()
}

/// Runs `path` (the damped cylinder of mass `m` [kg] under a harmonic load at 5 Hz) and checks
/// its centre's vertical motion: the amplitude of the total harmonic force `amplitude` [N] and
/// the mean of the total steady force `steady` [N] (both downward), as the module doc's closed
/// form; `what` names the case.
fn forced_response(path: &Path, m: f64, (amplitude, steady): (f64, f64), what: &str) {
    let f = 5.0;
    let r = simulate(path);
    let y = support::channel(&r, "runout/r.centre/vertical");
    let amp = 1e-6 * support::hann_amplitude(y, 1000.0, f);
    let want = steady_amplitude(amplitude, m, f);
    assert!((amp / want - 1.0).abs() < 2e-4, "{what}: {amp} vs {want} m");
    let y0 = 1e-6 * mean(y);
    assert!(
        (y0 / (-steady / 2.0e5) - 1.0).abs() < 1e-3,
        "{what}: mean {y0} m"
    );
}

#[test]
fn harmonic_arm_force_and_web_tension_give_the_forced_response_amplitude() {
    let dir = support::scratch("loads-harmonic");
    damped_cylinder(&dir);
    // Arms: 100 N sin(2π 5 t) downward on each journal, on a steady −300 N.
    let arms = "arm_force_n = [0.0, -300.0]\narm_profile = \"harmonic\"\n\
                arm_amplitude_n = [0.0, -100.0]\narm_frequency_hz = 5.0\n";
    let path = machine(&dir, arms, "");
    let m = cylinder_mass(&path);
    forced_response(&path, m, (200.0, 600.0), "arms");
    // A web over the whole 400 mm, wrap 180° (resultant 2T per metre), pressing down:
    // T = 1 ± 0.5 kN/m at 5 Hz gives 800 N steady and 400 N amplitude.
    let web = "[[webs]]\nname = \"w\"\nroll = \"r\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
               tension_kn_per_m = 1.0\nwrap_deg = 180.0\nresultant_deg = -90.0\n\
               profile = \"harmonic\"\namplitude_kn_per_m = 0.5\nfrequency_hz = 5.0\n";
    forced_response(&machine(&dir, "", web), m, (400.0, 800.0), "web");
}

#[test]
fn a_table_of_arm_forces_settles_at_its_last_load() {
    let dir = support::scratch("loads-table");
    damped_cylinder(&dir);
    let arms = "arm_profile = \"table\"\narm_times_s = [0.0, 0.5, 1.0]\n\
                arm_table_n = [[0.0, 0.0], [0.0, -500.0], [0.0, -500.0]]\n";
    let r = simulate(&machine(&dir, arms, ""));
    let y = support::channel(&r, "runout/r.centre/vertical");
    // 2 × 500 N on 2k = 2e5 N/m: 5 mm down; the transient has decayed by e^{−ζω t} < 1e-4.
    assert!((1e-6 * mean(y) / -5.0e-3 - 1.0).abs() < 1e-3, "{}", mean(y));
}

#[test]
fn bad_loads_are_clear_errors_at_their_key_and_line() {
    let dir = support::scratch("loads-errors");
    damped_cylinder(&dir);
    let web = |body: &str| {
        format!(
            "[[webs]]\nname = \"w\"\nroll = \"r\"\nfrom_mm = 0.0\nto_mm = 400.0\nwrap_deg = 90.0\n\
             resultant_deg = -90.0\n{body}\n"
        )
    };
    let cases = [
        (
            "",
            web("tension_kn_per_m = nan"),
            "webs[0].tension_kn_per_m",
            "tension_kn_per_m = nan",
            "must be zero or positive",
        ),
        (
            "",
            web("tension_kn_per_m = -1.0"),
            "webs[0].tension_kn_per_m",
            "tension_kn_per_m = -1.0",
            "must be zero or positive",
        ),
        (
            "",
            web("tension_kn_per_m = 1.0").replace("wrap_deg = 90.0", "wrap_deg = 400.0"),
            "webs[0].wrap_deg",
            "wrap_deg = 400.0",
            "(0, 360]",
        ),
        (
            "",
            web("tension_kn_per_m = 1.0").replace("roll = \"r\"", "roll = \"q\""),
            "webs[0].roll",
            "roll = \"q\"",
            "unknown roll `q`",
        ),
        (
            "",
            web("tension_kn_per_m = 1.0").replace("to_mm = 400.0", "to_mm = 500.0"),
            "webs[0].from_mm",
            "from_mm = 0.0",
            "must lie on roll `r`",
        ),
        (
            "",
            web("tension_kn_per_m = 1.0\nprofile = \"harmonic\"\namplitude_kn_per_m = 2.0\nfrequency_hz = 5.0"),
            "webs[0].amplitude_kn_per_m",
            "amplitude_kn_per_m = 2.0",
            "a web cannot push",
        ),
        (
            "",
            web("profile = \"table\"\ntimes_s = [0.0, 1.0, 0.5]\ntable_kn_per_m = [1.0, 1.0, 1.0]"),
            "webs[0].times_s",
            "times_s = [0.0, 1.0, 0.5]",
            "must start at 0 and increase",
        ),
        (
            "",
            web("tension_kn_per_m = 1.0\nfrequency_hz = 5.0"),
            "webs[0].frequency_hz",
            "frequency_hz = 5.0",
            "only for webs[0].profile = \"harmonic\"",
        ),
        (
            "arm_profile = \"harmonic\"\narm_amplitude_n = [0.0, 10.0]\narm_frequency_hz = -2.0",
            String::new(),
            "rolls[0].arm_frequency_hz",
            "arm_frequency_hz = -2.0",
            "must be a positive number",
        ),
        (
            "arm_force_n = [0.0, 1.0]\narm_profile = \"table\"\narm_times_s = [0.0, 1.0]\n\
             arm_table_n = [[0.0, 0.0], [0.0, 1.0]]",
            String::new(),
            "rolls[0].arm_force_n",
            "arm_force_n = [0.0, 1.0]",
            "the table gives the load",
        ),
        (
            "arm_profile = \"harmonic\"\narm_frequency_hz = 2.0",
            String::new(),
            "rolls[0].arm_profile",
            "arm_profile = \"harmonic\"",
            "needs `rolls[0].arm_amplitude_n` too",
        ),
    ];
    for (roll_extra, tail, key, line, reason) in cases {
        let path = machine(&dir, roll_extra, &tail);
        let text = std::fs::read_to_string(&path).unwrap();
        let e = Scene::load(&path, &[]).expect_err(key);
        support::assert_error_at(&e, &path, &text, (key, line, reason));
    }
}
