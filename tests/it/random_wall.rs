//! A random wall given by its spectrum per circumferential harmonic
//! (`[[roll.shell.random_wall.spectrum]]`, src/rotor/wall/random_field.rs) in a scene and in a
//! sampled study: each job's wall drawn from its seed, the same bytes at one and two threads and
//! through shards, its realised statistics stored against their closed form, and bad spectra
//! refused naming file, key and line. (The field's distribution — variance Σ σ_n², Rayleigh
//! amplitudes — is checked on 2000 realisations by the unit tests of random_field.rs.)

use crate::support;

use rotorsweep::scene::Scene;
use rotorsweep::study::Study;
use support::{assert_error_at, scratch, write_file};

/// The reference roll (studies/scenes/reference-roll.toml) with a random wall of harmonics 1
/// and 2 (0.20 and 0.15 mm), the same along the whole shell (no correlation length along).
fn spectral_scene() -> String {
    let base = support::repo().join("studies/scenes/reference-roll.toml");
    format!(
        "extends = {:?}\nname = \"spectral-wall\"\n\
         [roll.shell.random_wall]\nseed = 1\nmean_mm = 18.72\n\
         [[roll.shell.random_wall.spectrum]]\norder = 1\nstd_mm = 0.20\n\
         [[roll.shell.random_wall.spectrum]]\norder = 2\nstd_mm = 0.15\n",
        base.display().to_string()
    )
}

/// The job attribute `name` of job `id` in the results file `content`.
fn attr(content: &[(String, Vec<u64>)], id: &str, name: &str) -> f64 {
    let path = format!("{id}@{name}");
    let (_, bits) = content
        .iter()
        .find(|(p, _)| *p == path)
        .unwrap_or_else(|| panic!("no {path}"));
    f64::from_bits(bits[0])
}

/// A Monte Carlo study of three jobs, each its own wall (distribution "seed") and its own σ_2
/// (uniform 0.10 … 0.20 mm on `spectrum[1].std_mm`). Every job's stored statistics follow the
/// closed form of a wall of two harmonics constant along z, t = mean + a_1 cos(φ − θ_1) +
/// a_2 cos(2φ − θ_2): the grid mean is the mean (no order 0), the mode-weighted amplitudes are
/// a_1, a_2 (the same at every station), and the population variance over the 36 angles is
/// (a_1² + a_2²)/2. The runs at one and two threads and the merged shards hold the same bytes.
#[test]
fn a_spectral_wall_is_drawn_per_job_reproducibly_with_its_statistics_stored() {
    let d = scratch("random-wall-spectrum");
    write_file(&d, "wall.toml", &spectral_scene());
    let path = write_file(
        &d,
        "s.toml",
        "name = \"spectral-mc\"\nscene = \"wall.toml\"\n\
         [set]\n\"simulation.t_end_s\" = 0.2\n\"simulation.settle_s\" = 0.1\n\
         [sample]\nmethod = \"monte-carlo\"\nn = 3\nseed = 5\n\
         [[sample.parameters]]\nkey = \"roll.shell.random_wall.seed\"\ndistribution = \"seed\"\n\
         [[sample.parameters]]\nkey = \"roll.shell.random_wall.spectrum[1].std_mm\"\n\
         distribution = \"uniform\"\nlower = 0.10\nupper = 0.20\n",
    );
    let st = Study::load(&path).unwrap();
    assert_eq!(st.jobs.len(), 3);
    let [one, two, merged] = support::contents_at_one_two_threads_and_shards(&st, &d);
    assert_eq!(one, two);
    assert_eq!(one, merged);
    let mut h1s = Vec::new();
    for job in &st.jobs {
        let id = format!("jobs/{}", job.id);
        let (mean, std) = (
            attr(&one, &id, "wall_mean_mm"),
            attr(&one, &id, "wall_std_mm"),
        );
        let (h1, h2) = (attr(&one, &id, "wall_h1_mm"), attr(&one, &id, "wall_h2_mm"));
        eprintln!(
            "{}: mean {mean} mm, std {std} mm, h1 {h1} mm, h2 {h2} mm",
            job.id
        );
        assert!((mean - 18.72).abs() < 1e-9, "{mean}");
        let closed = ((h1 * h1 + h2 * h2) / 2.0).sqrt();
        assert!((std - closed).abs() < 1e-9 * closed, "{std} vs {closed}");
        h1s.push(h1);
    }
    h1s.sort_by(f64::total_cmp);
    assert!(h1s.windows(2).all(|w| w[0] < w[1]), "each job its own wall");
}

