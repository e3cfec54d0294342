//! A support of the roll: the journal's lateral modal rows, its optional support mass (a stand,
//! or the mass of a linear support), and its force law (roller contacts or linear
//! spring–dampers).
//!
//! In: a [`SupportModel`] of the scene and the journal's lateral rows of Φ (2 × nm); at each
//! evaluation the modal coordinates and velocities, the support mass's coordinates [m, m/s]
//! (inertial), the roll angle θ [rad] and speed Ω [rad/s]. Out: the journal's displacement w
//! and velocity ẇ relative to its support [m, m/s] (inertial), R(θ); the force on the journal
//! [N] with its stiffness and damping ([`Local`]); the 2 × n map from q to w; for outputs a
//! [`SupportState`]. Method: the journal centre in I is R(θ) Φ_j p, its velocity
//! R(θ) Φ_j ṗ + Ω ẑ × (R(θ) Φ_j p); a linear support's K and C are taken at the speed Ω.
//! On the integrators' hot path: what the force and Newton files call is `#[inline]`, so that
//! it can be inlined there as when they shared one file.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::contact::{Contacts, Local};
use crate::scene::{LinearSupport, SupportModel};

/// A support's force law.
#[derive(Debug, Clone)]
pub(super) enum Law {
    Contact(Contacts),
    Linear(LinearSupport),
}

#[derive(Debug, Clone)]
pub(super) struct SupportSys {
    /// Lateral rows of Φ at the journal (2 × nm).
    pub(super) rows: DMatrix<f64>,
    /// Index of the support mass's x coordinate in q, if any.
    pub(super) stand: Option<usize>,
    pub(super) law: Law,
}

/// The support forces at one state, for outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportState {
    /// Journal centre displacement in I [m].
    pub journal: Vector2<f64>,
    /// Support mass displacement in I [m] (zero without one).
    pub stand: Vector2<f64>,
    /// Contact force per roller [N] (empty for linear supports).
    pub contact: Vec<f64>,
}

impl SupportSys {
    /// The support of a scene on the journal rows `rows`; `add_mass(mass, K, C)` adds its support
    /// mass with its spring–damper to ground and returns the index of its x coordinate in q.
    pub(super) fn new(
        model: &SupportModel,
        rows: DMatrix<f64>,
        mut add_mass: impl FnMut(f64, Matrix2<f64>, Matrix2<f64>) -> usize,
    ) -> Self {
        match model {
            SupportModel::Rollers(rs) => {
                let st = rs.stand;
                let idx = add_mass(st.mass, st.spring.k_matrix(), st.spring.c_matrix());
                Self {
                    rows,
                    stand: Some(idx),
                    law: Law::Contact(Contacts::new(rs)),
                }
            }
            SupportModel::Linear(l) => {
                let stand = l
                    .mass
                    .map(|(mass, g)| add_mass(mass, g.k_matrix(), g.c_matrix()));
                Self {
                    rows,
                    stand,
                    law: Law::Linear(l.clone()),
                }
            }
        }
    }

    /// The force law at roll angle θ, given as (θ, sin θ, cos θ); each roller's force [N] pushed
    /// to `out` if given (contacts only).
    #[inline]
    pub(super) fn local(
        &self,
        angle: (f64, f64, f64),
        omega: f64,
        w: Vector2<f64>,
        wd: Vector2<f64>,
        out: Option<&mut Vec<f64>>,
    ) -> Local {
        match &self.law {
            Law::Linear(l) => {
                let sp = l.spring_at(omega);
                let (k, c) = (sp.k_matrix(), sp.c_matrix());
                Local {
                    f: -(k * w + c * wd),
                    kc: k,
                    cc: c,
                }
            }
            Law::Contact(contacts) => contacts.local(angle, omega, w, wd, out),
        }
    }

    /// Journal displacement and velocity relative to the support (inertial), and R(θ)Φ_j, for
    /// `nm` modal coordinates.
    #[inline]
    pub(super) fn relative(
        &self,
        nm: usize,
        sc: (f64, f64),
        omega: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Matrix2<f64>) {
        let r = rot(sc);
        let u = rows_times(&self.rows, &q.as_slice()[..nm]);
        let ub = rows_times(&self.rows, &v.as_slice()[..nm]);
        let wj = r * u;
        let mut wjd = r * ub + omega * Vector2::new(-wj.y, wj.x);
        let mut w = wj;
        if let Some(i) = self.stand {
            w -= Vector2::new(q[i], q[i + 1]);
            wjd -= Vector2::new(v[i], v[i + 1]);
        }
        (w, wjd, r)
    }

    /// The 2 × n map from q (n coordinates, nm modal) to the relative journal displacement
    /// w = (rows) p − s, with `rows` the journal's lateral modal rows (already rotated to the
    /// frame of w).
    pub(super) fn connection(&self, n: usize, nm: usize, rows: &DMatrix<f64>) -> DMatrix<f64> {
        let mut tq = DMatrix::zeros(2, n);
        tq.view_mut((0, 0), (2, nm)).copy_from(rows);
        if let Some(i) = self.stand {
            tq[(0, i)] = -1.0;
            tq[(1, i + 1)] = -1.0;
        }
        tq
    }
}

/// (rows) p for a 2 × nm matrix of lateral modal rows (column-major: row 0 and 1 of column j at
/// 2j and 2j + 1) and the nm modal coordinates p, without a temporary.
pub(super) fn rows_times(rows: &DMatrix<f64>, p: &[f64]) -> Vector2<f64> {
    let (mut x, mut y) = (0.0, 0.0);
    for (rj, pj) in rows.as_slice().chunks_exact(2).zip(p) {
        x += rj[0] * pj;
        y += rj[1] * pj;
    }
    Vector2::new(x, y)
}

/// R(θ) from (sin θ, cos θ).
pub(super) fn rot((s, c): (f64, f64)) -> Matrix2<f64> {
    Matrix2::new(c, -s, s, c)
}
