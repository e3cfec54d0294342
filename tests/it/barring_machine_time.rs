//! The coupled machine's barring map confirmed by its time run: the shipped
//! studies/scenes/two-roll-nip-visco.toml (the reference roll pressed at 10 kN/m against the
//! roll with the 15 mm viscoelastic cover, 90 coordinates, 20 segments) at 14.75 Hz, where the
//! earlier one-mode map gave +2.45 1/s and the time run decayed (docs/machines.md).
//!
//! The map: `barring_map` (`linear/barring_machine.rs`) at 14.75 Hz, its least stable barring
//! root (measured on this build: −0.5783 1/s at 25.455 Hz, the coupled rolls' mode on the
//! rolling cover, 1.89 waves per revolution). The time run: `bodies::run` of the same file
//! with `speed.hz = 14.75`, 4 s from the standstill equilibrium (the jump to speed starts the
//! vibration), the cover's 4096 points (1024 are too coarse for a rate: 30 % off in
//! tests/it/barring_time.rs), generalized-α with ρ∞ = 1 (no numerical damping) at a fixed
//! 20 µs step (the default BDF at 1e-7 m put the 79 Hz root's rate 30 % off: −0.64 against
//! −0.93 1/s with generalized-α and with BDF at 1e-11 m, measured over 8 s). Its rate: the
//! sum of the 20 segment forces, its Hann-windowed Fourier amplitude at the map's frequency in
//! 1 s windows every 0.25 s over 1–4 s, the least-squares slope of its logarithm (exact for one
//! decaying sine: each window is the first one scaled by e^{σ t}; the other components lie
//! 4 Hz and more away: the forced 2× at 29.5 Hz, the 79 Hz root). Measured: −0.5799 1/s (over
//! 1–8 s −0.5793), within 0.3 % of the map; the test allows 3 %, as the single-DOF test
//! (tests/it/barring_time.rs). Its frequency: the peak of the 1–4 s amplitude within ±2 Hz of
//! the map's (measured 25.423 Hz): within 0.1 Hz.
//!
//! An unstable point: the shipped machine's map is stable over 8.5–15 Hz at 10 kN/m
//! (docs/machines.md), so a machine of two stiff cylinders (tests/fixtures/stiff-jeffcott.toml,
//! Ø200 × 400 mm, 98.7 kg, bending above 1 kHz, on supports of 3e6 N/m and 100 Ns/m), the upper
//! one under the shipped viscoelastic cover (15 mm, E_r = 30, E_u = 90 MPa, τ = 50 ms) pressed
//! at 10 kN/m over its 400 mm in 4 segments, no gravity. Its map over 4–20 Hz (1 Hz steps) is
//! unstable at 8, 10, 13 and 16 Hz (lobes of polygon orders 16, 13, 10, 8) and stable between;
//! at 13 Hz its root is +0.7407 1/s at 111.252 Hz (9.84 waves per revolution of the covered roll,
//! nip share 0.73). The time run ramps the lower roll from rest to 13 Hz over 1 s (a jump to
//! speed would start the cover at its relaxed law and shake the nip at 110 Hz to the edge of
//! opening, far beyond small vibration, where the amplitude saturates at once) and holds it;
//! its rate as above over windows from 1 to 3 s. Measured: +0.7397 1/s (0.1 % from the map;
//! over 1–2.5 s +0.7427, 1–3.5 s +0.7368: later the amplitude, 20 % of the nip force by 3.5 s,
//! is no longer small and the rate falls), peak at 111.25 Hz. The test allows 3 % and 0.1 Hz.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use rotorsweep::dynamics::bodies::run;
use rotorsweep::dynamics::Model;
use rotorsweep::linear::barring_machine::{barring_map, MapPoint, MapRequest};
use rotorsweep::scene::Machine;

use crate::support;

const SPEED_HZ: f64 = 14.75;

fn scene() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/scenes/two-roll-nip-visco.toml"
    ))
}

