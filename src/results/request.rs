//! What the post-analysis of a results file is asked to compute: a study's `[analysis]` table
//! ([`AnalysisSpec`]) and its labelled axes, as the results stage reads them back from the study
//! text stored in the file ([`analysis_of_text`]).
//!
//! In: the `[analysis]` table (orders of the spin frequency, max frequency [Hz], the baseline
//! label, the order-tracking block [revolutions]) and the `[[axes]]` of a study's TOML text.
//! Out: [`StudyAnalysis`]. The study stage parses the same table into the same type when it
//! loads a study (a stage owns its parameters).

use serde::Deserialize;

use crate::text::number_text;

/// The study's `[analysis]` table: what the post-processing of the results computes.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// Orders of the spin frequency whose lines are measured in every job (1, 2, 3, 4 by
    /// default; non-integer orders measure other lines, e.g. 0.92 for rollers turning at
    /// 115/125 of the roll's speed).
    #[serde(default = "default_orders")]
    pub orders: Vec<f64>,
    /// Highest frequency [Hz] kept in stored spectra and maps (default: 1.25 × the highest order
    /// × the job's speed, [`ORDER_MARGIN`]).
    pub max_freq_hz: Option<f64>,
    /// The label (on a labelled axis) of the baseline jobs: every other job on that axis gets
    /// its 1× trial-mass response against the baseline job with the same other keys.
    pub baseline: Option<String>,
    /// Order tracking of jobs whose speed changes while recording (`signal::orders`): the
    /// block length [revolutions] (default 8; blocks overlap by half).
    pub order_revolutions: Option<f64>,
}

/// The default spectrum range: this share above the highest analysed order's line, so that the
/// line and its window skirt show (1.25 × 4 × the speed for the default orders 1–4).
pub const ORDER_MARGIN: f64 = 1.25;

/// The order-tracking block length [revolutions] when a study names none.
pub const DEFAULT_ORDER_REVOLUTIONS: f64 = 8.0;

/// Orders 1, 2, 3 and 4: the lines measured when a study names none.
pub fn default_orders() -> Vec<f64> {
    vec![1.0, 2.0, 3.0, 4.0]
}

/// The orders an analysis may ask for: from 1e-3 (a line of one period in a thousand
/// revolutions, longer than any record's blocks) to 1e4 (beyond any record's Nyquist frequency
/// at a roll's speeds). Outside, the fit's phase 2π·order·revolutions is no longer a number
/// (1e308 overflows to NaN) or all its columns are one (1e-320), and the least-squares solve
/// has nothing to fit.
pub const ORDER_RANGE: (f64, f64) = (1e-3, 1e4);

/// Checks a list of orders: one or more, each within [`ORDER_RANGE`], none twice; the reason
/// names the offending order.
pub fn check_orders(orders: &[f64]) -> Result<(), String> {
    let (lo, hi) = ORDER_RANGE;
    if orders.is_empty() {
        return Err("needs one or more orders".into());
    }
    if let Some(o) = orders.iter().find(|o| !(lo..=hi).contains(*o)) {
        return Err(format!(
            "order {} is outside [{lo}, {hi}] (orders of the spin frequency: 1 is the 1×)",
            number_text(*o)
        ));
    }
    if let Some(i) = (1..orders.len()).find(|&i| orders[..i].contains(&orders[i])) {
        return Err(format!("order {} is given twice", number_text(orders[i])));
    }
    Ok(())
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        Self {
            orders: default_orders(),
            max_freq_hz: None,
            baseline: None,
            order_revolutions: None,
        }
    }
}

/// An axis with labels: its keys (the first one names the label) and one label per value.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelledAxis {
    /// The axis's keys.
    pub keys: Vec<String>,
    /// The labels, one per value.
    pub labels: Vec<String>,
}

/// What the post-processing and the report need of a study's text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyAnalysis {
    /// The `[analysis]` table.
    pub spec: AnalysisSpec,
    /// The axes with labels.
    pub labelled: Vec<LabelledAxis>,
    /// The keys of every axis (several for a zipped axis), in axis order.
    pub axis_keys: Vec<Vec<String>>,
}

/// An axis's keys: `key`, or a non-empty `keys` list; `None` for neither or both.
pub fn axis_keys(key: &Option<String>, keys: &Option<Vec<String>>) -> Option<Vec<String>> {
    match (key, keys) {
        (Some(k), None) => Some(vec![k.clone()]),
        (None, Some(ks)) if !ks.is_empty() => Some(ks.clone()),
        _ => None,
    }
}

/// The parts of a study file the analysis reads (the study stage validates the rest).
#[derive(Debug, Deserialize)]
struct StudyView {
    #[serde(default)]
    analysis: AnalysisSpec,
    #[serde(default)]
    axes: Vec<AxisView>,
}

#[derive(Debug, Deserialize)]
struct AxisView {
    key: Option<String>,
    keys: Option<Vec<String>>,
    labels: Option<Vec<String>>,
}

/// The `[analysis]` table and the axes of a study's text; `None` when the text is not a study
/// file.
pub fn analysis_of_text(text: &str) -> Option<StudyAnalysis> {
    let raw: StudyView = toml::from_str(text).ok()?;
    let mut out = StudyAnalysis {
        spec: raw.analysis,
        ..StudyAnalysis::default()
    };
    for a in &raw.axes {
        let Some(keys) = axis_keys(&a.key, &a.keys) else {
            continue;
        };
        if let Some(labels) = &a.labels {
            out.labelled.push(LabelledAxis {
                keys: keys.clone(),
                labels: labels.clone(),
            });
        }
        out.axis_keys.push(keys);
    }
    Some(out)
}
