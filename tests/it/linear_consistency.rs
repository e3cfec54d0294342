//! The frequency-domain unbalance response against the time simulation (`simulation::run`, body frame,
//! BDF) at the same speed, on linear supports: the Jeffcott rotor of studies/scenes/jeffcott.toml
//! (shaft Ø30 × 700 mm, 12.331 kg disk, 20 g at 100 mm) on bearings with pedestal masses and
//! anisotropic ground springs (so the orbit is elliptic and has a backward part, in which the
//! rotating modal damping acts), a stationary damper at the disk, the default modal damping, no
//! gravity. The 1× line of the simulated runout, fitted as the study analysis does
//! (`signal::lines`, phase against roll angle 0), must equal the linear response within 1 % in
//! amplitude and 1° in phase, below and above the first critical speed (≈ 44 Hz).

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::integrators::Status;
use rotorsweep::linear::modes::{damped_modes, Split};
use rotorsweep::linear::response::sensor_response;

const PER_REV: f64 = 40.0;
const SETTLE_S: f64 = 1.0;
const REVS: f64 = 24.0;

/// The Jeffcott rotor on its pedestals, tolerance 1e-10 m, BDF up to order 5. This case showed
/// BDF's stability-lobe pathology (src/integrators/stability.rs): until the step was kept out of
/// the lobes of the order chosen (`Modes::stable_step`), its error test rejected a third of the
/// steps at 60 Hz (4 221 of 13 262 accepted, 0.20 s CPU, `untrusted`; measured); now 1 of 8 263
/// (0.012 s), and at 30 Hz 1 of 10 390 (was 1 185 of 13 191).
fn scene(hz: f64) -> rotorsweep::scene::Scene {
    let t_end = SETTLE_S + REVS / hz;
    let text = format!(
        r#"name = "jeffcott-consistency"
{rotor}
{mounting}
[speed]
hz = {hz}
[simulation]
t_end_s = {t_end}
settle_s = {SETTLE_S}
sample_rate_hz = {rate}
gravity_m_s2 = 0.0
[solver]
tolerance = 1e-10
hmax = 2e-4
"#,
        rotor = support::JEFFCOTT_ROTOR,
        mounting = support::JEFFCOTT_PEDESTALS,
        rate = PER_REV * hz,
    );
    support::scene_from_text("jeffcott-consistency.toml", &text)
}

#[test]
fn unbalance_response_equals_the_simulated_1x_line() {
    let model = Model::build(&scene(30.0), None).unwrap();
    for hz in [30.0, 60.0] {
        let s = scene(hz);
        let sys = LinearSystem::of_scene(&s, &model).unwrap();
        let w = 2.0 * std::f64::consts::PI * hz;
        assert!(!damped_modes(&sys, w, Split::Whirl).unwrap().unstable());
        let lin = sensor_response(&sys, w, &sys.unbalance).unwrap()[0];
        let ratio = lin.minor() / lin.major();
        assert!(
            ratio.abs() < 0.999,
            "{hz} Hz: minor/major {ratio}, should be elliptic"
        );
        let res = rotorsweep::dynamics::simulation::run(&s, &model);
        assert_eq!(res.stats.status, Status::Ok, "{}", res.stats.cause);
        let t = &res.time;
        for (name, want) in [
            ("runout/disk/vertical", lin.vertical),
            ("runout/disk/horizontal", lin.horizontal),
        ] {
            let x = support::channel(&res, name);
            let got = rotorsweep::signal::lines(x, t, &[hz])[0];
            let want_um = 1e6 * want.norm();
            let dphi = (got.arg() - want.arg()).to_degrees();
            let dphi = (dphi + 180.0).rem_euclid(360.0) - 180.0;
            eprintln!(
                "{hz} Hz {name}: simulated {:.4} um at {:.3}°, linear {want_um:.4} um at {:.3}°",
                got.norm(),
                got.arg().to_degrees(),
                want.arg().to_degrees()
            );
            assert!(
                (got.norm() / want_um - 1.0).abs() < 0.01,
                "{hz} Hz {name}: {} against {want_um} um",
                got.norm()
            );
            assert!(dphi.abs() < 1.0, "{hz} Hz {name}: phase off by {dphi}°");
        }
    }
}
