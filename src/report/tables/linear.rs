//! The `linear` table: per linearised system (`/linear/<id>` of a study, `/linear/<scene>` of a
//! `rotorsweep linear -o` file), long form: the lateral modes at every stored speed (damped
//! frequency [Hz]; damping ratio, log decrement and whirl where stored, as `linear -o` does and
//! a study's Campbell data does not), the critical speeds [Hz] with their whirl and log
//! decrement, the stability threshold [Hz] and the Floquet-unstable ranges [Hz].
//!
//! In: `/linear/<name>/campbell/{speed_hz, whirl_hz, log_dec, damping_ratio, whirl}`,
//! `critical_speeds_hz`, `critical_log_dec`, `critical_whirl`, the attribute
//! `stability_threshold_hz` and `floquet/unstable_ranges_hz`. Out: the long form (one row per
//! quantity: `mode`, `critical_speed`, `stability_threshold`, `floquet_unstable`) and the
//! markdown grid of speeds × lowest modes (at most [`LINEAR_MD_SPEEDS`] evenly picked speeds and
//! [`LINEAR_MD_MODES`] modes per system), then a line each for the critical speeds, the
//! threshold and the Floquet ranges. A system without Campbell data gives nothing.

use std::fmt::Write as _;

use hdf5::types::VarLenUnicode;
use hdf5::{File, Group};

use crate::report::table::{Cell, Grid, Table};
use crate::store;
use crate::text::significant;

/// Most speeds the markdown form of the `linear` table shows per system (evenly picked, the
/// first and last included; CSV and JSON hold every stored speed).
const LINEAR_MD_SPEEDS: usize = 11;

/// Most modes per speed the markdown form of the `linear` table shows (the lowest).
const LINEAR_MD_MODES: usize = 6;

/// A float dataset of `g` as (values, columns: 1 for 1-D), if there.
fn read_matrix(g: &Group, name: &str) -> Option<(Vec<f64>, usize)> {
    let ds = g.dataset(name).ok()?;
    let cols = match ds.shape().as_slice() {
        [_] => 1,
        [_, c] => *c,
        _ => return None,
    };
    Some((ds.read_raw::<f64>().ok()?, cols))
}

/// The whirl of a `campbell/whirl` code (its `codes` attribute: 1 forward, −1 backward, 0 mixed).
fn whirl_name(code: f64) -> &'static str {
    if code > 0.5 {
        "forward"
    } else if code < -0.5 {
        "backward"
    } else {
        "mixed"
    }
}

/// A mode as the markdown grid shows it: `44.378 δ 0.0137 forward`, or the frequency alone.
fn md_mode(freq: f64, log_dec: f64, whirl: &str) -> String {
    let mut t = significant(freq, 5);
    if log_dec.is_finite() {
        let _ = write!(t, " δ {}", significant(log_dec, 3));
    }
    if !whirl.is_empty() {
        let _ = write!(t, " {whirl}");
    }
    t
}

/// Element `i` of a stored vector, if stored and there.
fn at(v: &Option<Vec<f64>>, i: usize) -> Option<f64> {
    v.as_ref().and_then(|v| v.get(i).copied())
}

/// One row of the long form of system `name`: the quantity, its speed [Hz] and end speed [Hz]
/// (of a range), the mode's rank, its [frequency [Hz], damping ratio, log decrement] and whirl.
fn row(
    name: &str,
    quantity: &str,
    speed: f64,
    end: f64,
    mode: Cell,
    fzd: [f64; 3],
    whirl: &str,
) -> Vec<Cell> {
    let [f, z, d] = fzd;
    vec![
        Cell::Text(name.to_string()),
        Cell::Text(quantity.to_string()),
        Cell::Number(speed),
        Cell::Number(end),
        mode,
        Cell::Number(f),
        Cell::Number(z),
        Cell::Number(d),
        Cell::Text(whirl.to_string()),
    ]
}

/// The `mode` rows of system `name` at every stored speed and the markdown lines of the picked
/// speeds (the lowest modes); `log_dec` as stored (read by the caller, which needs it too).
fn mode_rows(
    name: &str,
    g: &Group,
    speeds: &[f64],
    log_dec: &Option<Vec<f64>>,
    rows: &mut Vec<Vec<Cell>>,
    md: &mut Vec<Vec<String>>,
) {
    let (freq, nb) = read_matrix(g, "campbell/whirl_hz").unwrap_or_default();
    let stored = |name: &str| read_matrix(g, name).map(|m| m.0);
    let (zeta, whirl) = (stored("campbell/damping_ratio"), stored("campbell/whirl"));
    let nan = f64::NAN;
    let step = speeds
        .len()
        .saturating_sub(1)
        .div_ceil(LINEAR_MD_SPEEDS - 1)
        .max(1);
    for (s, speed) in speeds.iter().enumerate() {
        let mut line = vec![name.to_string(), format!("{speed:.2}")];
        for k in 0..nb {
            let i = s * nb + k;
            let w = at(&whirl, i).map_or("", whirl_name);
            let d = at(log_dec, i).unwrap_or(nan);
            rows.push(row(
                name,
                "mode",
                *speed,
                nan,
                Cell::Count(k as u64 + 1),
                [freq[i], at(&zeta, i).unwrap_or(nan), d],
                w,
            ));
            if k < LINEAR_MD_MODES {
                line.push(md_mode(freq[i], d, w));
            }
        }
        if s % step == 0 || s + 1 == speeds.len() {
            md.push(line);
        }
    }
}

