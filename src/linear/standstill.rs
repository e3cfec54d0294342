//! The supported (standstill) frequencies of a linear system: its undamped modes at zero speed,
//! each with the plane of the rotor's motion.
//!
//! In: a [`LinearSystem`] (SI). Out: [`SupportedMode`]s (frequency [Hz] and kind), the vertical
//! and horizontal bending frequencies [Hz] (`supported_hz` of `modes` and `linear`) and damped
//! lateral whirl frequencies at a speed.
//!
//! Method: the real generalized symmetric eigenproblem K φ = ω² M φ where the supports'
//! stiffness is symmetric, degenerate pairs (isotropic supports) rotated into their horizontal
//! and vertical members by the kinetic energy of the x family; with cross-coupled support
//! stiffness the complex problem of [`damped_modes`] on the undamped system. Cost O(n³).

use nalgebra::DVector;

use super::modes::{damped_modes, Kind, Split};
use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::numerics::eigen;
use crate::rotor::reduction::{classify, ModeKind};

/// A frequency of the supported rotor with its character.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportedMode {
    /// Frequency [Hz].
    pub freq_hz: f64,
    /// Dominant family of the rotor's motion.
    pub kind: ModeKind,
}

impl LinearSystem {
    /// Undamped frequencies at standstill, ascending, with the character of the rotor's motion.
    /// Cross-coupled (non-symmetric) support stiffness is kept (then the frequencies come from
    /// the complex eigenproblem); a degenerate pair (isotropic supports) is split into its
    /// horizontal and vertical members instead of two arbitrary "mixed" combinations, and a
    /// lateral mode in neither plane goes to the one holding more of its kinetic energy.
    pub fn standstill_modes(&self) -> Result<Vec<SupportedMode>, LinearError> {
        let (k, _) = self.at(0.0);
        let skew = (&k - k.transpose()).amax();
        if skew > 1e-12 * k.amax() {
            let undamped = self.undamped();
            let set = damped_modes(&undamped, 0.0, Split::Planes)?;
            return Ok(set
                .modes
                .iter()
                .map(|m| SupportedMode {
                    freq_hz: m.freq_hz,
                    kind: plane_kind(
                        self.family_energy(&m.shape.map(|z| z.re), &m.shape.map(|z| z.im)),
                    ),
                })
                .collect());
        }
        let eig = eigen::generalized_symmetric(&k, &self.m)?;
        let mut vectors = eig.vectors.clone();
        let fx = self.family_matrix(0);
        for (a, b) in clusters(eig.values.as_slice(), 1e-7) {
            let v = vectors.columns(a, b - a).into_owned();
            let form = v.transpose() * &fx * &v;
            let rot = nalgebra::SymmetricEigen::new(0.5 * (&form + form.transpose())).eigenvectors;
            vectors.columns_mut(a, b - a).copy_from(&(v * rot));
        }
        Ok((0..eig.values.len())
            .map(|i| {
                let v = vectors.column(i).into_owned();
                let zero = DVector::zeros(v.len());
                SupportedMode {
                    freq_hz: eig.values[i].max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
                    kind: plane_kind(self.family_energy(&v, &zero)),
                }
            })
            .collect())
    }

    /// The non-zero [`standstill_modes`](Self::standstill_modes) frequencies [Hz] of vertical
    /// and of horizontal bending, ascending: the `supported_hz` of `modes` and `linear`.
    pub fn supported_hz(&self) -> Result<(Vec<f64>, Vec<f64>), LinearError> {
        let modes = self.standstill_modes()?;
        let pick = |k: ModeKind| -> Vec<f64> {
            modes
                .iter()
                .filter(|m| m.kind == k && m.freq_hz > 1e-6)
                .map(|m| m.freq_hz)
                .collect()
        };
        Ok((pick(ModeKind::BendingY), pick(ModeKind::BendingX)))
    }

    /// Damped whirl frequencies [Hz] of the lateral modes at spin speed `omega` [rad/s] in the
    /// stationary frame, ascending (supports at that speed, damping included); axial and
    /// torsional modes are left out.
    pub fn whirl_hz(&self, omega: f64) -> Result<Vec<f64>, LinearError> {
        let set = damped_modes(self, omega, Split::Whirl)?;
        Ok(set
            .modes
            .iter()
            .filter(|m| m.kind == Kind::Lateral)
            .map(|m| m.freq_hz)
            .collect())
    }
}

/// The kind of a supported mode from its kinetic energy per family: the reduction's 80 % rule,
/// except that a lateral mode it calls mixed (a circular mode of cross-coupled supports, say)
/// goes to the plane holding more of its energy instead of being lost to both.
fn plane_kind(e: [f64; 4]) -> ModeKind {
    match classify(e) {
        ModeKind::Mixed if e[0] + e[1] >= e[2].max(e[3]) => {
            if e[0] >= e[1] {
                ModeKind::BendingX
            } else {
                ModeKind::BendingY
            }
        }
        k => k,
    }
}

/// Index ranges [a, b) of runs of ascending values that agree within `rel` (relative to the
/// larger magnitude), of length ≥ 2.
pub fn clusters(values: &[f64], rel: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut a = 0;
    for i in 1..=values.len() {
        let same = i < values.len()
            && (values[i] - values[i - 1]).abs()
                <= rel * values[i].abs().max(values[i - 1].abs()).max(1e-300);
        if !same {
            if i - a >= 2 {
                out.push((a, i));
            }
            a = i;
        }
    }
    out
}
