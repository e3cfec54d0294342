//! Export: a scene's model and its linear plant, out to other tools.
//!
//! In: a validated scene, its [`Model`](crate::dynamics::model::Model) and (for the plant) its
//! [`LinearSystem`](crate::dynamics::LinearSystem). Out: [`model`] writes the full FE body's
//! or the reduced model's matrices as Matrix Market files, the node and DOF tables as CSV, a
//! documented HDF5 file `model.h5` and, for the full body, a scene `scene.toml` that runs on
//! the exported body; [`plant`] writes the linear plant at one speed as a state-space model
//! (A, B, C, D with named inputs and outputs) to HDF5, `.npz` or `.mat` ([`mat`]). docs/export.md documents the
//! layouts. SI units throughout, stated in each file.

pub mod mat;
pub mod model;
pub mod plant;