/// The `critical_speed` rows of system `name` and their markdown line.
fn critical_rows(name: &str, g: &Group, rows: &mut Vec<Vec<Cell>>, md: &mut Vec<Vec<String>>) {
    let nan = f64::NAN;
    let crit = read_matrix(g, "critical_speeds_hz")
        .map(|m| m.0)
        .unwrap_or_default();
    let crit_dec = read_matrix(g, "critical_log_dec").map(|m| m.0);
    let crit_whirl: Vec<String> = g
        .dataset("critical_whirl")
        .and_then(|d| d.read_raw::<VarLenUnicode>())
        .map(|v| v.iter().map(|w| w.to_string()).collect())
        .unwrap_or_default();
    let mut line = vec![name.to_string(), "critical speeds [Hz]".to_string()];
    for (i, c) in crit.iter().enumerate() {
        let w = crit_whirl.get(i).map_or("", String::as_str);
        let d = at(&crit_dec, i).unwrap_or(nan);
        rows.push(row(
            name,
            "critical_speed",
            *c,
            nan,
            Cell::Text(String::new()),
            [*c, nan, d],
            w,
        ));
        line.push(md_mode(*c, d, w));
    }
    if crit.is_empty() {
        line.push("none in the range".into());
    }
    md.push(line);
}

/// The `stability_threshold` row of system `name` (empty: stable over the stored `speeds`) and
/// its markdown line.
fn threshold_rows(
    name: &str,
    g: &Group,
    speeds: &[f64],
    rows: &mut Vec<Vec<Cell>>,
    md: &mut Vec<Vec<String>>,
) {
    let nan = f64::NAN;
    let top = speeds.last().copied().unwrap_or(nan);
    let threshold = store::read_num(g, "stability_threshold_hz").ok();
    rows.push(row(
        name,
        "stability_threshold",
        threshold.unwrap_or(nan),
        nan,
        Cell::Text(String::new()),
        [nan; 3],
        "",
    ));
    md.push(vec![
        name.to_string(),
        "stability threshold [Hz]".into(),
        threshold.map_or_else(
            || match speeds {
                [one] => format!("none (stable at {one:.2} Hz)"),
                _ => format!("none (stable over {:.2}–{top:.2} Hz)", speeds[0]),
            },
            |t| significant(t, 6),
        ),
    ]);
}

/// The `floquet_unstable` rows of system `name` and their markdown line, when it has Floquet
/// results.
fn floquet_rows(name: &str, g: &Group, rows: &mut Vec<Vec<Cell>>, md: &mut Vec<Vec<String>>) {
    let Some((ranges, _)) = read_matrix(g, "floquet/unstable_ranges_hz") else {
        return;
    };
    let nan = f64::NAN;
    let pairs: Vec<[f64; 2]> = ranges.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
    for [a, b] in &pairs {
        rows.push(row(
            name,
            "floquet_unstable",
            *a,
            *b,
            Cell::Text(String::new()),
            [nan; 3],
            "",
        ));
    }
    let shown: Vec<String> = pairs
        .iter()
        .map(|[a, b]| format!("{}–{}", significant(*a, 6), significant(*b, 6)))
        .collect();
    md.push(vec![
        name.to_string(),
        "Floquet unstable [Hz]".into(),
        if shown.is_empty() {
            "none in the range".into()
        } else {
            shown.join(", ")
        },
    ]);
}

/// The rows and markdown lines of one `/linear/<name>` group (a system without Campbell data
/// gives none).
fn linear_system(
    name: &str,
    g: &Group,
    rows: &mut Vec<Vec<Cell>>,
    md: &mut Vec<Vec<String>>,
) -> hdf5::Result<()> {
    let Some((speeds, _)) = read_matrix(g, "campbell/speed_hz") else {
        return Ok(());
    };
    let log_dec = read_matrix(g, "campbell/log_dec").map(|m| m.0);
    mode_rows(name, g, &speeds, &log_dec, rows, md);
    critical_rows(name, g, rows, md);
    // The stability threshold is computed with the damped modes only (their log decrements).
    if log_dec.is_some() {
        threshold_rows(name, g, &speeds, rows, md);
    }
    floquet_rows(name, g, rows, md);
    Ok(())
}

/// The `linear` table of every `/linear/<name>` group with Campbell data.
pub(crate) fn linear_table(f: &File) -> hdf5::Result<Option<Table>> {
    let Ok(lg) = f.group("linear") else {
        return Ok(None);
    };
    let mut rows = Vec::new();
    let mut md = Vec::new();
    for name in lg.member_names()? {
        linear_system(&name, &lg.group(&name)?, &mut rows, &mut md)?;
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let width = md.iter().map(Vec::len).max().unwrap_or(2);
    let columns = ["system", "speed [Hz]"]
        .iter()
        .map(|c| c.to_string())
        .chain((1..width - 1).map(|k| format!("mode {k}")))
        .collect();
    Ok(Some(Table {
        name: "linear".into(),
        title: "Linear systems".into(),
        legend: format!(
            "Damped lateral modes per spin speed (quantity `mode`: damped frequency [Hz], \
             damping ratio, log decrement δ, whirl, where stored; rank from 1 upwards), critical \
             speeds [Hz] with their whirl and δ, the stability threshold [Hz] (empty: stable \
             over the range) and the Floquet-unstable speed ranges [Hz]; in markdown and HTML \
             at most {LINEAR_MD_SPEEDS} evenly spaced speeds and the lowest {LINEAR_MD_MODES} \
             modes per system (CSV and JSON: all)."
        ),
        columns: [
            "system",
            "quantity",
            "speed_hz",
            "speed_end_hz",
            "mode",
            "freq_hz",
            "damping_ratio",
            "log_dec",
            "whirl",
        ]
        .iter()
        .map(|c| c.to_string())
        .collect(),
        rows,
        markdown: Some(Grid {
            columns,
            rows: md,
            classes: Vec::new(),
        }),
    }))
}
