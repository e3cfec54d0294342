//! The spinning reduced roll on its supports as a second-order system M q̈ = F(t, q, q̇).
//!
//! In: a [`Scene`] and its [`Model`] (reduced basis).
//! Out: a [`RollSystem`] with coordinates q = (modal coordinates p, then (x, y) [m] of each stand
//! or support mass in the inertial frame), the force F [N], and the Newton matrix
//! a M − b ∂F/∂q − c ∂F/∂q̇ the implicit integrators need (analytic; only the contacts change).
//!
//! Rotor (body frame, physics.md §4): M p̈ + (D + 2Ω G_c) ṗ + (K − Ω²E + Ω̇C) p = Ω² f_c − Ω̇ f_t +
//! g_B(θ) + Φ_jᵀ R(θ)ᵀ F_j + f_axial, with g_B = Rᵀ(0, −g, 0) and F_j the supports' forces on the
//! journals in the inertial frame. The journal centre in I is R(θ) u_j, u_j = Φ_j p.
//! Contact per roller (physics.md §5, thesis §3): δ = H_j + H_r + L − |w − L e|, with w the
//! journal's displacement relative to its stand, e the unit vector toward the roller and
//! L = R_j + R_r; F = k δ^e + c(δ) δ̇ along the line of centres, c rising as the cubic step from 0
//! at δ = 0 to c_max at δ = d; F = 0 for δ ≤ 0 (lift-off), and F is never adhesive (clamped ≥ 0).
//! Journal roundness seen by roller i at angle a_i: H_j(θ − a_i); roller roundness either of the
//! roll angle (the source's choice) or of the roller's own angle −θ R_j/R_r.
//! A scene pays for what it uses: a constant speed pre-combines the linear matrices.
//!
//! Per-evaluation cost (the integrators call the force once per corrector iteration): the
//! linear part is one SIMD product [K − Ω²E | D + 2ΩG] [q; q̇] (`crate::numerics::dense::Padded`); the
//! modal mass, the identity to round-off for mass-normalised modes, is made exactly diagonal so
//! that M q̈ is elementwise; one `sin_cos` of θ serves R(θ) and every roundness profile (angle
//! addition for θ − a_i, recurrences for the harmonics) unless a roller's roundness turns with
//! its own angle; the Hertz power δ^1.5 is δ √δ.

use crate::numerics::dense::Padded;
use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use crate::dynamics::model::Model;
use crate::scene::{
    ContactLaw, Harmonic, LinearSupport, RollerPhase, Scene, SpeedProfile, SupportModel,
};

/// One roller in the frame of its support.
#[derive(Debug, Clone)]
struct RollerSys {
    /// Unit vector from the journal centre toward the roller centre (inertial).
    e: Vector2<f64>,
    /// Sine and cosine of the roller angle a_i from straight below.
    sin_cos: (f64, f64),
    /// R_j + R_r [m].
    l: f64,
    /// Roller roundness.
    roundness: Profile,
    /// Roller angle per roll angle (−R_j/R_r), or 1 for the source's roll-angle drive.
    ratio: f64,
}

/// A roller's penetration and what its rate and direction need (`RollerSys::penetration`).
struct Penetration {
    /// δ = H_j + H_r + L − |d| [m].
    delta: f64,
    /// d(H_j + H_r)/dθ [m/rad].
    dh: f64,
    /// d = w − L e, from the roller centre to the journal centre [m], and |d|.
    d: Vector2<f64>,
    dist: f64,
}

impl RollerSys {
    /// The penetration of the journal `journal` at relative displacement w into this roller at
    /// roll angle θ, given as (θ, sin θ, cos θ).
    fn penetration(
        &self,
        journal: &Profile,
        (theta, st, ct): (f64, f64, f64),
        w: Vector2<f64>,
    ) -> Penetration {
        // sin and cos of θ − a by angle addition; of the roller's angle ratio·θ by its own
        // sin_cos unless the roller turns with the roll angle (ratio 1).
        let (sa, ca) = self.sin_cos;
        let (hj, dhj) = journal.eval((st * ca - ct * sa, ct * ca + st * sa));
        let (hr, dhr) = if self.roundness.terms.is_empty() {
            (0.0, 0.0)
        } else if self.ratio == 1.0 {
            self.roundness.eval((st, ct))
        } else {
            self.roundness.eval((self.ratio * theta).sin_cos())
        };
        let d = w - self.l * self.e;
        let dist = d.norm();
        // L − |d| without cancellation: (2L w·e − |w|²)/(L + |d|).
        let gap = (2.0 * self.l * w.dot(&self.e) - w.norm_squared()) / (self.l + dist);
        Penetration {
            delta: hj + hr + gap,
            dh: dhj + self.ratio * dhr,
            d,
            dist,
        }
    }
}