/// |Σ x_i w_i e^{−2πi f t_i}| over `x` sampled at `dt` [s], w the Hann window.
fn amplitude(x: &[f64], dt: f64, f: f64) -> f64 {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let (mut re, mut im) = (0.0, 0.0);
    for (i, v) in x.iter().enumerate() {
        let w = 0.5 - 0.5 * (2.0 * PI * i as f64 / (n - 1) as f64).cos();
        let a = -2.0 * PI * f * i as f64 * dt;
        re += (v - mean) * w * a.cos();
        im += (v - mean) * w * a.sin();
    }
    re.hypot(im)
}

/// The barring map's point of `machine` at `speed` [Hz] and the nip's own line load.
fn map_point(machine: &Machine, model: &Model, speed: f64) -> MapPoint {
    let request = MapRequest {
        nip: None,
        speeds_hz: vec![speed],
        loads_kn_per_m: None,
    };
    let mut map = barring_map(machine, model, &request).unwrap();
    map.loads.remove(0).points.remove(0)
}

#[test]
fn coupled_barring_map_root_is_the_time_runs_decay() {
    let sets: Vec<String> = [
        "speed.hz=14.75",
        "simulation.t_end_s=4",
        "simulation.settle_s=0",
        "nips[0].cover_points=4096",
        "solver.integrator=gen-alpha",
        "solver.rho_inf=1.0",
        "solver.fixed_step=true",
        "solver.hmax=2e-5",
    ]
    .map(String::from)
    .to_vec();
    let (s, model) = Model::load(&scene(), &sets, None).unwrap();
    let machine = s.machine.as_ref().unwrap();
    let p = &map_point(machine, &model, SPEED_HZ);
    let (rate, freq) = (p.growth_per_s, p.frequency_hz);
    assert!(p.stable && rate < 0.0, "map at {SPEED_HZ} Hz: {p:?}");

    let result = run(machine, &model);
    let (run_rate, run_freq) = rate_and_peak(&result, "nips/press/force", freq, (1.0, 4.0));
    eprintln!(
        "{SPEED_HZ} Hz: map {rate:.4} 1/s at {freq:.3} Hz; time run {run_rate:.4} 1/s, \
         peak {run_freq:.3} Hz"
    );
    assert!(run_rate < 0.0, "time run {run_rate} 1/s");
    assert!(
        (run_rate - rate).abs() < 0.03 * rate.abs(),
        "time run {run_rate} 1/s vs map {rate} 1/s"
    );
    assert!(
        (run_freq - freq).abs() < 0.1,
        "time run {run_freq} Hz vs map {freq} Hz"
    );
}

