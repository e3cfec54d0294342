//! Run-ups and coast-downs through a critical speed, order-tracked (issue 11), against the
//! closed form of a Jeffcott rotor: a stiff steel cylinder Ø200 × 400 mm (bending above 1 kHz)
//! on two equal isotropic linear supports k, c, so its bounce mode is a Jeffcott rotor of the
//! whole mass m on 2k, 2c (tests/it/linear_jeffcott.rs; Friswell et al., *Dynamics of Rotating
//! Machines*, 2010, §3.5): a central unbalance m_u e at body angle α whirls forward with
//! x + iy = m_u e Ω² e^{i(θ + α)} / (2k − mΩ² + 2icΩ), so the horizontal 1× is
//! X = m_u e Ω² e^{iα} / (2k − mΩ² + 2icΩ) and the vertical Y = −iX (x = Re(X e^{iθ})).
//! A slow ramp must track that steady state; a fast one lags it: the peak comes later and
//! lower on a run-up (and earlier on a coast-down) than the steady-state peak (Lewis 1932;
//! Genta, *Dynamics of Rotating Systems*, 2005, §4.7).

use crate::support;

use std::f64::consts::{PI, TAU};

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation;
use rotorsweep::signal::orders;
use rustfft::num_complex::Complex64;

const K: f64 = 1.0e5;
const C: f64 = 450.0;
const MU_E: f64 = 0.010 * 0.100;
const ALPHA: f64 = PI / 6.0;

/// The stiff Jeffcott rotor ramped by the `[speed]` lines `speed`, recorded over [settle, end].
fn run(speed: &str, settle: f64, end: f64) -> simulation::JobResult {
    let spring =
        format!("kx_n_per_m = {K}, ky_n_per_m = {K}, cx_ns_per_m = {C}, cy_ns_per_m = {C}");
    let tail = format!(
        "[speed]\n{speed}\n[simulation]\nt_end_s = {end}\nsettle_s = {settle}\n\
         sample_rate_hz = 500.0\ngravity_m_s2 = 0.0\nstatic_start = false\n\
         [solver]\nhmax = 1e-3\ntolerance = 1e-9\n"
    );
    let text = support::stiff_jeffcott(&spring, "", &tail);
    let scene = support::scene_from_text("runup.toml", &text);
    assert!(
        scene.outputs.speed,
        "a ramp records speed and roll angle by default"
    );
    let model = Model::build(&scene, None).unwrap();
    let r = simulation::run(&scene, &model);
    assert_eq!(r.stats.status.name(), "ok", "{}", r.stats.cause);
    r
}

/// The rotor's mass [kg] (cylinder + the 10 g mass) and the closed-form horizontal 1× [µm].
fn closed_form(f_hz: f64) -> Complex64 {
    let m = 7850.0 * PI * 0.1f64.powi(2) * 0.4 + 0.010;
    let w = TAU * f_hz;
    let x = MU_E * w * w * Complex64::from_polar(1.0, ALPHA)
        / Complex64::new(2.0 * K - m * w * w, 2.0 * C * w);
    1e6 * x
}

/// Tracked 1× blocks of `revs` revolutions, half overlapping, of the centre's horizontal and
/// vertical runout.
fn tracked(r: &simulation::JobResult, revs: f64) -> Vec<orders::Block> {
    let t = &r.time;
    let theta = support::channel(r, "speed/roll_angle");
    let h = support::channel(r, "runout/centre/horizontal");
    let v = support::channel(r, "runout/centre/vertical");
    orders::track(t, theta, &[h, v], &[1.0], revs, 0.5 * revs).unwrap()
}

