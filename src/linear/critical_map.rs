//! Undamped critical-speed map: critical speeds against a support stiffness.
//!
//! In: a [`LinearSystem`] and support stiffnesses [N/m].
//! Out: per stiffness k the undamped critical speeds [Hz] (lateral, ascending) with every
//! support's spring between journal and support mass (or ground) replaced by an isotropic k
//! (no cross-coupling, no damping; support masses and their ground springs kept), and the
//! actual supports' direct stiffnesses (kx, ky) [N/m] to mark on the map.
//!
//! Method: a synchronous whirl q = Re(X e^{iΩt}) of the undamped system needs
//! (K − Ω² (M − i G_s)) X = 0; with X = a + ib this is the real symmetric pencil
//! diag(K, K) − Ω² [[M, G_s], [−G_s, M]] (each root twice, for X and iX), solved as the real
//! eigenproblem of its inverse-mass form. A body with stress stiffening has K + Ω² K_σ, so M
//! becomes M − K_σ in that pencil. A system of more than [`FULL_MAX`] coordinates, given
//! a range, is first projected on its undamped modes (with that support stiffness) below
//! [`BASIS_FACTOR`] × the range, and lists the critical speeds up to half that cut-off (as the
//! damped modes, [`super::basis`]). Frame: stationary.

use nalgebra::DMatrix;

use super::basis::{BASIS_FACTOR, FULL_MAX, MIN_RANGE_HZ};
use super::campbell::LISTED_OF_CUTOFF;
use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::numerics::eigen;
use crate::rotor::reduction::ModeKind;

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The map (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalMap {
    /// Support stiffness [N/m].
    pub stiffness: Vec<f64>,
    /// Critical speeds [Hz] per stiffness, ascending.
    pub critical_hz: Vec<Vec<f64>>,
    /// The actual supports' (kx, ky) [N/m].
    pub actual: Vec<(f64, f64)>,
}

/// Undamped critical speeds [Hz] of the lateral modes of `sys` with its supports as they are.
pub fn undamped_critical_hz(sys: &LinearSystem) -> Result<Vec<f64>, LinearError> {
    let (k, _) = sys.at(0.0);
    critical_of(sys, &k, None)
}

fn critical_of(
    sys: &LinearSystem,
    k: &DMatrix<f64>,
    cutoff_hz: Option<f64>,
) -> Result<Vec<f64>, LinearError> {
    // A large system on its undamped modes below the cut-off (module doc).
    let basis = match cutoff_hz {
        Some(f) => {
            let eig = eigen::generalized_symmetric(&(0.5 * (k + k.transpose())), &sys.m)?;
            let keep: Vec<usize> = (0..eig.values.len())
                .filter(|&i| eig.values[i] <= (TAU * f).powi(2))
                .collect();
            Some(DMatrix::from_fn(sys.n(), keep.len(), |r, j| {
                eig.vectors[(r, keep[j])]
            }))
        }
        None => None,
    };
    let project = |a: &DMatrix<f64>| match &basis {
        Some(v) => v.transpose() * a * v,
        None => a.clone(),
    };
    // Stress stiffening K + Ω² K_σ: at the critical speed ω = Ω it joins the inertia term.
    let inertia = match sys.stress_stiffness() {
        Some(ks) => &sys.m - ks,
        None => sys.m.clone(),
    };
    let (m, g, k) = (project(&inertia), project(&sys.gs), project(k));
    let n = m.nrows();
    let mut b = DMatrix::zeros(2 * n, 2 * n);
    b.view_mut((0, 0), (n, n)).copy_from(&m);
    b.view_mut((n, n), (n, n)).copy_from(&m);
    b.view_mut((0, n), (n, n)).copy_from(&g);
    b.view_mut((n, 0), (n, n)).copy_from(&(-&g));
    let mut kk = DMatrix::zeros(2 * n, 2 * n);
    kk.view_mut((0, 0), (n, n)).copy_from(&k);
    kk.view_mut((n, n), (n, n)).copy_from(&k);
    let a = b
        .lu()
        .solve(&kk)
        .ok_or_else(|| LinearError::Singular("critical-speed map: singular inertia".into()))?;
    let (values, vectors) = eigen::general(&a)?;
    let full = |x: nalgebra::DVector<f64>| match &basis {
        Some(v) => v * x,
        None => x,
    };
    let mut out = Vec::new();
    for (i, l) in values.iter().enumerate() {
        if l.re <= (TAU * 0.01).powi(2) || l.im.abs() > 1e-8 * l.re {
            continue;
        }
        let part = |off: usize, f: fn(&faer::c64) -> f64| {
            full(nalgebra::DVector::from_fn(n, |r, _| {
                f(&vectors[(r + off, i)])
            }))
        };
        let ea = sys.family_energy(&part(0, |z| z.re), &part(0, |z| z.im));
        let eb = sys.family_energy(&part(n, |z| z.re), &part(n, |z| z.im));
        let e = std::array::from_fn(|f| ea[f] + eb[f]);
        if matches!(
            crate::rotor::reduction::classify(e),
            ModeKind::Axial | ModeKind::Torsion
        ) {
            continue;
        }
        let hz = l.re.sqrt() / TAU;
        if cutoff_hz.is_none_or(|f| hz <= LISTED_OF_CUTOFF * f) {
            out.push(hz);
        }
    }
    out.sort_by(f64::total_cmp);
    // Each root appears twice (X and iX): keep one of each close pair.
    let mut dedup: Vec<f64> = Vec::new();
    let mut i = 0;
    while i < out.len() {
        dedup.push(out[i]);
        if i + 1 < out.len() && (out[i + 1] - out[i]).abs() <= 1e-6 * out[i] {
            i += 2;
        } else {
            i += 1;
        }
    }
    Ok(dedup)
}

/// The critical-speed map over `stiffness` [N/m] (module doc) up to `range_hz` (`None`: every
/// mode; a system of at most [`FULL_MAX`] coordinates is solved whole either way).
pub fn critical_map(
    sys: &LinearSystem,
    stiffness: &[f64],
    range_hz: Option<f64>,
) -> Result<CriticalMap, LinearError> {
    let cutoff_hz = range_hz
        .filter(|_| sys.n() > FULL_MAX)
        .map(|r| BASIS_FACTOR * r.max(MIN_RANGE_HZ));
    let critical_hz = stiffness
        .iter()
        .map(|&ks| critical_of(sys, &sys.stiffness_with_supports(ks), cutoff_hz))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(CriticalMap {
        stiffness: stiffness.to_vec(),
        critical_hz,
        actual: sys.support_direct_stiffness(),
    })
}
