//! The barring roots of the coupled rolls: every coordinate of the machine in the viscoelastic
//! nip at once.
//!
//! In: a [`CoupledNip`]: the machine's M [kg], C [N s/m] and K [N/m] on its coordinates (the
//! rolls on their supports, the nip's closed segments' static stiffness taken out; at speed with
//! each roll's gyroscopic and circulatory terms as `linear/machine.rs` adds them), and per
//! closed segment j its length L_j [m], its penetration row J_j (δ_j = J_j q) and the cover's
//! steady rolling state there ([`Rolling`]); the cover ([`CoverSpec`]) and the covered roll's
//! revolution frequency f_c [Hz]. Out: [`CoupledNip::roots`]: the characteristic roots λ
//! [1/s] of the coupled machine found from its frozen modes, each with the frozen mode it
//! started from and the nip's share of it ([`CoupledNip::newton`]: zero for a mode of the rolls
//! the nip does not touch); [`CoupledNip::frozen`]: those modes (frequency [Hz], damping ratio, the nip's
//! share of their strain energy).
//!
//! Method: small vibration q e^{λt} about the steady rolling state: each closed segment pushes
//! back with L_j H_j(λ) J_j q (H of `dynamics/cover_response.rs`: the rolling cover's response
//! at the vibration's own rate with the memory of every revolution), so the roots are those of
//! det T(λ) = 0, T(λ) = M λ² + C λ + K + Σ_j L_j H_j(λ) J_jᵀ J_j. Newton's method on det T:
//! λ ← λ − 1/tr(T⁻¹ T′) (T′ = 2 M λ + C + Σ_j L_j H_j′(λ) J_jᵀ J_j, H′ by a central difference:
//! H is analytic), converged when the step is below [`ROOT_TOLERANCE`] of |λ|, at most
//! [`ROOT_ITERATIONS`] steps. Starts: the frozen modes, the eigenvalues of the state matrix of
//! M q̈ + (C + Σ L_j Im H_j(iω̂)/ω̂ J_jᵀJ_j) q̇ + (K + Σ L_j Re H_j(iω̂) J_jᵀJ_j) q = 0 at
//! ω̂ = 2π [`FROZEN_HZ`] (the nip as a spring and dashpot at one frequency), those whose share
//! of strain energy in the nip is at least [`NIP_SHARE`] of the largest, each shifted in
//! frequency by [`START_SHIFTS`] × f_c (the delay's roots lie about a revolution frequency
//! apart). Where the one-mode analysis of `linear/barring_machine.rs` projects the nip on one
//! mode of the rolls without it, here the nip couples every mode: the vibration near the cover's
//! frequency is a combination of many of the rolls' modes, with their damping.

use nalgebra::{Complex, DMatrix, DVector};

use crate::dynamics::cover::Rolling;
use crate::dynamics::cover_response::response;
use crate::numerics::eigen;
use crate::scene::CoverSpec;

type C64 = Complex<f64>;

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// Relative Newton step at which a root counts as converged.
pub const ROOT_TOLERANCE: f64 = 1e-10;

/// Most Newton steps from one start.
pub const ROOT_ITERATIONS: usize = 60;

/// The frequency at which the frozen modes take the nip as a spring and dashpot [Hz].
pub const FROZEN_HZ: f64 = 50.0;

/// Frozen modes started from: those with at least this share of the largest nip share.
pub const NIP_SHARE: f64 = 0.01;

/// Shifts of each start in frequency, in revolution frequencies of the covered roll.
pub const START_SHIFTS: [f64; 5] = [-1.0, -0.5, 0.0, 0.5, 1.0];

/// The coupled machine in its viscoelastic nip (module doc).
#[derive(Debug, Clone)]
pub struct CoupledNip<'a> {
    /// Mass matrix [kg].
    pub m: DMatrix<f64>,
    /// Damping matrix [N s/m] (without the cover).
    pub c: DMatrix<f64>,
    /// Stiffness matrix [N/m] (without the cover).
    pub k: DMatrix<f64>,
    /// Per closed segment: its length L [m], its row J and the cover's rolling state there.
    pub segments: Vec<(f64, DVector<f64>, &'a Rolling)>,
}

/// A frozen mode (module doc).
#[derive(Debug, Clone, Copy)]
pub struct FrozenMode {
    /// Its eigenvalue [1/s].
    pub lambda: C64,
    /// Share of its strain energy in the nip [-].
    pub nip_share: f64,
}

/// A root of det T(λ) = 0 and the frozen mode it was found from.
#[derive(Debug, Clone, Copy)]
pub struct CoupledRoot {
    /// λ [1/s].
    pub lambda: C64,
    /// Index of the frozen mode in [`CoupledNip::frozen`]'s list.
    pub mode: usize,
    /// The nip's share of the root (see [`CoupledNip::newton`]) [-].
    pub nip_share: f64,
}

