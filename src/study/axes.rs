//! A study's sweep axes, each read into its keys and rows of values.
//!
//! In: the `[[axes]]` tables: `key` or several `keys` (moved together, zipped), and `values`
//! (for several keys, one list per value) or a `range` `{start, stop, step}` (one key; its
//! points rounded to 12 significant digits), and optional `labels`, one per value.
//! Out: per axis its keys and its rows (one value per key), each row distinct (`10` and `10.0`
//! are the same value); errors naming `axes[i]` and the field for a malformed axis, a range of
//! more than [`MAX_JOBS`] points, a value given twice, or labels that do not name the rows.

use std::collections::BTreeMap;

use super::context::Ctx;
use super::file::AxisFile;
use super::limit::MAX_JOBS;
use super::values::normal_value;
use crate::error::InputError;

/// An axis's keys and its rows (one value per key).
pub(super) type AxisRows = (Vec<String>, Vec<Vec<toml::Value>>);

/// Every axis's keys and rows, in axis order, each axis's rows distinct.
pub(super) fn rows(c: &Ctx, axes: &[AxisFile]) -> Result<Vec<AxisRows>, InputError> {
    let mut out = Vec::new();
    for (i, a) in axes.iter().enumerate() {
        let (keys, rows) = axis_values(c, i, a)?;
        let at = if a.range.is_some() { "range" } else { "values" };
        distinct_rows(c, &format!("axes[{i}].{at}"), &keys, &rows)?;
        out.push((keys, rows));
    }
    Ok(out)
}

/// Axis `i`'s keys and rows: its `values`, or the points of its `range`.
fn axis_values(c: &Ctx, i: usize, a: &AxisFile) -> Result<AxisRows, InputError> {
    let key = format!("axes[{i}]");
    let keys = a.key_list().ok_or_else(|| {
        c.err(
            &key,
            "an axis needs either `key` or a non-empty `keys` list",
        )
    })?;
    let rows: Vec<Vec<toml::Value>> = match (&a.values, &a.range) {
        (Some(vals), None) => {
            if vals.is_empty() {
                return Err(c.err(&format!("{key}.values"), "an axis needs at least one value"));
            }
            if keys.len() == 1 {
                vals.iter().map(|v| vec![v.clone()]).collect()
            } else {
                vals.iter()
                    .enumerate()
                    .map(|(j, v)| match v.as_array() {
                        Some(row) if row.len() == keys.len() => Ok(row.clone()),
                        _ => Err(c.err(
                            &format!("{key}.values"),
                            format!(
                                "value {j} must be a list of {} values, one per key",
                                keys.len()
                            ),
                        )),
                    })
                    .collect::<Result<_, _>>()?
            }
        }
        (None, Some(r)) => {
            if a.labels.is_some() {
                return Err(c.err(&format!("{key}.labels"), "labels go with `values`"));
            }
            if keys.len() != 1 {
                return Err(c.err(&format!("{key}.range"), "a range goes with a single `key`"));
            }
            if !(r.step > 0.0 && r.stop >= r.start && r.start.is_finite() && r.stop.is_finite()) {
                return Err(c.err(&format!("{key}.range"), "needs start <= stop and step > 0"));
            }
            // Counted as a float first: (stop − start) / step may be far beyond any integer (or
            // infinite for a subnormal step).
            let count = ((r.stop - r.start) / r.step + 1e-9).floor() + 1.0;
            if count > MAX_JOBS as f64 {
                return Err(c.err(
                    &format!("{key}.range"),
                    format!("{count:e} values, more than the {MAX_JOBS} jobs a study may have"),
                ));
            }
            let n = count as usize;
            (0..n)
                .map(|j| {
                    // Rounded to 12 significant digits so that 7.2 + 3·0.2 reads as 7.8.
                    let v = r.start + j as f64 * r.step;
                    let v: f64 = format!("{v:.12e}").parse().unwrap_or(v);
                    vec![toml::Value::Float(v)]
                })
                .collect()
        }
        _ => return Err(c.err(&key, "an axis needs either `values` or `range`")),
    };
    Ok((keys, rows))
}

/// An axis must not list one value twice, even written differently (`10` and `10.0`, `[1, 2]`
/// and `[1.0, 2.0]`): that is two jobs of the same physics.
fn distinct_rows(
    c: &Ctx,
    at: &str,
    keys: &[String],
    rows: &[Vec<toml::Value>],
) -> Result<(), InputError> {
    let mut seen = BTreeMap::new();
    for (j, row) in rows.iter().enumerate() {
        let text: Vec<String> = row.iter().map(normal_value).collect();
        if let Some(first) = seen.insert(text.join(","), j) {
            let shown = |r: &[toml::Value]| {
                r.iter()
                    .map(toml::Value::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(c.err(
                at,
                format!(
                    "axis `{}`: values {first} ({}) and {j} ({}) are the same, so two jobs \
                     would have the same physics",
                    keys.join(", "),
                    shown(&rows[first]),
                    shown(row)
                ),
            ));
        }
    }
    Ok(())
}

/// Axis `i`'s labels: one per row, none empty, none twice.
pub(super) fn check_labels(
    c: &Ctx,
    i: usize,
    labels: &[String],
    rows: usize,
) -> Result<(), InputError> {
    let key = format!("axes[{i}].labels");
    if labels.len() != rows {
        return Err(c.err(&key, format!("{} labels for {} values", labels.len(), rows)));
    }
    let mut seen = std::collections::BTreeSet::new();
    if let Some(bad) = labels
        .iter()
        .find(|x| x.trim().is_empty() || !seen.insert(*x))
    {
        return Err(c.err(
            &key,
            format!("label `{bad}` is empty or given twice (labels name the rows)"),
        ));
    }
    Ok(())
}