#[derive(Debug, Clone)]
enum Law {
    Contact {
        law: ContactLaw,
        journal: Profile,
        rollers: Vec<RollerSys>,
    },
    Linear(LinearSupport),
}

#[derive(Debug, Clone)]
struct SupportSys {
    /// Lateral rows of Φ at the journal (2 × nm).
    rows: DMatrix<f64>,
    /// Index of the support mass's x coordinate in q, if any.
    stand: Option<usize>,
    law: Law,
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

/// The system (module doc).
#[derive(Debug, Clone)]
pub struct RollSystem {
    /// Number of modal coordinates.
    pub nm: usize,
    /// Number of coordinates.
    pub n: usize,
    m: DMatrix<f64>,
    k: DMatrix<f64>,
    e: DMatrix<f64>,
    c: DMatrix<f64>,
    g: DMatrix<f64>,
    d: DMatrix<f64>,
    fc: DVector<f64>,
    ft: DVector<f64>,
    gx: DVector<f64>,
    gy: DVector<f64>,
    /// Gravity on the support masses (inertial, constant).
    f_stand: DVector<f64>,
    /// Gravitational acceleration [m/s²].
    gravity: f64,
    supports: Vec<SupportSys>,
    drive: Option<(DVector<f64>, f64, f64)>,
    /// The prescribed speed profile.
    pub speed: SpeedProfile,
    /// For a constant speed: [K − Ω²E | D + 2ΩG] pre-combined (n × 2n).
    lin: Option<DMatrix<f64>>,
    /// `lin` for the SIMD product of the force.
    lin_padded: Option<Padded>,
    /// Sensor names and their lateral rows of Φ (2 × nm).
    pub sensors: Vec<(String, DMatrix<f64>)>,
    /// Displacement [m] per unit of each coordinate: max lateral translation of a mode over the
    /// nodes, 1 for support masses (the error-norm weights of `integrators`).
    pub weights: Vec<f64>,
}

/// (rows) p for a 2 × nm matrix of lateral modal rows (column-major: row 0 and 1 of column j at
/// 2j and 2j + 1) and the nm modal coordinates p, without a temporary.
fn rows_times(rows: &DMatrix<f64>, p: &[f64]) -> Vector2<f64> {
    let (mut x, mut y) = (0.0, 0.0);
    for (rj, pj) in rows.as_slice().chunks_exact(2).zip(p) {
        x += rj[0] * pj;
        y += rj[1] * pj;
    }
    Vector2::new(x, y)
}

/// R(θ) from (sin θ, cos θ).
fn rot((s, c): (f64, f64)) -> Matrix2<f64> {
    Matrix2::new(c, -s, s, c)
}

/// k δ^e, with the Hertz exponent 3/2 as δ √δ and 1 and 2 as products (no `pow`).
fn elastic(law: &ContactLaw, delta: f64) -> f64 {
    let e = law.exponent;
    law.k
        * if e == 1.5 {
            delta * delta.sqrt()
        } else if e == 1.0 {
            delta
        } else if e == 2.0 {
            delta * delta
        } else {
            delta.powf(e)
        }
}

/// A roundness profile Σ c_k cos(k x + φ_k), with the phases' sines and cosines precomputed.
#[derive(Debug, Clone)]
struct Profile {
    /// (k, c_k cos φ_k, c_k sin φ_k), ascending k.
    terms: Vec<(u32, f64, f64)>,
}

impl Profile {
    fn new(h: &[Harmonic]) -> Self {
        let mut terms: Vec<(u32, f64, f64)> = h
            .iter()
            .map(|hk| {
                (
                    hk.order,
                    hk.amplitude * hk.phase.cos(),
                    hk.amplitude * hk.phase.sin(),
                )
            })
            .collect();
        terms.sort_by_key(|t| t.0);
        Self { terms }
    }

