//! `plan`'s estimate of a machine (study/plan.rs): its record holds what a run of it writes
//! (every roll's channels and the nips' segment fields, counted from the run itself), and its
//! CPU estimate grows with the nip segments and with the rolls.

use std::path::Path;

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::run;
use rotorsweep::scene::Scene;
use rotorsweep::study::plan::{record_bytes, run_cpu_s};

fn two_roll(set: &[&str]) -> Scene {
    let path = support::repo().join("studies/scenes/two-roll-nip.toml");
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scene::load(&path, &set).unwrap_or_else(|e| panic!("{e}"))
}

/// The shipped two-roll nip with a third roll, the reference roll again below the first one,
/// pressed on it through a steel-on-steel nip of 20 segments.
fn three_roll(dir: &Path) -> Scene {
    let scenes = support::repo().join("studies/scenes");
    let text = std::fs::read_to_string(scenes.join("two-roll-nip.toml"))
        .unwrap()
        .replace("scene = \"", &format!("scene = \"{}/", scenes.display()));
    let third = format!(
        "\n[[rolls]]\nname = \"lower\"\nscene = \"{}/reference-roll.toml\"\n\
         position_mm = [0.0, -320.0]\nsurface_speed_of = \"reference\"\n\
         [[nips]]\nname = \"lower\"\nroll_a = \"reference\"\nroll_b = \"lower\"\nfrom_mm = 250.0\n\
         to_mm = 4250.0\nsegments = 20\nlaw = \"hertz\"\nline_load_kn_per_m = 10.0\n",
        scenes.display()
    );
    let path = support::write_file(dir, "three.toml", &(text + &third));
    Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_machines_record_estimate_is_what_its_run_writes() {
    // 0.5 s settling, 0.25 s recorded at 1 kHz: 251 samples.
    let scene = two_roll(&["simulation.t_end_s=0.75"]);
    let model = Model::build(&scene, None).unwrap();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    let samples = r.time.len();
    let values = r.time.len()
        + r.channels.iter().map(|c| c.data.len()).sum::<usize>()
        + r.fields.iter().map(|f| f.data.len()).sum::<usize>();
    assert_eq!(values % samples, 0);
    assert_eq!(
        record_bytes(&scene),
        (values * 8) as f64,
        "{samples} samples of {} values",
        values / samples
    );
    // Beyond the first roll's own record: the second roll's channels and the nip's fields.
    let first = &scene.machine.as_ref().unwrap().rolls[0].scene;
    assert!(record_bytes(&scene) > record_bytes(first) + (samples * 40 * 8) as f64);
}

#[test]
fn a_machines_cpu_estimate_grows_with_segments_and_rolls() {
    let cpu = |segments: usize| run_cpu_s(&two_roll(&[&format!("nips[0].segments={segments}")]));
    let (c10, c20, c40, c80) = (cpu(10), cpu(20), cpu(40), cpu(80));
    assert!(
        c10 < c20 && c20 < c40 && c40 < c80,
        "{c10} {c20} {c40} {c80}"
    );
    // Against the CPU measured on the shipped scene (module doc of study/plan.rs): 10 s
    // simulated of two-roll-nip.toml took 0.80 / 1.05 / 1.49 / 2.29 s at 10 / 20 / 40 / 80
    // segments (release build, 2 shared cores; estimated 0.78 / 0.99 / 1.41 / 2.25 s); the
    // shipped run is 1 s long.
    for (c, measured) in [(c10, 0.80), (c20, 1.05), (c40, 1.49), (c80, 2.29)] {
        let estimate = 10.0 * c;
        assert!(
            (estimate / measured - 1.0).abs() < 0.1,
            "{estimate} vs {measured} s"
        );
    }
    let dir = support::scratch("plan-three-rolls");
    let three = three_roll(&dir);
    // A third roll and a second nip of 20 segments: measured 1.57 s for 10 s simulated
    // (estimated 1.70 s).
    let c3 = run_cpu_s(&three);
    assert!(c3 > c20 + 0.5 * (c40 - c20), "{c3} vs {c20}");
    assert!((10.0 * c3 / 1.57 - 1.0).abs() < 0.15, "{c3}");
    assert!(record_bytes(&three) > record_bytes(&two_roll(&[])));
}
