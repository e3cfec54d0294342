//! A study's per-job `[budget]`: the CPU time and step limits every job (and every reference
//! run, unless `[reference]` sets its own) runs under.
//!
//! In: `[budget]` `cpu_s` [s of CPU time] and `steps` [integrator steps, accepted and
//! rejected]. Out: the scene overrides `solver.cpu_budget_s` and `solver.max_steps`, applied
//! after `[set]` (a job past them ends with status `budget`). Error: a CPU budget that is not a
//! positive number.

use super::context::Ctx;
use super::file::BudgetFile;
use crate::error::InputError;

/// The budget as scene overrides, CPU time first.
pub(super) fn overrides(c: &Ctx, b: &BudgetFile) -> Result<Vec<(String, toml::Value)>, InputError> {
    let mut budget = Vec::new();
    if let Some(s) = b.cpu_s {
        if !(s > 0.0 && s.is_finite()) {
            return Err(c.err("budget.cpu_s", "must be a positive number"));
        }
        budget.push(("solver.cpu_budget_s".to_string(), toml::Value::Float(s)));
    }
    if let Some(n) = b.steps {
        budget.push((
            "solver.max_steps".to_string(),
            toml::Value::Integer(n as i64),
        ));
    }
    Ok(budget)
}