    /// The profile and its derivative with respect to x, given (sin x, cos x), with the
    /// angle-addition recurrence for the multiples of x.
    fn eval(&self, (s1, c1): (f64, f64)) -> (f64, f64) {
        if self.terms.is_empty() {
            return (0.0, 0.0);
        }
        let (mut sk, mut ck) = (0.0, 1.0);
        let mut k = 0;
        let (mut v, mut dv) = (0.0, 0.0);
        for &(order, a, b) in &self.terms {
            while k < order {
                (sk, ck) = (sk * c1 + ck * s1, ck * c1 - sk * s1);
                k += 1;
            }
            // c cos(kx + φ) = a cos kx − b sin kx; d/dx = −k (a sin kx + b cos kx).
            v += a * ck - b * sk;
            dv -= order as f64 * (a * sk + b * ck);
        }
        (v, dv)
    }
}

/// The cubic STEP from 0 at u = 0 to 1 at u = 1, and its derivative.
fn step(u: f64) -> (f64, f64) {
    if u >= 1.0 {
        (1.0, 0.0)
    } else if u <= 0.0 {
        (0.0, 0.0)
    } else {
        (u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u))
    }
}

/// Force on the journal [N, inertial] and its stiffness and damping (−∂F/∂w, −∂F/∂ẇ) in the
/// relative journal–support coordinates w.
struct Local {
    f: Vector2<f64>,
    kc: Matrix2<f64>,
    cc: Matrix2<f64>,
}

impl RollSystem {
    /// Builds the system of a scene on its reduced model.
    pub fn new(scene: &Scene, model: &Model) -> Self {
        let r = &model.reduced;
        let nm = r.len();
        let n_st = scene.supports.iter().filter(|s| s.has_mass()).count();
        let n = nm + 2 * n_st;
        let pad = |a: &DMatrix<f64>| {
            let mut out = DMatrix::zeros(n, n);
            out.view_mut((0, 0), (nm, nm)).copy_from(a);
            out
        };
        let padv = |a: &DVector<f64>| {
            let mut out = DVector::zeros(n);
            out.rows_mut(0, nm).copy_from(a);
            out
        };
        let mut m = pad(&r.m);
        // Mass-normalised modes: ΦᵀMΦ is the identity to round-off. Its round-off is dropped so
        // that M is exactly diagonal and the integrators apply it elementwise (`dense::MassOp`);
        // a basis that is not orthonormal (an entry above 1e-10 of the diagonal) keeps its M.
        let orthonormal = (0..nm).all(|j| {
            (0..nm).all(|i| i == j || m[(i, j)].abs() <= 1e-10 * (m[(i, i)] * m[(j, j)]).sqrt())
        });
        if orthonormal {
            for j in 0..nm {
                for i in (0..nm).filter(|&i| i != j) {
                    m[(i, j)] = 0.0;
                }
            }
        }
        let mut k = pad(&r.k);
        let mut d = DMatrix::zeros(n, n);
        for i in 0..nm {
            let f = r.freq_hz[i];
            if f > 0.0 {
                d[(i, i)] =
                    2.0 * scene.damping.ratio(f) * 2.0 * std::f64::consts::PI * f * r.m[(i, i)];
            }
        }
        let gravity = scene.simulation.gravity;
        let mut f_stand = DVector::zeros(n);
        let mut supports = Vec::new();
        let mut next = nm;
        for s in &scene.supports {
            let node = model.rotor.named[&s.node];
            let rows = r.node_rows(node).rows(0, 2).into_owned();
            let mut add_mass = |mass: f64, kk: Matrix2<f64>, cc: Matrix2<f64>| {
                m[(next, next)] = mass;
                m[(next + 1, next + 1)] = mass;
                k.view_mut((next, next), (2, 2)).copy_from(&kk);
                d.view_mut((next, next), (2, 2)).copy_from(&cc);
                f_stand[next + 1] = -mass * gravity;
                next += 2;
                next - 2
            };
            let sys = match &s.model {
                SupportModel::Rollers(rs) => {
                    let st = rs.stand;
                    let idx = add_mass(st.mass, st.spring.k_matrix(), st.spring.c_matrix());
                    let rj = 0.5 * rs.journal_diameter;
                    SupportSys {
                        rows,
                        stand: Some(idx),
                        law: Law::Contact {
                            law: rs.contact,
                            journal: Profile::new(&rs.journal_roundness),
                            rollers: rs
                                .rollers
                                .iter()
                                .map(|ro| RollerSys {
                                    e: Vector2::new(ro.angle.sin(), -ro.angle.cos()),
                                    sin_cos: ro.angle.sin_cos(),
                                    l: rj + 0.5 * ro.diameter,
                                    roundness: Profile::new(&ro.roundness),
                                    ratio: match rs.roller_phase {
                                        RollerPhase::RollAngle => 1.0,
                                        RollerPhase::RollerAngle => -rj / (0.5 * ro.diameter),
                                    },
                                })
                                .collect(),
                        },
                    }
                }
                SupportModel::Linear(l) => {
                    let stand = l
                        .mass
                        .map(|(mass, g)| add_mass(mass, g.k_matrix(), g.c_matrix()));
                    SupportSys {
                        rows,
                        stand,
                        law: Law::Linear(l.clone()),
                    }
                }
            };
            supports.push(sys);
        }
        let drive = scene.drive.as_ref().map(|dr| {
            let row = r.node_rows(model.rotor.named[&dr.node]).row(2).transpose();
            (
                padv(&row.into_owned()),
                dr.axial_stiffness,
                dr.axial_damping,
            )
        });
        let sensors = scene
            .sensors
            .iter()
            .map(|name| {
                let node = model.rotor.named[name];
                (name.clone(), r.node_rows(node).rows(0, 2).into_owned())
            })
            .collect();
        let mut weights = vec![1.0; n];
        for (j, w) in weights.iter_mut().enumerate().take(nm) {
            *w = (0..r.phi.nrows())
                .filter(|i| i % 6 < 3)
                .map(|i| r.phi[(i, j)].abs())
                .fold(0.0, f64::max);
        }
        let mut sys = Self {
            nm,
            n,
            m,
            k,
            e: pad(&r.e),
            c: pad(&r.c),
            g: pad(&r.gc),
            d,
            fc: padv(&r.fc),
            ft: padv(&r.ft),
            gx: padv(&r.gx),
            gy: padv(&r.gy),
            f_stand,
            gravity,
            supports,
            drive,
            speed: scene.speed.clone(),
            lin: None,
            lin_padded: None,
            sensors,
            weights,
        };
        if let SpeedProfile::Constant(w) = sys.speed {
            let mut lin = DMatrix::zeros(n, 2 * n);
            lin.view_mut((0, 0), (n, n))
                .copy_from(&(&sys.k - w * w * &sys.e));
            lin.view_mut((0, n), (n, n))
                .copy_from(&(&sys.d + 2.0 * w * &sys.g));
            sys.lin_padded = Some(Padded::from_matrix(&lin));
            sys.lin = Some(lin);
        }
        sys
    }

