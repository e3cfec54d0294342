//! Issue 2's target: the reference roll's FE model and its reduction to "30n+12st" in under 0.2 s.
//!
//! `load_and_build`: `Scene::load` (TOML, thickness-map CSV) + `Model::build` (mesh, section
//! quadrature over the map, assembly, Craig–Bampton, orthogonalisation, selection).
//! `build`: `Model::build` alone, the scene loaded once beforehand. `load`: `Scene::load` alone.
//! Run with `cargo bench --bench model_build`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use rotorsweep::dynamics::model::Model;
use rotorsweep::rotor::reduction::ModeSelection;
use rotorsweep::scene::Scene;

fn reference_roll() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/scenes/reference-roll.toml")
}

fn model_build(c: &mut Criterion) {
    let path = reference_roll();
    let modes = ModeSelection::parse("30n+12st").expect("mode selection");
    let scene = Scene::load(&path, &[]).expect("reference scene");
    let model = Model::build(&scene, Some(&modes)).expect("model");
    eprintln!(
        "reference roll: {} elements, {} nodes, {} DOFs -> {} modal coordinates ({})",
        model.rotor.elements.len(),
        model.rotor.node_z.len(),
        model.rotor.ndof(),
        model.reduced.len(),
        model.reduced.counts_label()
    );

    let mut g = c.benchmark_group("reference_roll_30n12st");
    g.sample_size(20).measurement_time(Duration::from_secs(10));
    g.bench_function("load_and_build", |b| {
        b.iter(|| {
            let scene = Scene::load(black_box(&path), &[]).expect("scene");
            Model::build(&scene, Some(&modes)).expect("model")
        })
    });
    g.bench_function("build", |b| {
        b.iter(|| Model::build(black_box(&scene), Some(&modes)).expect("model"))
    });
    g.bench_function("load", |b| {
        b.iter(|| Scene::load(black_box(&path), &[]).expect("scene"))
    });
    g.finish();
}

criterion_group!(benches, model_build);
criterion_main!(benches);
