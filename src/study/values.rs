//! TOML values and key=value overrides as text.
//!
//! In: the tables of a study (`[set]`, a `[[jobs]]` entry, `[reference]`, `[pruning]`) and TOML
//! values. Out: the tables flattened to (dotted key, value) pairs ([`flatten`]); a value as the
//! text a `--set` override takes ([`value_text`]: strings quoted); a value and a job's overrides
//! as text that is the same for values of the same meaning ([`normal_value`], [`normal_text`]:
//! `10` and `10.0` alike), so that two jobs of the same physics are found.

use std::collections::BTreeMap;

/// One override: a dotted scene key and its value.
pub(super) type Override = (String, toml::Value);

/// Appends the leaves of `t` as (dotted key, value), the keys prefixed with `prefix`.
pub(super) fn flatten(prefix: &str, t: &toml::Table, out: &mut Vec<(String, toml::Value)>) {
    for (k, v) in t {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(sub) => flatten(&key, sub, out),
            other => out.push((key, other.clone())),
        }
    }
}

/// A value as the text of a `KEY=VALUE` override (strings quoted, the rest as TOML writes it).
pub(crate) fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

/// A value as text that is the same for values of the same meaning: integers as the floats they
/// are read as (up to 2⁵³, where both are exact), −0 as 0, tables with sorted keys.
pub(super) fn normal_value(v: &toml::Value) -> String {
    const EXACT: i64 = 1 << 53;
    match v {
        toml::Value::Integer(i) if i.abs() <= EXACT => format!("{:?}", *i as f64 + 0.0),
        toml::Value::Float(f) => format!("{:?}", f + 0.0),
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(normal_value).collect();
            format!("[{}]", items.join(","))
        }
        toml::Value::Table(t) => {
            let items: BTreeMap<&String, String> =
                t.iter().map(|(k, v)| (k, normal_value(v))).collect();
            let items: Vec<String> = items.iter().map(|(k, v)| format!("{k:?}={v}")).collect();
            format!("{{{}}}", items.join(","))
        }
        other => value_text(other),
    }
}

/// A job's overrides as normalised text, by key ([`normal_value`]).
pub(super) fn normal_text(overrides: &[(String, toml::Value)]) -> String {
    let by_key: BTreeMap<&String, String> = overrides
        .iter()
        .map(|(k, v)| (k, normal_value(v)))
        .collect();
    let items: Vec<String> = by_key.iter().map(|(k, v)| format!("{k}={v}")).collect();
    items.join(";")
}