    /// The mass matrix.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.m
    }

    /// The support's force law at roll angle θ, given as (θ, sin θ, cos θ).
    fn local(
        &self,
        s: &SupportSys,
        (theta, st, ct): (f64, f64, f64),
        omega: f64,
        w: Vector2<f64>,
        wd: Vector2<f64>,
        out: Option<&mut Vec<f64>>,
    ) -> Local {
        match &s.law {
            Law::Linear(l) => {
                let sp = l.spring_at(omega);
                let (k, c) = (sp.k_matrix(), sp.c_matrix());
                Local {
                    f: -(k * w + c * wd),
                    kc: k,
                    cc: c,
                }
            }
            Law::Contact {
                law,
                journal,
                rollers,
            } => {
                let mut f = Vector2::zeros();
                let mut kc = Matrix2::zeros();
                let mut cc = Matrix2::zeros();
                let mut forces = out;
                for r in rollers {
                    let p = r.penetration(journal, (theta, st, ct), w);
                    let (delta, dist) = (p.delta, p.dist);
                    let nrm = p.d / dist;
                    let ddelta = omega * p.dh - nrm.dot(&wd);
                    let mut fmag = 0.0;
                    if delta > 0.0 {
                        let (st, dst) = step(delta / law.d);
                        let cdamp = law.c_max * st;
                        let elastic = elastic(law, delta);
                        fmag = elastic + cdamp * ddelta;
                        if fmag > 0.0 {
                            let kd =
                                law.exponent * elastic / delta + law.c_max * dst / law.d * ddelta;
                            let nnt = nrm * nrm.transpose();
                            kc += kd * nnt - fmag / dist * (Matrix2::identity() - nnt);
                            cc += cdamp * nnt;
                            f += fmag * nrm;
                        } else {
                            fmag = 0.0;
                        }
                    }
                    if let Some(v) = forces.as_deref_mut() {
                        v.push(fmag);
                    }
                }
                Local { f, kc, cc }
            }
        }
    }

    /// Journal displacement and velocity relative to the support (inertial), and R(θ)Φ_j.
    fn relative(
        &self,
        s: &SupportSys,
        sc: (f64, f64),
        omega: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Matrix2<f64>) {
        let r = rot(sc);
        let u = rows_times(&s.rows, &q.as_slice()[..self.nm]);
        let ub = rows_times(&s.rows, &v.as_slice()[..self.nm]);
        let wj = r * u;
        let mut wjd = r * ub + omega * Vector2::new(-wj.y, wj.x);
        let mut w = wj;
        if let Some(i) = s.stand {
            w -= Vector2::new(q[i], q[i + 1]);
            wjd -= Vector2::new(v[i], v[i + 1]);
        }
        (w, wjd, r)
    }

    /// F(q, q̇) at roll angle θ, speed Ω and acceleration Ω̇, into `out`.
    pub fn force_at(
        &self,
        (theta, omega, alpha): (f64, f64, f64),
        q: &DVector<f64>,
        v: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        match &self.lin_padded {
            Some(lin) if alpha == 0.0 && Some(omega) == self.constant_speed() => {
                // [K − Ω²E | D + 2ΩG] [q; v] in one SIMD product (`crate::numerics::dense`): the force's
                // largest cost in the timing case.
                lin.matvec(out.as_mut_slice(), false, q.as_slice(), v.as_slice(), -1.0);
            }
            _ => {
                out.gemv(-1.0, &self.k, q, 0.0);
                out.gemv(omega * omega, &self.e, q, 1.0);
                out.gemv(-1.0, &self.d, v, 1.0);
                out.gemv(-2.0 * omega, &self.g, v, 1.0);
                if alpha != 0.0 {
                    out.gemv(-alpha, &self.c, q, 1.0);
                }
            }
        }
        // The one transcendental call of the force (with roller roundness on the roll angle).
        let (s, c) = theta.sin_cos();
        let (w2, gs, gc) = (omega * omega, -self.gravity * s, -self.gravity * c);
        let loads = (self.fc.as_slice().iter())
            .zip(self.gx.as_slice())
            .zip(self.gy.as_slice())
            .zip(self.f_stand.as_slice());
        for (o, (((fc, gx), gy), fs)) in out.as_mut_slice().iter_mut().zip(loads) {
            *o += w2 * fc + gs * gx + gc * gy + fs;
        }
        if alpha != 0.0 {
            out.axpy(-alpha, &self.ft, 1.0);
        }
        for sup in &self.supports {
            let (w, wd, r) = self.relative(sup, (s, c), omega, q, v);
            let loc = self.local(sup, (theta, s, c), omega, w, wd, None);
            let fb = r.transpose() * loc.f;
            let rows = sup.rows.as_slice().chunks_exact(2);
            for (o, rj) in out.as_mut_slice()[..self.nm].iter_mut().zip(rows) {
                *o += rj[0] * fb.x + rj[1] * fb.y;
            }
            if let Some(i) = sup.stand {
                out[i] -= loc.f.x;
                out[i + 1] -= loc.f.y;
            }
        }
        if let Some((row, ka, ca)) = &self.drive {
            let uz = row.dot(q);
            let vz = row.dot(v);
            out.axpy(-(ka * uz + ca * vz), row, 1.0);
        }
    }

    fn constant_speed(&self) -> Option<f64> {
        match self.speed {
            SpeedProfile::Constant(w) => Some(w),
            _ => None,
        }
    }

    /// F(t, q, q̇).
    pub fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.force_at(self.speed.at(t), q, v, out);
    }

    /// out = a M − b ∂F/∂q − c ∂F/∂q̇ at (θ, Ω, Ω̇).
    pub fn newton_matrix_at(
        &self,
        (theta, omega, alpha): (f64, f64, f64),
        q: &DVector<f64>,
        v: &DVector<f64>,
        (a, b, c): (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        let n = self.n;
        match &self.lin {
            Some(lin) if alpha == 0.0 && Some(omega) == self.constant_speed() => {
                // a M + b (K − Ω²E) + c (D + 2ΩG) in one pass (nalgebra's scaled sums make an
                // n × n temporary each).
                let (kq, cv) = lin.as_slice().split_at(n * n);
                let terms = self.m.as_slice().iter().zip(kq).zip(cv);
                for (o, ((m, k), d)) in out.as_mut_slice().iter_mut().zip(terms) {
                    *o = a * m + b * k + c * d;
                }
            }
            _ => {
                out.copy_from(&self.m);
                *out *= a;
                *out += b * &self.k;
                *out -= (b * omega * omega) * &self.e;
                if alpha != 0.0 {
                    *out += (b * alpha) * &self.c;
                }
                *out += c * &self.d;
                *out += (2.0 * c * omega) * &self.g;
            }
        }
        let (st, ct) = theta.sin_cos();
        for sup in &self.supports {
            let (w, wd, r) = self.relative(sup, (st, ct), omega, q, v);
            let loc = self.local(sup, (theta, st, ct), omega, w, wd, None);
            // T_q (2 × n): w = R Φ_j p − s; T_Ω = Ω S R Φ_j (the rotation of the journal velocity).
            let rp = DMatrix::from_column_slice(2, self.nm, (r * &sup.rows).as_slice());
            let tq = self.connection(sup, &rp);
            let s_mat = Matrix2::new(0.0, -omega, omega, 0.0);
            let mut tw = DMatrix::zeros(2, n);
            tw.view_mut((0, 0), (2, self.nm)).copy_from(&(s_mat * rp));
            let kk = b * loc.kc + c * loc.cc;
            let inner = kk * &tq + (b * loc.cc) * tw;
            // out += T_qᵀ inner, a rank-2 update (nalgebra's gemm packs for a general product).
            let (tq, inner) = (tq.as_slice(), inner.as_slice());
            for (col, ij) in out
                .as_mut_slice()
                .chunks_exact_mut(n)
                .zip(inner.chunks_exact(2))
            {
                for (o, ti) in col.iter_mut().zip(tq.chunks_exact(2)) {
                    *o += ti[0] * ij[0] + ti[1] * ij[1];
                }
            }
        }
        if let Some((row, ka, ca)) = &self.drive {
            out.ger(b * ka + c * ca, row, row, 1.0);
        }
    }

    /// The 2 × n map from q to a support's relative journal displacement w = (rows) p − s, with
    /// `rows` the journal's lateral modal rows (already rotated to the frame of w).
    fn connection(&self, sup: &SupportSys, rows: &DMatrix<f64>) -> DMatrix<f64> {
        let mut tq = DMatrix::zeros(2, self.n);
        tq.view_mut((0, 0), (2, self.nm)).copy_from(rows);
        if let Some(i) = sup.stand {
            tq[(0, i)] = -1.0;
            tq[(1, i + 1)] = -1.0;
        }
        tq
    }

    /// The Newton matrix at time t.
    pub fn newton_matrix(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        coef: (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        self.newton_matrix_at(self.speed.at(t), q, v, coef, out);
    }

    /// Journal, support-mass and contact state of every support at time t.
    pub fn support_states(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> Vec<SupportState> {
        let (theta, omega, _) = self.speed.at(t);
        let (st, ct) = theta.sin_cos();
        self.supports
            .iter()
            .map(|s| {
                let (w, wd, _) = self.relative(s, (st, ct), omega, q, v);
                let stand = s
                    .stand
                    .map(|i| Vector2::new(q[i], q[i + 1]))
                    .unwrap_or_default();
                let mut contact = Vec::new();
                self.local(s, (theta, st, ct), omega, w, wd, Some(&mut contact));
                SupportState {
                    journal: w + stand,
                    stand,
                    contact,
                }
            })
            .collect()
    }

    /// Inertial lateral displacement [m] of each sensor plane's centre at time t.
    pub fn sensor_displacements(&self, t: f64, q: &DVector<f64>) -> Vec<Vector2<f64>> {
        let r = rot(self.speed.at(t).0.sin_cos());
        let p = &q.as_slice()[..self.nm];
        self.sensors
            .iter()
            .map(|(_, rows)| r * rows_times(rows, p))
            .collect()
    }

    /// The body-frame velocity that keeps a deflected shape q at rest in the inertial frame when
    /// the spin jumps to Ω: material velocity u̇ = −Ω ẑ×u, projected on the modes, M v = −Ω G_c q.
    /// (Zero body velocity would make the static sag turn with the roll and throw it sideways.)
    pub fn quiescent_velocity(&self, q: &DVector<f64>, omega: f64) -> DVector<f64> {
        let rhs = -omega * (&self.g * q);
        self.m
            .clone()
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| DVector::zeros(self.n))
    }

    /// The gravity load at rest (θ = 0): rotor and support masses.
    pub fn gravity_at_rest(&self) -> DVector<f64> {
        -self.gravity * &self.gy + &self.f_stand
    }

    /// Static equilibrium under gravity at standstill (θ = 0): Newton on F(q, 0) = 0 from `q0`.
    /// Open contacts get the stiffness of a 1 µm penetration in the Newton matrix (not in F) so
    /// the iteration can close them.
    pub fn static_equilibrium(&self, q0: &DVector<f64>) -> Result<DVector<f64>, String> {
        let mut q = q0.clone();
        let v = DVector::zeros(self.n);
        let mut f = DVector::zeros(self.n);
        let mut jac = DMatrix::zeros(self.n, self.n);
        let state = (0.0, 0.0, 0.0);
        let floor = self.contact_floor();
        for _ in 0..200 {
            self.force_at(state, &q, &v, &mut f);
            self.newton_matrix_at(state, &q, &v, (0.0, 1.0, 0.0), &mut jac);
            for (sup, kf) in self.supports.iter().zip(&floor) {
                if let (Law::Contact { .. }, Some(kf)) = (&sup.law, kf) {
                    let tq = self.connection(sup, &sup.rows);
                    jac.gemm(1.0, &tq.transpose(), &(kf * &tq), 1.0);
                }
            }
            let dq =
                jac.clone().lu().solve(&f).ok_or(
                    "static equilibrium: singular stiffness (is every rigid mode supported?)",
                )?;
            q += &dq;
            let step = dq
                .iter()
                .zip(&self.weights)
                .map(|(d, w)| (d * w).abs())
                .fold(0.0, f64::max);
            if step < 1e-13 {
                self.force_at(state, &q, &v, &mut f);
                return Ok(q);
            }
        }
        Err("static equilibrium: Newton did not converge in 200 iterations".into())
    }

    /// A small regularising contact stiffness per contact support (1 µm penetration, all rollers).
    fn contact_floor(&self) -> Vec<Option<Matrix2<f64>>> {
        self.supports
            .iter()
            .map(|s| match &s.law {
                Law::Contact { law, rollers, .. } => Some(
                    rollers
                        .iter()
                        .map(|r| 1e-3 * law.tangent(1e-6) * r.e * r.e.transpose())
                        .sum(),
                ),
                Law::Linear(_) => None,
            })
            .collect()
    }
}

impl crate::integrators::SecondOrder for RollSystem {
    fn n(&self) -> usize {
        self.n
    }

    fn mass(&self) -> &DMatrix<f64> {
        &self.m
    }

    fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        RollSystem::force(self, t, q, v, out);
    }

    fn newton_matrix(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        coef: (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        RollSystem::newton_matrix(self, t, q, v, coef, out);
    }

    fn weights(&self) -> &[f64] {
        &self.weights
    }

    fn linear_in_state(&self) -> bool {
        self.supports
            .iter()
            .all(|s| matches!(s.law, Law::Linear(_)))
    }

    /// One event per contact roller: its penetration δ [m].
    fn n_events(&self) -> usize {
        (self.supports.iter())
            .map(|s| match &s.law {
                Law::Contact { rollers, .. } => rollers.len(),
                Law::Linear(_) => 0,
            })
            .sum()
    }

    /// The penetration δ [m] of every contact roller, supports and rollers in scene order.
    fn events(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut [f64]) {
        let (theta, omega, _) = self.speed.at(t);
        let (st, ct) = theta.sin_cos();
        let mut slots = out.iter_mut();
        for sup in &self.supports {
            if let Law::Contact {
                journal, rollers, ..
            } = &sup.law
            {
                let (w, _, _) = self.relative(sup, (st, ct), omega, q, v);
                for (r, slot) in rollers.iter().zip(&mut slots) {
                    *slot = r.penetration(journal, (theta, st, ct), w).delta;
                }
            }
        }
    }
}
