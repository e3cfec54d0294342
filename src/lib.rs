//! rotorsweep: overnight parameter studies of flexible-rotor dynamics.
//!
//! The modules are the pipeline's stages, listed in the order data flows through them; a stage
//! imports only from the stages above it (checked by the test `layering`):
//!
//! | stage | in → out |
//! |---|---|
//! | [`error`], [`text`] | shared by all: input errors naming file, line and key; numbers as text |
//! | [`numerics`] | dense kernels and eigen-solvers |
//! | [`signal`] | sampled records → spectra, lines, peaks, orders, influence coefficients |
//! | [`rotor`] | rotor spec → sections, wall map, beam FE, Craig–Bampton reduction; FE bodies imported from files |
//! | [`integrators`] | a second-order system and [`SolverSettings`](integrators::SolverSettings) → a time history |
//! | [`scene`] | scene TOML → validated [`Scene`](scene::Scene) in SI (a stage owns its parameters: the scene builds the rotor's and integrators' own types) |
//! | [`dynamics`] | scene → reduced model, linear and nonlinear systems on supports, one simulation |
//! | [`linear`] | linear system → damped modes, Campbell, critical speeds, response, Floquet, statics |
//! | [`store`] | results → the HDF5 layout and its writers |
//! | [`export`] | a scene's model → Matrix Market, CSV, HDF5 and a scene on the body; its linear plant → state space |
//! | [`results`] | a results file → its analysis, order tracking, balancing; measured records in |
//! | [`study`] | study TOML → jobs, plan, campaign run, shards, merge |
//! | [`report`] | a results file → tables (Markdown, CSV, JSON, HTML) |
//! | [`calibration`] | calibration TOML → parameters fitted to measured targets, every evaluation a study run |

#![warn(missing_docs)]

pub mod error;
pub mod text;

pub mod numerics;
pub mod signal;

pub mod rotor;

pub mod integrators;

pub mod scene;

pub mod dynamics;

pub mod linear;

pub mod store;

pub mod export;

pub mod results;

pub mod study;

pub mod report;

pub mod calibration;
