//! A job's scene table without copying the scene: the base scene's entries, with only the
//! top-level entries the job's overrides touch copied and overridden, and the canonical text of
//! every entry, which the ids ([`super::ids`]) hash.
//!
//! In: the base scene's merged table ([`BaseTable`], its entries' texts serialised once per
//! study) and a job's overrides (dotted keys, applied in order). Out: a [`JobTable`] that reads
//! like the overridden table (`get`), and the canonical text of any choice of its top-level
//! entries ([`JobTable::canonical_parts`]): the same bytes as `toml::to_string` of that
//! subtable. Method: `toml::to_string` of a table writes its plain (non-table) entries first,
//! each on its own line, in key order, then each table or array of tables in key order, one
//! blank line between them; so the whole text is put together from the text of each entry on
//! its own (tested on shaped tables below, and by every shipped study's ids staying the same).
//! Cost: per job, a copy of the touched entries and their serialisation only (for a sweep of
//! the speed, the `speed` table), instead of three copies and four serialisations of the whole
//! scene.

use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex};

use crate::error::InputError;
use crate::scene::locate::{parse_path, Step};
use crate::scene::set_path;

/// The text `toml::to_string` gives for the one-entry table `{key: value}`; `None` where it
/// cannot be serialised.
fn entry_text(key: &str, value: &toml::Value) -> Option<String> {
    let one: BTreeMap<&str, &toml::Value> = BTreeMap::from([(key, value)]);
    toml::to_string(&one).ok()
}

/// The base scene's table and the text of each of its entries.
pub(super) struct BaseTable<'a> {
    table: &'a toml::Table,
    text: BTreeMap<&'a str, Option<String>>,
    /// The base's own canonical parts and hash states by selection and starting state
    /// ([`JobTable::hash_parts`]).
    prefixes: Mutex<HashMap<(&'static str, u64), Arc<Prefix>>>,
}

/// The canonical parts of the unchanged base for one selection (each piece by address and
/// length) and the hash state after each of them (`states[i]`: after the first i pieces).
struct Prefix {
    pieces: Vec<(usize, usize)>,
    states: Vec<u64>,
}

impl<'a> BaseTable<'a> {
    /// The entries of `table`, each serialised once.
    pub(super) fn new(table: &'a toml::Table) -> Self {
        let text = table
            .iter()
            .map(|(k, v)| (k.as_str(), entry_text(k, v)))
            .collect();
        BaseTable {
            table,
            text,
            prefixes: Mutex::default(),
        }
    }
}

/// A job's scene table: the base with the top-level entries its overrides touch replaced.
pub(super) struct JobTable<'a> {
    base: &'a BaseTable<'a>,
    /// The touched entries, overridden (a table holding only them).
    own: toml::Value,
    /// Their texts.
    own_text: BTreeMap<String, Option<String>>,
}

impl<'a> JobTable<'a> {
    /// The base with `overrides` applied in order; `err` makes the error of an override that
    /// does not fit the table (its key, the reason).
    pub(super) fn new(
        base: &'a BaseTable<'a>,
        overrides: &[(String, toml::Value)],
        err: impl Fn(&str, String) -> InputError,
    ) -> Result<Self, InputError> {
        let mut own = toml::Table::new();
        for (k, _) in overrides {
            if let Some(Step::Key(top)) = parse_path(k).into_iter().next() {
                if let (false, Some(v)) = (own.contains_key(&top), base.table.get(&top)) {
                    own.insert(top, v.clone());
                }
            }
        }
        let mut own = toml::Value::Table(own);
        for (k, v) in overrides {
            set_path(&mut own, k, v.clone()).map_err(|r| err(k, r))?;
        }
        let own_text = own
            .as_table()
            .into_iter()
            .flatten()
            .map(|(k, v)| (k.clone(), entry_text(k, v)))
            .collect();
        Ok(JobTable {
            base,
            own,
            own_text,
        })
    }

    /// Top-level entry `key` of the overridden table.
    pub(super) fn get(&self, key: &str) -> Option<&toml::Value> {
        self.own.get(key).or_else(|| self.base.table.get(key))
    }

    /// The state a hash `step` (a function of the state and a piece of text) leaves after
    /// `start` and the canonical parts of the selection `keep`/`drop`, which `selection` names
    /// (one selection per name in a study). The same as stepping over every piece; the leading
    /// pieces this job shares with the unchanged base (the same strings, by address: the
    /// entries before the first one its overrides touch) are stepped over once per study and
    /// starting state, not once per job.
    pub(super) fn hash_parts(
        &self,
        selection: &'static str,
        keep: &[&str],
        drop: &[&str],
        start: u64,
        step: impl Fn(u64, &str) -> u64,
    ) -> u64 {
        let pieces = self.canonical_parts(keep, drop);
        let prefix = {
            let mut known = (self.base.prefixes.lock()).unwrap_or_else(|e| e.into_inner());
            let entry = known.entry((selection, start)).or_insert_with(|| {
                let unchanged = JobTable {
                    base: self.base,
                    own: toml::Value::Table(toml::Table::new()),
                    own_text: BTreeMap::new(),
                };
                let base = unchanged.canonical_parts(keep, drop);
                let mut states = vec![start];
                for p in &base {
                    states.push(step(states[states.len() - 1], p));
                }
                let pieces = base
                    .iter()
                    .map(|p| (p.as_ptr() as usize, p.len()))
                    .collect();
                Arc::new(Prefix { pieces, states })
            });
            entry.clone()
        };
        let shared = (pieces.iter().zip(&prefix.pieces))
            .take_while(|(p, &(at, len))| p.as_ptr() as usize == at && p.len() == len)
            .count();
        (pieces[shared..].iter()).fold(prefix.states[shared], |h, p| step(h, p))
    }

