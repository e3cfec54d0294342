//! The tables of `rotorsweep report`, one builder per table (two for the paired `orders` /
//! `order_resonances` and `balancing` / `balancing_residual`): each reads what it needs from the
//! results file (or takes the [`Job`](super::jobs::Job)s) and gives a
//! [`Table`](super::Table), or none when the file holds nothing for it.

mod balancing;
mod calibration;
mod linear;
mod nips;
pub(crate) mod orders;
pub(crate) mod outputs;
mod per_grid_point;
mod resonances;
mod samples;
mod sensitivity;
mod solver;
mod stability;
mod statistics;
mod trial_mass;

pub(crate) use balancing::balancing_tables;
pub(crate) use calibration::{
    calibration_hint, calibration_overview, calibration_tables, is_calibration,
};
pub(crate) use linear::linear_table;
pub(crate) use nips::nips_table;
pub(crate) use orders::{order_resonance_table, orders_table, records, OrderRow};
pub(crate) use per_grid_point::{per_grid_point, Builder};
pub(crate) use resonances::{pick, resonance_table};
pub(crate) use samples::samples_table;
pub(crate) use sensitivity::sensitivity_table;
pub(crate) use solver::solver_table;
pub(crate) use stability::stability_table;
pub(crate) use statistics::statistics_table;
pub(crate) use trial_mass::trial_mass_table;
