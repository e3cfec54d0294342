//! A study's list of jobs as overrides, before any scene is read: the cartesian product of the
//! axes, then the explicit `[[jobs]]`.
//!
//! In: the axes' keys and rows ([`super::axes`]), their labels, the `[[jobs]]` tables.
//! Out: a [`Grid`]: every job's (dotted key, value) overrides and labels, the keys that vary
//! (axis keys in axis order, then the explicit jobs' keys), which axis sets which key, and how
//! many jobs come from the axes. The last axis varies fastest. Without axes, the explicit jobs
//! are the whole list (with neither, one job of the base scene). Errors: a key swept on two
//! axes, an explicit job without keys, labels that do not name their axis's rows.

use std::collections::BTreeMap;

use super::axes::{check_labels, AxisRows};
use super::context::Ctx;
use super::file::AxisFile;
use super::values::flatten;
use crate::error::InputError;

/// One job before expansion: its overrides (dotted key, value) and its labels (the axis's first
/// key, label).
pub(super) type Combo = (Vec<(String, toml::Value)>, Vec<(String, String)>);

/// The jobs of a study as overrides.
pub(super) struct Grid {
    /// Every job: the product of the axes first, then the explicit jobs.
    pub(super) combos: Vec<Combo>,
    /// Keys that vary between jobs, in axis order.
    pub(super) varying: Vec<String>,
    /// The axis that sets each swept key.
    pub(super) axis_of_key: BTreeMap<String, usize>,
    /// How many of the jobs come from the axes (the explicit jobs follow).
    pub(super) axis_combos: usize,
}

impl Grid {
    /// The product of the axes (`rows`: each axis's keys and rows), then the explicit `jobs`.
    pub(super) fn new(
        c: &Ctx,
        axes: &[AxisFile],
        rows: Vec<AxisRows>,
        jobs: &[toml::Table],
    ) -> Result<Grid, InputError> {
        let mut grid = Grid::product(c, axes, rows)?;
        if axes.is_empty() && !jobs.is_empty() {
            grid.combos.clear();
        }
        grid.axis_combos = grid.combos.len();
        grid.explicit(c, jobs)?;
        Ok(grid)
    }

    /// The product of the axes.
    fn product(c: &Ctx, axes: &[AxisFile], rows: Vec<AxisRows>) -> Result<Grid, InputError> {
        let mut combos: Vec<Combo> = vec![(Vec::new(), Vec::new())];
        let mut varying = Vec::new();
        let mut axis_of_key = BTreeMap::new();
        for (i, (a, (keys, rows))) in axes.iter().zip(rows).enumerate() {
            if let Some(l) = &a.labels {
                check_labels(c, i, l, rows.len())?;
            }
            for k in &keys {
                if axis_of_key.insert(k.clone(), i).is_some() {
                    return Err(c.err(&format!("axes[{i}]"), format!("key `{k}` is swept twice")));
                }
                varying.push(k.clone());
            }
            let mut next = Vec::with_capacity(combos.len() * rows.len());
            for combo in &combos {
                for (r, row) in rows.iter().enumerate() {
                    let mut c2 = combo.clone();
                    c2.0.extend(keys.iter().cloned().zip(row.iter().cloned()));
                    if let Some(l) = &a.labels {
                        c2.1.push((keys[0].clone(), l[r].clone()));
                    }
                    next.push(c2);
                }
            }
            combos = next;
        }
        Ok(Grid {
            combos,
            varying,
            axis_of_key,
            axis_combos: 0,
        })
    }

    /// Appends the explicit jobs (their keys join the varying keys).
    fn explicit(&mut self, c: &Ctx, jobs: &[toml::Table]) -> Result<(), InputError> {
        for (j, t) in jobs.iter().enumerate() {
            let mut o = Vec::new();
            flatten("", t, &mut o);
            for (k, _) in &o {
                if !self.varying.contains(k) {
                    self.varying.push(k.clone());
                }
            }
            if o.is_empty() {
                return Err(c.err(
                    &format!("jobs[{j}]"),
                    "an explicit job needs at least one key",
                ));
            }
            self.combos.push((o, Vec::new()));
        }
        Ok(())
    }
}
