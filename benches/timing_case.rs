//! Issue 3's target: the source's timing case (studies/scenes/timing-case.toml: reference roll,
//! 30n+12st, map, roundness and contacts, 16.4 Hz, 10 s simulated, BDF at 1e-7 m and hmax 100 µs)
//! in at most 0.5 s of CPU on one core. The job runs on one thread, so its wall time is its CPU
//! time; the job's own thread-CPU statistic is printed beside criterion's numbers.
//! Run with `cargo bench --bench timing_case`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation;
use rotorsweep::scene::Scene;

fn timing_case(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/scenes/timing-case.toml");
    let scene = Scene::load(&path, &[]).expect("timing case scene");
    let model = Model::build(&scene, None).expect("model");
    let r = simulation::run(&scene, &model);
    eprintln!(
        "timing case: status {}, {} steps, {} rejected, {:.3} iterations/step, CPU {:.3} s",
        r.stats.status.name(),
        r.stats.steps,
        r.stats.rejected(),
        r.stats.iterations_per_step(),
        r.stats.cpu_time_s
    );
    let mut g = c.benchmark_group("timing_case");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    g.bench_function("bdf_10s_hmax100us", |b| {
        b.iter(|| black_box(simulation::run(&scene, &model)))
    });
    g.finish();
}

criterion_group!(benches, timing_case);
criterion_main!(benches);
