//! The pieces shared by the calibration file's readers (`file`, `record`): a target [`Row`]
//! (an output of one job, its measured value and standard deviation in the output's own unit,
//! its weight, and for a measured record's row its [`OrderPoint`]: sensor, direction, order,
//! speed [Hz] and part) and [`Ctx`], the file being read (path and text), which turns a key
//! into an error naming the file, the key and its line (`scene::locate::line_of`).

use std::path::Path;

use crate::error::InputError;
use crate::scene::locate;

/// One target row: an output of one job of the study, measured with a standard deviation.
#[derive(Debug, Clone)]
pub struct Row {
    /// The row's key in the file (`resonances[0].amplitude_um`).
    pub at: String,
    /// Its line.
    pub line: Option<usize>,
    /// Output name (the statistics table's, `peak_amplitude_um:centre/vertical:2x`).
    pub output: String,
    /// Index of the study's job.
    pub job: usize,
    /// Measured value.
    pub value: f64,
    /// Its standard deviation.
    pub std: f64,
    /// Weight.
    pub weight: f64,
    /// For a row of a measured record (`[[records]]`): its order amplitude's place and part;
    /// the model's value is read from the job's order rows, not from `output`.
    pub point: Option<OrderPoint>,
}

/// Where a record row lies: the order amplitude of a sensor's direction at a speed, one part.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderPoint {
    /// Sensor.
    pub sensor: String,
    /// `vertical` or `horizontal`.
    pub direction: String,
    /// Order.
    pub order: f64,
    /// The measured block's mean speed [Hz].
    pub speed_hz: f64,
    /// The imaginary part (else the real part).
    pub imaginary: bool,
}

/// The file being checked: its path and text, for errors naming the file, key and line.
pub(super) struct Ctx<'a> {
    pub(super) path: &'a Path,
    pub(super) text: &'a str,
}

impl Ctx<'_> {
    pub(super) fn line(&self, key: &str) -> Option<usize> {
        locate::line_of(self.text, key)
    }

    pub(super) fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        let e = InputError::new(self.path, reason).with_key(key);
        match self.line(key) {
            Some(l) => e.at_line(l),
            None => e,
        }
    }
}