/// Each bad spectrum is refused at its key and line in the scene file; a bad override at
/// `<command line --set>` with its key.
#[test]
fn a_bad_spectrum_names_its_file_key_and_line() {
    let d = scratch("random-wall-spectrum-errors");
    let good = spectral_scene();
    let k = "roll.shell.random_wall";
    // (the line replaced, its replacement, the line the error is at, the key, the reason)
    let cases: [(&str, &str, &str, &str, &str); 8] = [
        (
            "order = 2",
            "order = 2.5",
            "order = 2.5",
            "spectrum[1].order",
            "a whole number",
        ),
        (
            "order = 2",
            "order = 0",
            "order = 0",
            "spectrum[1].order",
            "order 0 is the mean wall",
        ),
        (
            "order = 2",
            "order = 18",
            "order = 18",
            "spectrum[1].order",
            "the orders 1 … 17",
        ),
        (
            "order = 2",
            "order = 1 # again",
            "order = 1 # again",
            "spectrum[1].order",
            "order 1 is given twice",
        ),
        (
            "std_mm = 0.15",
            "std_mm = -0.15",
            "std_mm = -0.15",
            "spectrum[1].std_mm",
            "got -0.15",
        ),
        (
            "std_mm = 0.15",
            "std_mm = nan",
            "std_mm = nan",
            "spectrum[1].std_mm",
            "got NaN",
        ),
        (
            "seed = 1",
            "seed = 1\nstd_mm = 0.3",
            "std_mm = 0.3",
            "std_mm",
            "not both",
        ),
        (
            "order = 1",
            "order = \"one\"",
            "order = \"one\"",
            "spectrum[0].order",
            "expected f64: the key takes a number, written without quotes",
        ),
    ];
    for (old, new, at, key, reason) in cases {
        let text = good.replacen(old, new, 1);
        let path = write_file(&d, "bad.toml", &text);
        let e = Scene::load(&path, &[]).expect_err(new);
        assert_error_at(&e, &path, &text, (&format!("{k}.{key}"), at, reason));
    }
    // Every harmonic at 0: the wall would be uniform.
    let text = good
        .replace("std_mm = 0.20", "std_mm = 0.0")
        .replace("std_mm = 0.15", "std_mm = 0");
    let path = write_file(&d, "zero.toml", &text);
    let e = Scene::load(&path, &[]).unwrap_err();
    assert_eq!(
        e.key.as_deref(),
        Some("roll.shell.random_wall.spectrum"),
        "{e}"
    );
    assert!(e.reason.contains("positive std_mm"), "{e}");
    // Through an override.
    let path = write_file(&d, "wall.toml", &good);
    let e = Scene::load(&path, &[format!("{k}.spectrum[1].std_mm=-1")]).unwrap_err();
    assert_eq!(e.file.to_string_lossy(), "<command line --set>", "{e}");
    assert_eq!(
        e.key.as_deref(),
        Some("roll.shell.random_wall.spectrum[1].std_mm"),
        "{e}"
    );
    // The good scene loads, its wall the realisation of its seed.
    let scene = Scene::load(&path, &[]).unwrap();
    let w = scene.wall_field.expect("a random wall's statistics");
    assert!((w.mean_mm - 18.72).abs() < 1e-9);
}
