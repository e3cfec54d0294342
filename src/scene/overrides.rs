//! `--set key=value` overrides of a scene: parsing, applying them to the merged table in order,
//! and finding the key a schema error of the overridden table is about.
//!
//! In: the merged table of a scene and its bases ([`Source`]) and `key=value` strings (dotted
//! keys with `[i]` indices; the value as TOML, or a string if it is not). Out: the overridden
//! table and the keys set, or an [`InputError`] at `<command line --set>`. Method: each path is
//! walked in the TOML value, creating tables on the way; an override that replaces an earlier
//! one (`speed.hz` after `speed.hz.x`) or does not fit the file's structure is refused.

use std::path::Path;

use super::file::SceneFile;
use super::locate;
use super::source::Source;
use crate::error::InputError;

/// The file errors of `--set` overrides (and of a study's job overrides, before the study
/// relocates them) name.
pub const COMMAND_LINE: &str = "<command line --set>";

/// Parses `key=value` of `--set`: the value as a TOML value, or as a string if it is not one.
pub fn parse_override(s: &str) -> Result<(String, toml::Value), String> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}`: expected key=value"))?;
    let k = k.trim().to_string();
    let v = v.trim();
    let value = toml::from_str::<toml::Table>(&format!("v = {v}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(v.to_string()));
    Ok((k, value))
}

/// Whether setting dotted key `later` after `earlier` replaces it: `earlier` lies strictly inside
/// `later` (`speed.hz` after `speed.hz.x`), so the earlier value would be dropped.
pub fn replaces(later: &str, earlier: &str) -> bool {
    let (l, e) = (locate::parse_path(later), locate::parse_path(earlier));
    l.len() < e.len() && e[..l.len()] == l[..]
}

/// Sets a dotted key (with `[i]` indices) in a TOML value, creating tables on the way.
pub fn set_path(root: &mut toml::Value, key: &str, value: toml::Value) -> Result<(), String> {
    fn set_in(
        v: &mut toml::Value,
        steps: &[locate::Step],
        value: toml::Value,
        key: &str,
    ) -> Result<(), String> {
        use locate::Step;
        let Some((first, rest)) = steps.split_first() else {
            *v = value;
            return Ok(());
        };
        let child = match (first, v) {
            (Step::Key(k), toml::Value::Table(t)) => t
                .entry(k.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            (Step::Index(i), toml::Value::Array(a)) => {
                let len = a.len();
                a.get_mut(*i)
                    .ok_or_else(|| format!("`{key}`: index {i} out of range (length {len})"))?
            }
            (Step::Key(k), toml::Value::Array(a)) => {
                // `supports.0.x` for `supports[0].x`: say how arrays are indexed.
                let hint = match k.parse::<usize>() {
                    Ok(i) => format!(
                        "; arrays are indexed with brackets: write `…[{i}]…` (e.g. `supports[0].stand.mass_kg`)"
                    ),
                    Err(_) => format!(" (an array of {} entries: index it as `[i]`)", a.len()),
                };
                return Err(format!(
                    "`{key}`: the path does not match the file's structure{hint}"
                ));
            }
            _ => {
                return Err(format!(
                    "`{key}`: the path does not match the file's structure"
                ))
            }
        };
        set_in(child, rest, value, key)
    }
    let steps = locate::parse_path(key);
    if steps.is_empty() {
        return Err("empty key".into());
    }
    set_in(root, &steps, value, key)
}

/// The merged table of a scene (`source`) with `key=value` overrides applied in order, and the
/// keys they set. An override that replaces an earlier one, or whose path does not fit the
/// table, is an error at the command line.
pub fn with_overrides(
    source: &Source,
    overrides: &[String],
) -> Result<(toml::Value, Vec<String>), InputError> {
    apply(
        source,
        overrides
            .iter()
            .map(|o| parse_override(o).map_err(|r| InputError::new(Path::new(COMMAND_LINE), r))),
    )
}

/// [`with_overrides`] of overrides already read as (dotted key, value): a study's jobs.
pub fn with_override_values(
    source: &Source,
    overrides: &[(String, toml::Value)],
) -> Result<(toml::Value, Vec<String>), InputError> {
    apply(
        source,
        overrides.iter().map(|(k, v)| Ok((k.clone(), v.clone()))),
    )
}

/// The merged table with `overrides` applied in order (the first error, in order, stops it).
fn apply(
    source: &Source,
    overrides: impl Iterator<Item = Result<(String, toml::Value), InputError>>,
) -> Result<(toml::Value, Vec<String>), InputError> {
    let cli = Path::new(COMMAND_LINE);
    let mut table = toml::Value::Table(source.table.clone());
    let mut keys: Vec<String> = Vec::new();
    for o in overrides {
        let (k, v) = o?;
        if let Some(other) = keys.iter().find(|p| replaces(&k, p)) {
            return Err(InputError::new(
                cli,
                format!(
                    "`{k}` would replace `{other}`, given before it: `{other}` would be dropped"
                ),
            )
            .with_key(k));
        }
        set_path(&mut table, &k, v).map_err(|r| InputError::new(cli, r).with_key(k.clone()))?;
        keys.push(k);
    }
    Ok((table, keys))
}

/// The dotted key a deserialisation error of the overridden scene `table` is about.
pub(super) fn override_error_key(table: &toml::Value) -> Option<String> {
    let text = toml::to_string(table).ok()?;
    let e = toml::from_str::<SceneFile>(&text).err()?;
    locate::key_at(&text, e.span()?.start)
}