    /// The canonical text of the subtable of the entries that `keep` (all when empty) names and
    /// `drop` does not, as consecutive parts (their concatenation is `toml::to_string` of that
    /// subtable); empty where an entry cannot be serialised.
    pub(super) fn canonical_parts(&self, keep: &[&str], drop: &[&str]) -> Vec<&str> {
        let chosen = |k: &str| (keep.is_empty() || keep.contains(&k)) && !drop.contains(&k);
        let mut keys: Vec<&str> = self.base.text.keys().copied().collect();
        keys.extend(self.own_text.keys().map(String::as_str));
        keys.sort_unstable();
        keys.dedup();
        let mut plain = Vec::new();
        let mut tables = Vec::new();
        for k in keys.into_iter().filter(|k| chosen(k)) {
            let text = match self.own_text.get(k) {
                Some(t) => t,
                None => &self.base.text[k],
            };
            let Some(text) = text.as_deref() else {
                return Vec::new();
            };
            if text.starts_with('[') {
                tables.push(text);
            } else {
                plain.push(text);
            }
        }
        for (i, t) in tables.into_iter().enumerate() {
            if i > 0 || !plain.is_empty() {
                plain.push("\n");
            }
            plain.push(t);
        }
        plain
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `toml::to_string` of the subtable chosen by `keep`/`drop` of `table` with `overrides`.
    fn whole(
        table: &toml::Table,
        overrides: &[(String, toml::Value)],
        keep: &[&str],
        drop: &[&str],
    ) -> String {
        let mut merged = toml::Value::Table(table.clone());
        for (k, v) in overrides {
            set_path(&mut merged, k, v.clone()).unwrap();
        }
        let mut t = merged.as_table().unwrap().clone();
        t.retain(|k, _| (keep.is_empty() || keep.contains(&k)) && !drop.contains(&k));
        toml::to_string(&t).unwrap()
    }

    /// The parts put together equal the serialisation of the whole table (the property the ids
    /// rest on), for tables of every shape a scene has: plain entries sorting before and after
    /// tables, an empty table, a table holding only tables, arrays of tables, inline arrays, and
    /// overrides that change a value, add a table and add a plain entry.
    #[test]
    fn the_parts_are_the_whole_serialisation() {
        let table: toml::Table = toml::from_str(
            r#"
            a_plain = 1.5
            name = "x"
            z_plain = [1, 2.5, "s"]
            [empty]
            [roll.shell]
            length_mm = 5000.0
            [[roll.sensors]]
            name = "c"
            z_mm = 2.0
            [[supports]]
            kx = 1e7
            [supports.stand]
            mass_kg = 5.0
            [[supports]]
            kx = 2e7
            [speed]
            hz = 10.0
            "#,
        )
        .unwrap();
        let base = BaseTable::new(&table);
        let v = |s: &str| -> toml::Value {
            toml::from_str::<toml::Table>(&format!("v = {s}")).unwrap()["v"].clone()
        };
        let cases: Vec<Vec<(String, toml::Value)>> = vec![
            vec![],
            vec![("speed.hz".into(), v("12.5"))],
            vec![
                ("supports[1].stand.mass_kg".into(), v("7.0")),
                ("new.table.x".into(), v("1")),
            ],
            vec![
                ("b_plain".into(), v("true")),
                ("roll.shell.length_mm".into(), v("1e308")),
            ],
            vec![("zz".into(), v("nan")), ("empty.k".into(), v("[]"))],
        ];
        for overrides in &cases {
            let job = JobTable::new(&base, overrides, |k, r| {
                InputError::new(std::path::Path::new("t"), format!("{k}: {r}"))
            })
            .unwrap();
            for (selection, keep, drop) in [
                ("all", &[][..], &[][..]),
                ("roll and supports", &["roll", "supports"][..], &[][..]),
                ("no speed", &[][..], &["speed"][..]),
                ("name and speed", &["name", "speed"][..], &[][..]),
            ] {
                let parts = job.canonical_parts(keep, drop);
                assert_eq!(
                    parts.concat(),
                    whole(&table, overrides, keep, drop),
                    "overrides {overrides:?}, keep {keep:?}, drop {drop:?}"
                );
                // The hash over the parts with the base's shared pieces stepped once per
                // study equals stepping over every piece (FNV-1a's step, as the ids use it).
                let step = |h: u64, piece: &str| {
                    (piece.bytes())
                        .fold(h, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
                };
                for start in [0xcbf2_9ce4_8422_2325, 7] {
                    assert_eq!(
                        job.hash_parts(selection, keep, drop, start, step),
                        parts.iter().fold(start, |h, p| step(h, p)),
                        "overrides {overrides:?}, selection {selection}"
                    );
                }
            }
        }
    }
}