/// The time run's rate [1/s] and peak frequency [Hz] at the root `freq` [Hz] (module doc): the
/// nip's summed force, its Hann-windowed amplitude at `freq` in 1 s windows every 0.25 s from
/// `span.0` to `span.1` [s], the least-squares slope of its logarithm; the peak of the amplitude
/// over the whole span within ±2 Hz of `freq`, on a 1 mHz grid.
fn rate_and_peak(
    result: &rotorsweep::dynamics::simulation::JobResult,
    field: &str,
    freq: f64,
    (from, to): (f64, f64),
) -> (f64, f64) {
    let field = (result.fields.iter())
        .find(|f| f.name == field)
        .unwrap_or_else(|| panic!("{field}"));
    let nt = result.time.len();
    let dt = result.time[1] - result.time[0];
    let segments = field.data.len() / nt;
    let total: Vec<f64> = (0..nt)
        .map(|i| (0..segments).map(|j| field.data[j * nt + i]).sum())
        .collect();
    let window = (1.0 / dt).round() as usize;
    let at = |t: f64| ((t - result.time[0]) / dt).round() as usize;
    let starts = ((to - from - 1.0) / 0.25).round() as usize;
    let points: Vec<(f64, f64)> = (0..=starts)
        .map(|k| {
            let t0 = from + 0.25 * k as f64;
            let i = at(t0);
            (t0 + 0.5, amplitude(&total[i..i + window], dt, freq).ln())
        })
        .collect();
    let np = points.len() as f64;
    let (mt, my) = (points.iter()).fold((0.0, 0.0), |a, p| (a.0 + p.0 / np, a.1 + p.1 / np));
    let rate = points.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>()
        / points.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let span = &total[at(from)..at(to).min(nt)];
    let peak = (0..=4000)
        .map(|k| freq - 2.0 + 1e-3 * k as f64)
        .map(|f| (f, amplitude(span, dt, f)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
        .0;
    (rate, peak)
}

/// The two stiff cylinders of the module doc in `dir`, the lower one's speed `speed` (TOML
/// lines of its [speed] table); returns the machine file.
fn cylinders_in_a_visco_nip(dir: &Path, speed: &str) -> PathBuf {
    let spring = "kx_n_per_m = 3.0e6, ky_n_per_m = 3.0e6, cx_ns_per_m = 100.0, cy_ns_per_m = 100.0";
    let run_keys = format!(
        "[speed]\n{speed}\n[simulation]\nt_end_s = 3.0\nsettle_s = 0.0\ngravity_m_s2 = 0.0\n\
         [solver]\nintegrator = \"gen-alpha\"\nrho_inf = 1.0\nfixed_step = true\nhmax = 2e-5\n"
    );
    support::write_file(
        dir,
        "a.toml",
        &support::stiff_jeffcott(spring, "", &run_keys),
    );
    support::write_file(dir, "b.toml", &support::stiff_jeffcott(spring, "", ""));
    let text = "name = \"cylinders\"\n\
        [[rolls]]\nname = \"a\"\nscene = \"a.toml\"\nposition_mm = [0.0, 0.0]\n\
        [[rolls]]\nname = \"b\"\nscene = \"b.toml\"\nposition_mm = [0.0, 215.0]\n\
        surface_speed_of = \"a\"\n\
        [[nips]]\nname = \"press\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\n\
        to_mm = 400.0\nsegments = 4\nlaw = \"cover\"\ncover_on = \"b\"\n\
        cover_thickness_mm = 15.0\ncover_modulus_mpa = 30.0\ncover_poisson = 0.45\n\
        cover_unrelaxed_modulus_mpa = 90.0\ncover_relaxation_time_s = 0.05\n\
        cover_points = 4096\nline_load_kn_per_m = 10.0\n";
    support::write_file(dir, "machine.toml", text)
}

#[test]
fn unstable_barring_root_of_a_coupled_machine_is_the_time_runs_growth() {
    let dir = support::scratch("barring-unstable");
    let speed = 13.0;
    let (s, model) = Model::load(
        &cylinders_in_a_visco_nip(&dir, &format!("hz = {speed}")),
        &[],
        None,
    )
    .unwrap();
    let p = &map_point(s.machine.as_ref().unwrap(), &model, speed);
    let (rate, freq) = (p.growth_per_s, p.frequency_hz);
    assert!(!p.stable && rate > 0.0, "map at {speed} Hz: {p:?}");

    // The same machine ramped from rest to the speed over 1 s, then held.
    let ramp = format!("profile = \"ramp\"\nfrom_hz = 0.0\nto_hz = {speed}\nramp_end_s = 1.0");
    let (s, model) = Model::load(&cylinders_in_a_visco_nip(&dir, &ramp), &[], None).unwrap();
    let result = run(s.machine.as_ref().unwrap(), &model);
    assert!(result.stats.status.completed(), "{}", result.stats.cause);
    let (run_rate, run_freq) = rate_and_peak(&result, "nips/press/force", freq, (1.0, 3.0));
    eprintln!(
        "{speed} Hz: map {rate:.4} 1/s at {freq:.3} Hz; time run {run_rate:.4} 1/s, \
         peak {run_freq:.3} Hz"
    );
    assert!(
        (run_rate - rate).abs() < 0.03 * rate,
        "time run {run_rate} 1/s vs map {rate} 1/s"
    );
    assert!(
        (run_freq - freq).abs() < 0.1,
        "time run {run_freq} Hz vs map {freq} Hz"
    );
}