/// The speed and amplitude of the highest tracked horizontal 1× block.
fn peak(blocks: &[orders::Block]) -> (f64, f64) {
    blocks
        .iter()
        .map(|b| (b.speed_hz, b.amplitudes[0][0].norm()))
        .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

/// The worst relative amplitude error and phase error [deg] of tracked 1× blocks against the
/// closed form, horizontal and vertical.
fn worst(blocks: &[orders::Block]) -> (f64, f64) {
    let (mut amp, mut phase) = (0.0f64, 0.0f64);
    for b in blocks {
        let x = closed_form(b.speed_hz);
        let y = Complex64::new(0.0, -1.0) * x;
        for (z, e) in [(b.amplitudes[0][0], x), (b.amplitudes[1][0], y)] {
            amp = amp.max((z.norm() / e.norm() - 1.0).abs());
            phase = phase.max((z / e).arg().abs().to_degrees());
        }
    }
    (amp, phase)
}

#[test]
fn slow_run_up_tracks_the_steady_state_unbalance_response() {
    // ω_n = √(2k/m) = 45.0 rad/s (7.17 Hz), ζ = 2c/(2√(2km)) = 0.101. 3 → 12 Hz at 0.02 Hz/s:
    // α = 0.126 rad/s², η = α/ω_n² = 6e-5 ≪ ζ² = 0.010, a slow ramp: within 1 % and 1° of the
    // closed form over the whole sweep, the resonance included (a block averages 8 revs, less
    // than 0.03 Hz of speed, against a half-power width 2ζf_n = 1.45 Hz). The remaining error
    // is the response's lag behind the steady state, first order in the rate: five times the
    // rate gives about five times the error.
    let slow = |rate: f64| {
        let secs = 9.0 / rate;
        let r = run(
            &format!(
                "profile = \"ramp\"\nfrom_hz = 3.0\nto_hz = 12.0\nramp_start_s = 3.0\n\
                 rate_hz_per_s = {rate}"
            ),
            3.0,
            3.0 + secs,
        );
        // The speed channel follows the ramp.
        let sp = support::channel(&r, "speed/hz");
        assert!((sp[0] - 3.0).abs() < 1e-9 && (sp[sp.len() - 1] - 12.0).abs() < 1e-9);
        let blocks = tracked(&r, 8.0);
        assert!(blocks.len() > 100);
        worst(&blocks)
    };
    let (a1, p1) = slow(0.02);
    assert!(a1 < 0.01, "amplitude off by {a1}");
    assert!(p1 < 1.0, "phase off by {p1} deg");
    let (a5, p5) = slow(0.1);
    eprintln!(
        "worst 1x error at 0.02 Hz/s: {a1:.2e}, {p1:.3} deg; at 0.1 Hz/s: {a5:.2e}, {p5:.3} deg"
    );
    assert!((3.5..6.5).contains(&(a5 / a1)), "{a5} / {a1}");
    assert!((3.5..6.5).contains(&(p5 / p1)), "{p5} / {p1}");
}

#[test]
fn fast_ramps_shift_and_lower_the_peak_with_the_direction_of_the_ramp() {
    // At 3 Hz/s, η = 18.8/2025 = 9.3e-3 ≈ ζ²: the run-up's peak lies above the steady-state
    // peak speed (7.17/√(1 − 2ζ²) = 7.25 Hz for the displacement of an unbalance-driven
    // Jeffcott) and lower than its amplitude; the coast-down's lies below the steady peak,
    // lower too.
    let steady: Vec<f64> = (0..2000)
        .map(|i| closed_form(3.0 + 0.005 * i as f64).norm())
        .collect();
    let (i_max, a_max) =
        steady
            .iter()
            .enumerate()
            .fold((0, 0.0), |a, (i, v)| if *v > a.1 { (i, *v) } else { a });
    let f_max = 3.0 + 0.005 * i_max as f64;
    assert!((f_max - 7.25).abs() < 0.02, "{f_max}");
    let up = tracked(
        &run(
            "profile = \"ramp\"\nfrom_hz = 3.0\nto_hz = 12.0\nramp_start_s = 3.0\nrate_hz_per_s = 3.0",
            3.0,
            7.0,
        ),
        2.0,
    );
    let down = tracked(
        &run(
            "profile = \"ramp\"\nfrom_hz = 12.0\nto_hz = 3.0\nramp_start_s = 3.0\nrate_hz_per_s = 3.0",
            3.0,
            7.0,
        ),
        2.0,
    );
    let (fu, au) = peak(&up);
    let (fd, ad) = peak(&down);
    eprintln!("steady peak {a_max:.2} um at {f_max:.3} Hz; run-up {au:.2} um at {fu:.3} Hz, coast-down {ad:.2} um at {fd:.3} Hz");
    assert!(fu > f_max + 0.1, "run-up peak at {fu} Hz");
    assert!(fd < f_max - 0.1, "coast-down peak at {fd} Hz");
    assert!(au < 0.99 * a_max && ad < 0.99 * a_max, "{au} {ad} {a_max}");
}

#[test]
fn measured_speed_table_is_followed_and_tracked() {
    // A speed–time table 4 → 10 → 6 Hz (run-up, then coast-down), linear between its points:
    // the roll angle is its exact integral, and slow enough (0.02 Hz/s) that the tracked 1×
    // reads the closed form within 1 % and 1° on both legs.
    let r = run(
        "profile = \"table\"\ntimes_s = [0.0, 3.0, 303.0, 503.0]\ntable_hz = [4.0, 4.0, 10.0, 6.0]",
        3.0,
        503.0,
    );
    let theta = support::channel(&r, "speed/roll_angle");
    // θ(303) = 2π(4·3 + (4 + 10)/2·300) = 2π·2112.
    let i = r
        .time
        .iter()
        .position(|t| (t - 303.0).abs() < 1e-9)
        .unwrap();
    assert!((theta[i] - TAU * 2112.0).abs() < 1e-6, "{}", theta[i]);
    let blocks = tracked(&r, 8.0);
    assert!(blocks.iter().any(|b| b.time_s > 400.0 && b.speed_hz < 8.0));
    let (amp, phase) = worst(&blocks);
    assert!(amp < 0.01 && phase < 1.0, "{amp} {phase}");
}

#[test]
fn a_study_stores_tracked_orders_and_the_report_lists_them() {
    // A study of two jobs on the stiff Jeffcott: a run-up 3 → 12 Hz at 1 Hz/s and a constant
    // 7 Hz. `report --table orders --format json` has one row per job, order, block, sensor and
    // direction: the constant job one block, equal to its `/analysis/lines` entry; the ramp's
    // blocks ascend in speed and it has a waterfall.
    let dir = support::scratch("runup");
    let spring =
        format!("kx_n_per_m = {K}, ky_n_per_m = {K}, cx_ns_per_m = {C}, cy_ns_per_m = {C}");
    let tail = "[speed]\nprofile = \"ramp\"\nhz = 7.0\nfrom_hz = 3.0\nto_hz = 12.0\n\
                ramp_start_s = 1.0\nrate_hz_per_s = 1.0\n[simulation]\nt_end_s = 10.0\n\
                settle_s = 1.0\nsample_rate_hz = 500.0\ngravity_m_s2 = 0.0\n\
                static_start = false\n[solver]\nhmax = 1e-3\ntolerance = 1e-9\n";
    support::write_file(
        &dir,
        "scene.toml",
        &support::stiff_jeffcott(&spring, "", tail),
    );
    let study = support::write_file(
        &dir,
        "study.toml",
        "name = \"runup-test\"\nscene = \"scene.toml\"\n[[axes]]\nkey = \"speed.profile\"\n\
         values = [\"ramp\", \"constant\"]\nlabels = [\"ramp\", \"constant\"]\n[analysis]\n\
         orders = [1.0, 2.0]\norder_revolutions = 4.0\n",
    );
    let out = dir.join("out.h5");
    support::rotorsweep_ok(&["run", study.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let table = &support::report_table(&out, "orders");
    let cols: Vec<&str> = table["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    let col = |n: &str| cols.iter().position(|c| *c == n).unwrap();
    for n in [
        "job_id",
        "order",
        "speed_hz",
        "sensor",
        "direction",
        "amplitude_um",
        "phase_deg",
    ] {
        assert!(cols.contains(&n), "{n} in {cols:?}");
    }
    let rows = table["rows"].as_array().unwrap();
    let f = hdf5::File::open(&out).unwrap();
    let job_of = |label: &str| {
        let jobs = f.group("jobs").unwrap();
        jobs.member_names()
            .unwrap()
            .into_iter()
            .find(|id| {
                let g = jobs.group(id).unwrap();
                rotorsweep::store::read_str(&g, "label:speed.profile").unwrap() == label
            })
            .unwrap()
    };
    let (ramp, constant) = (job_of("ramp"), job_of("constant"));
    let of = |id: &str| -> Vec<&Vec<serde_json::Value>> {
        rows.iter()
            .map(|r| r.as_array().unwrap())
            .filter(|r| r[col("job_id")] == id)
            .collect()
    };
    // The constant job: 2 orders × 2 directions, one block.
    let c_rows = of(&constant);
    assert_eq!(c_rows.len(), 4);
    let one_h = c_rows
        .iter()
        .find(|r| r[col("order")] == 1.0 && r[col("direction")] == "horizontal")
        .unwrap();
    let amp = one_h[col("amplitude_um")].as_f64().unwrap();
    let x = closed_form(7.0);
    // Its 7 Hz record starts 1 s after the jump to speed (the transient's time constant
    // 1/(ζω_n) = 0.22 s leaves e^-4.5): within 2 % of the closed form.
    assert!((amp / x.norm() - 1.0).abs() < 0.02, "{amp} vs {}", x.norm());
    // The ramp: blocks of 4 revolutions (the first spans 3 → 4.1 Hz), half overlapping, 1×
    // speeds ascending to 12 Hz.
    let r_rows: Vec<_> = of(&ramp)
        .into_iter()
        .filter(|r| r[col("order")] == 1.0 && r[col("direction")] == "vertical")
        .collect();
    let speeds: Vec<f64> = r_rows
        .iter()
        .map(|r| r[col("speed_hz")].as_f64().unwrap())
        .collect();
    assert!(speeds.len() > 30, "{}", speeds.len()); // 67.5 revolutions, hop 2
    assert!(speeds.windows(2).all(|w| w[1] >= w[0]));
    assert!(
        speeds[0] < 4.0 && *speeds.last().unwrap() > 11.5,
        "{speeds:?}"
    );
    let wf = f.group(&format!("jobs/{ramp}/waterfall")).unwrap();
    let map = wf.dataset("map/centre/vertical").unwrap().shape();
    let n_speeds = wf.dataset("speed_hz").unwrap().shape()[0];
    assert_eq!(map[0], n_speeds);
    // The static part is removed per block (stored apart, one per block): 0 Hz holds only the
    // fluctuation's Hann leakage, at most A·|sinc d/(1 − d²)| ≤ 2.7 % of a line d ≥ 1.9 bins
    // away (the window's highest sidelobe), so below 5 % of the block's peak (the 1×, read
    // within the Hann scalloping loss of 15 %) from 1.9 / 0.512 s = 3.7 Hz on; below that the
    // 1× lies inside the window's ±2-bin main lobe around 0 Hz (src/results/orders.rs).
    let means = wf.dataset("mean/centre/vertical").unwrap().shape();
    assert_eq!(means, vec![n_speeds]);
    let freq: Vec<f64> = wf.dataset("freq_hz").unwrap().read_raw().unwrap();
    let block_s = 1.0 / freq[1];
    assert!((block_s - 0.512).abs() < 1e-9, "{block_s}");
    let wf_speeds: Vec<f64> = wf.dataset("speed_hz").unwrap().read_raw().unwrap();
    let rows: Vec<f64> = wf
        .dataset("map/centre/vertical")
        .unwrap()
        .read_raw()
        .unwrap();
    let mean_v: Vec<f64> = wf
        .dataset("mean/centre/vertical")
        .unwrap()
        .read_raw()
        .unwrap();
    // Nothing static here (no gravity, no offset): each stored mean is the fit's error alone
    // (the 1× changes in amplitude and speed within a block), below 2 % of the block's peak,
    // where the plain mean would hold up to |sin πd|/(πd) of the 1× (21 % at d = 1.5, the
    // first blocks; 5 % at d = 1.9).
    for (b, row) in rows.chunks(map[1]).enumerate() {
        let peak = row[1..].iter().copied().fold(0.0, f64::max);
        assert!(
            mean_v[b].abs() < 0.02 * peak,
            "block {b}: {} {peak}",
            mean_v[b]
        );
    }
    let mut checked = 0;
    for (b, row) in rows.chunks(map[1]).enumerate() {
        if wf_speeds[b] * block_s < 1.9 {
            continue;
        }
        let peak = row[1..].iter().copied().fold(0.0, f64::max);
        assert!(
            row[0] < 0.05 * peak,
            "block {b} at {} Hz: {row:?}",
            wf_speeds[b]
        );
        checked += 1;
    }
    assert!(checked + 3 >= n_speeds, "{checked} of {n_speeds}");
    // The default range: 1.25 × the highest order (2) × the highest block speed.
    let cap = 2.5 * wf_speeds.iter().copied().fold(0.0, f64::max);
    let top = *freq.last().unwrap();
    assert!(top <= cap && top > cap - freq[1], "{top} {cap}");
    assert!(f.group(&format!("jobs/{constant}/waterfall")).is_err());
}
