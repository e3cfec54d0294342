//! The `balancing` and `balancing_residual` tables of `rotorsweep report`, for a study results
//! file of trial-mass runs (`study::balancing`: an `[analysis] baseline` on a masses axis, one
//! trial-mass run per plane and speed).
//!
//! In: the results file's path (the corrections come from its `/analysis/lines`; the
//! model-based reference needs the study file the run named, read as `rotorsweep balance
//! --check` reads it). Out: `balancing`, one row per method and correction mass — `influence`
//! (the influence coefficients' least-squares corrections over all planes and speeds, without
//! constraints: `rotorsweep balance`'s `corrections`) and `ideal` (the scene's model-based
//! balancing of the same roll in the same planes, from the model's own unbalance, which a
//! workshop never knows: the reference) — with plane z [mm], radius [mm], mass [g] and angle
//! [deg]; `balancing_residual`, per speed, sensor and direction the reference run's 1× [µm] and
//! the 1× predicted after each method's masses through the same influence coefficients.
//! Without the study file the `ideal` rows and column are left out and the legend says why.

use std::path::Path;

use crate::report::table::{Cell, Table};
use crate::signal::influence::PlaneLimits;
use crate::study::balancing::{self, Correction};

/// The two tables, or None when the file is not a balancing study.
pub(crate) fn balancing_tables(path: &Path) -> Option<Vec<Table>> {
    let b = balancing::balance(path, &PlaneLimits::default()).ok()?;
    let ideal = balancing::ideal(&b, None);
    let mass_rows = |method: &str, cs: &[Correction]| -> Vec<Vec<Cell>> {
        cs.iter()
            .map(|c| {
                vec![
                    Cell::Text(method.into()),
                    Cell::Number(c.z_mm),
                    Cell::Number(c.radius_mm),
                    Cell::Number(c.mass_g),
                    Cell::Number(c.angle_deg),
                ]
            })
            .collect()
    };
    let mut rows = mass_rows("influence", &b.corrections);
    let note = match &ideal {
        Ok(i) => {
            rows.extend(mass_rows("ideal", &i.corrections));
            String::new()
        }
        Err(e) => format!(" (no `ideal` rows: {e})"),
    };
    let corrections = Table {
        name: "balancing".into(),
        title: "Balancing masses".into(),
        legend: format!(
            "Per method and plane the correction mass [g] at its radius [mm] and body angle \
             [deg] (the scene's convention) in the plane at z [mm]: `influence`, least squares \
             over the trial-mass runs' influence coefficients at all speeds (`rotorsweep \
             balance`); `ideal`, the model's own balancing from its unbalance (roll.balancing \
             in the same planes), the reference{note}"
        ),
        columns: ["method", "z_mm", "radius_mm", "mass_g", "angle_deg"]
            .map(String::from)
            .to_vec(),
        rows,
        markdown: None,
    };
    let ideal_after = ideal.as_ref().ok().map(|i| &i.predicted);
    let rows = b
        .predicted
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let mut row = vec![
                Cell::Number(p.speed_hz),
                Cell::Text(p.sensor.clone()),
                Cell::Text(p.direction.clone()),
                Cell::Number(p.before_um),
                Cell::Number(p.after_um),
            ];
            if let Some(a) = ideal_after {
                row.push(Cell::Number(a[k].after_um));
            }
            row
        })
        .collect();
    let mut columns: Vec<String> = [
        "speed_hz",
        "sensor",
        "direction",
        "before_um",
        "influence_um",
    ]
    .map(String::from)
    .to_vec();
    if ideal_after.is_some() {
        columns.push("ideal_um".into());
    }
    let residual = Table {
        name: "balancing_residual".into(),
        title: "Predicted 1× after balancing".into(),
        legend: format!(
            "Per speed [Hz], sensor and direction: the reference run's 1× amplitude [µm] and the \
             1× predicted by the influence coefficients after each method's masses of the \
             `balancing` table{note}"
        ),
        columns,
        rows,
        markdown: None,
    };
    Some(vec![corrections, residual])
}
