//! Study files: a base scene and sweep axes → a list of fully resolved jobs.
//!
//! In: a study `.toml` (the commented `studies/smoke.toml` documents the format): a base scene,
//! overrides for every job (`[set]`), sweep axes (cartesian product; an axis with several `keys`
//! moves them together, i.e. zipped), explicit `[[jobs]]`, a `[reference]` solver setting, a
//! per-job `[budget]`, and optional strain-energy pruning (the pseudo-key
//! `reduction.prune_threshold`, swept like any other key; 0 means the unpruned pilot).
//! Out: a [`Study`] with its [`Job`]s — each the scene's key=value overrides, a stable id (a hash
//! of every input that defines the job), the id of the reduced model it needs and of the
//! reference run it is compared with. Errors name the study file, the line, the key and the
//! reason; every job's scene, every reference's and every pruning pilot's is validated before
//! anything runs. Also errors: more than [`MAX_JOBS`] jobs (counted before the axes are
//! expanded), an axis value given twice (`10` and `10.0` alike), a key of `[set]`, the axes,
//! `[[jobs]]`, `[budget]`, `[reference]` or `[pruning]` that replaces one applied before it
//! (`speed.hz` after `speed.hz.x`),
//! `[pruning]` without pruned jobs or with model keys. The study's `[budget]` binds the reference
//! runs too, unless `[reference]` sets `solver.cpu_budget_s` / `solver.max_steps` itself.
//!
//! The files, in the order `Study::load` uses them: `file` (the raw tables), `context` (where
//! errors point), `axes`, `limit`, `grid` (the product of the axes and the explicit jobs),
//! `sample` (a `[sample]` table's jobs instead of the grid's),
//! `reference`, `pruning`, `budget`, `analysis`, `linear`, `replaced_keys`, `expand` (each job's
//! overrides, scene, ids and reference), with `values` (values as text) and `ids` (the hashes);
//! `jobs` holds the jobs and references, `load` the [`Study`].

pub mod balancing;
pub mod identity;
pub mod merge;
pub mod overview;
pub mod plan;
pub mod progress;
pub mod run;
pub mod sample;

mod analysis;
mod axes;
mod budget;
mod context;
mod expand;
mod file;
mod grid;
mod ids;
mod job_table;
mod jobs;
mod limit;
mod linear;
mod load;
mod pruning;
mod reference;
mod replaced_keys;
mod values;

pub use ids::fnv1a;
pub(crate) use ids::pilot_text;
pub use jobs::{Job, Reference, SceneFacts};
pub use limit::MAX_JOBS;
pub use linear::LINEAR_SPEEDS;
pub use load::Study;
pub use pruning::PRUNE_KEY;
pub(crate) use values::value_text;
