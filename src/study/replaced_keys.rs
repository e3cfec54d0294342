//! The order in which a job applies its keys, checked: no key may replace one applied before
//! it, which would drop the earlier silently.
//!
//! In: the keys of `[set]`, `[budget]` (as `solver.cpu_budget_s`, `solver.max_steps`), every
//! axis (and every `[sample]` parameter), every explicit job, `[reference]` and `[pruning]`. Out: an error at the later key
//! naming the earlier one and where it was set (`speed.hz` on an axis after `speed.hz.x` in
//! `[set]`). A later key inside an earlier one refines it and is allowed.

use super::context::Ctx;
use super::file::StudyFile;
use super::values::flatten;
use crate::error::InputError;
use crate::scene::replaces;

/// No key a job applies may replace one applied before it (`speed.hz` on an axis after
/// `speed.hz.x` in `[set]`): the earlier would be dropped silently. A job applies `[set]` and
/// `[budget]`, then every axis or one explicit job; its reference and its pruning pilot apply
/// `[reference]` or `[pruning]` after that. A later key inside an earlier one refines it.
pub(super) fn replaced_keys(
    c: &Ctx,
    base: &[(String, toml::Value)],
    raw: &StudyFile,
    reference: &[(String, toml::Value)],
    pilot: &[(String, toml::Value)],
) -> Result<(), InputError> {
    let mut common: Vec<(String, String)> = Vec::new();
    common.extend(base.iter().map(|(k, _)| (k.clone(), format!("set.{k}"))));
    if raw.budget.cpu_s.is_some() {
        common.push(("solver.cpu_budget_s".into(), "budget.cpu_s".into()));
    }
    if raw.budget.steps.is_some() {
        common.push(("solver.max_steps".into(), "budget.steps".into()));
    }
    let mut jobs = Vec::new();
    let mut with_axes = common.clone();
    for (i, a) in raw.axes.iter().enumerate() {
        for k in a.key_list().unwrap_or_default() {
            with_axes.push((k, format!("axes[{i}]")));
        }
    }
    if let Some(sample) = &raw.sample {
        with_axes.extend(sample.key_places());
    }
    jobs.push(with_axes);
    for (j, t) in raw.jobs.iter().enumerate() {
        let mut o = Vec::new();
        flatten("", t, &mut o);
        let mut g = common.clone();
        g.extend(
            o.into_iter()
                .map(|(k, _)| (k.clone(), format!("jobs[{j}].{k}"))),
        );
        jobs.push(g);
    }
    let mut groups = Vec::new();
    for (table, after) in [("reference", reference), ("pruning", pilot)] {
        for g in &jobs {
            let mut g = g.clone();
            g.extend(
                after
                    .iter()
                    .map(|(k, _)| (k.clone(), format!("{table}.{k}"))),
            );
            groups.push(g);
        }
    }
    for g in &groups {
        for (n, (b, at_b)) in g.iter().enumerate() {
            if let Some((a, at_a)) = g[..n].iter().find(|(a, _)| replaces(b, a)) {
                return Err(c.err(
                    at_b,
                    format!(
                        "`{b}` would replace `{a}` (at {at_a}), which is inside it: `{a}` would \
                         be dropped"
                    ),
                ));
            }
        }
    }
    Ok(())
}