impl CoupledNip<'_> {
    /// Σ_j L_j h_j J_jᵀ J_j added to `t`, h_j = `h(j)`.
    fn add_nip(&self, t: &mut DMatrix<C64>, h: impl Fn(usize) -> C64) {
        for (j, (len, row, _)) in self.segments.iter().enumerate() {
            let w = h(j) * *len;
            for a in 0..row.len() {
                if row[a] == 0.0 {
                    continue;
                }
                for b in 0..row.len() {
                    t[(a, b)] += w * (row[a] * row[b]);
                }
            }
        }
    }

    /// Each closed segment's H_j(λ) (module doc).
    fn responses(&self, cover: &CoverSpec, cover_hz: f64, l: C64) -> Vec<C64> {
        (self.segments.iter())
            .map(|(_, _, r)| response(cover, r, cover_hz, l))
            .collect()
    }

    /// T(λ) with the segments' responses `hs` = H_j(λ) (module doc).
    fn matrix(&self, l: C64, hs: &[C64]) -> DMatrix<C64> {
        let n = self.m.nrows();
        let mut t = DMatrix::from_fn(n, n, |a, b| {
            l * l * self.m[(a, b)] + l * self.c[(a, b)] + self.k[(a, b)]
        });
        self.add_nip(&mut t, |j| hs[j]);
        t
    }

    /// The frozen modes at ω̂ = 2π [`FROZEN_HZ`] with a positive frequency (module doc).
    pub fn frozen(&self, cover: &CoverSpec, cover_hz: f64) -> Result<Vec<FrozenMode>, String> {
        let n = self.m.nrows();
        let w = TAU * FROZEN_HZ;
        let hs = self.responses(cover, cover_hz, C64::new(0.0, w));
        let mut k = self.k.clone();
        let mut c = self.c.clone();
        let mut kn = DMatrix::zeros(n, n);
        for ((len, row, _), h) in self.segments.iter().zip(&hs) {
            kn.ger(len * h.re, row, row, 1.0);
            c.ger(len * h.im / w, row, row, 1.0);
        }
        k += &kn;
        let m_inv = (self.m.clone().lu().try_inverse()).ok_or("the mass matrix is singular")?;
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        a.view_mut((n, 0), (n, n)).copy_from(&(-&m_inv * &k));
        a.view_mut((n, n), (n, n)).copy_from(&(-&m_inv * &c));
        let (values, vectors) = eigen::general(&a).map_err(|e| format!("frozen modes: {e}"))?;
        let quad = |mat: &DMatrix<f64>, v: &DVector<C64>| -> f64 {
            let mut s = C64::new(0.0, 0.0);
            for r in 0..n {
                for q in 0..n {
                    s += v[r].conj() * mat[(r, q)] * v[q];
                }
            }
            s.re
        };
        let mut out = Vec::new();
        for (i, l) in values.iter().enumerate() {
            if l.im <= 0.0 {
                continue;
            }
            let v = DVector::from_fn(n, |r, _| C64::new(vectors[(r, i)].re, vectors[(r, i)].im));
            let share = quad(&kn, &v) / quad(&k, &v);
            out.push(FrozenMode {
                lambda: C64::new(l.re, l.im),
                nip_share: share,
            });
        }
        out.sort_by(|a, b| a.lambda.im.total_cmp(&b.lambda.im));
        Ok(out)
    }

    /// Newton's method on det T from `start` (module doc): the root and the nip's share of it,
    /// e = |2 (dλ/dα)/λ| for T + α Σ_j L_j H_j J_jᵀJ_j at α = 0 (for an undamped mode on a spring
    /// nip the share of its strain energy in the nip; zero for a root the nip does not touch);
    /// `None` when it does not converge.
    pub fn newton(&self, cover: &CoverSpec, cover_hz: f64, start: C64) -> Option<(C64, f64)> {
        let n = self.m.nrows();
        let mut l = start;
        for _ in 0..ROOT_ITERATIONS {
            let hs = self.responses(cover, cover_hz, l);
            let inv = self.matrix(l, &hs).lu().try_inverse()?;
            let h = 1e-7 * l.norm().max(1.0);
            let mut tr = C64::new(0.0, 0.0);
            for a in 0..n {
                for b in 0..n {
                    tr += inv[(a, b)] * (2.0 * l * self.m[(b, a)] + self.c[(b, a)]);
                }
            }
            let mut nip = C64::new(0.0, 0.0);
            for ((len, row, r), hl) in self.segments.iter().zip(&hs) {
                let dh = (response(cover, r, cover_hz, l + h)
                    - response(cover, r, cover_hz, l - h))
                    / (2.0 * h);
                let mut s = C64::new(0.0, 0.0);
                for a in 0..n {
                    if row[a] == 0.0 {
                        continue;
                    }
                    for b in 0..n {
                        s += inv[(a, b)] * (row[a] * row[b]);
                    }
                }
                tr += dh * *len * s;
                nip += *hl * *len * s;
            }
            let step = C64::new(1.0, 0.0) / tr;
            if !step.re.is_finite() || !step.im.is_finite() {
                return None;
            }
            l -= step;
            if step.norm() <= ROOT_TOLERANCE * l.norm().max(1.0) {
                return Some((l, (2.0 * nip / (tr * l)).norm()));
            }
        }
        None
    }

    /// The roots found from the frozen modes `modes` (of [`CoupledNip::frozen`]) with a positive
    /// frequency, each once (module doc).
    pub fn roots(
        &self,
        cover: &CoverSpec,
        cover_hz: f64,
        modes: &[FrozenMode],
    ) -> Vec<CoupledRoot> {
        let top = modes.iter().map(|m| m.nip_share).fold(0.0, f64::max);
        let mut out: Vec<CoupledRoot> = Vec::new();
        for (i, mode) in modes.iter().enumerate() {
            if mode.nip_share < NIP_SHARE * top {
                continue;
            }
            for s in START_SHIFTS {
                let start = mode.lambda + C64::new(0.0, s * TAU * cover_hz);
                let Some((l, share)) = self.newton(cover, cover_hz, start) else {
                    continue;
                };
                if l.im <= 0.0 || out.iter().any(|r| (r.lambda - l).norm() <= 1e-6 * l.norm()) {
                    continue;
                }
                out.push(CoupledRoot {
                    lambda: l,
                    mode: i,
                    nip_share: share,
                });
            }
        }
        out
    }
}
