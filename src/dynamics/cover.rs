//! A viscoelastic roll cover whose deformation is carried round by the roll: a Winkler layer of
//! standard-linear-solid (Zener) elements at points round the covered roll, each keeping its
//! internal state after it leaves the nip until it comes back one revolution later.
//!
//! In: a [`CoverSpec`] (relaxed and unrelaxed foundation moduli k_r, k_u [N/m³], relaxation
//! time τ [s], R = R_a R_b/(R_a + R_b) [m], the covered roll's outer radius R_c [m], N points
//! round the circumference) and a segment length L [m]; per evaluation the time t [s], the
//! body-frame angle ψ [rad] of the nip line on the covered roll and the segment's penetration
//! δ [m]. Out: the segment's force F [N] (pushing the rolls apart) and dF/dδ [N/m]; per point
//! its surface compression w [m] and internal (dashpot) compression w_v [m].
//!
//! Method: a point i sits at the body angle 2πi/N, so at arc x_i = R_c·wrap(2πi/N − ψ) from the
//! nip line, where the two surfaces overlap by g_i = δ − x_i²/(2R) (the Winkler geometry of the
//! elastic `cover` law). A point is a spring k_r in parallel with a Maxwell arm (spring
//! k_1 = k_u − k_r, dashpot of time τ = η/k_1): its pressure is p = k_r w + k_1 (w − w_v) with
//! ẇ_v = (w − w_v)/τ. In contact w = g_i and p > 0; out of contact p = 0, so
//! w = (k_1/k_u) w_v (the dent not yet recovered) and w_v decays with the retardation time
//! τ_σ = τ k_u/k_r. Over a step from the last accepted time t₀ (the anchor) to t, w is taken
//! linear between its values at t₀ and t and w_v integrated exactly (exponential integrator):
//! w_v(t) = E w_v(t₀) + (φ₁ − E) w(t₀) + (1 − φ₁) w(t), E = e^(−h/τ), φ₁ = (1 − E)/(h/τ),
//! h = t − t₀, so ∂p/∂g = k_u − k_1(1 − φ₁); a point is in contact when that p is positive, else
//! free with the exact decay. F = L Δs Σ p_i, Δs = 2πR_c/N (a point carries its arc). Only the
//! points inside the band |x| < √(2Rδ) are touched; a point outside keeps the time of its last
//! update and is brought forward by the exact free decay when it next enters. A held penetration
//! at standstill relaxes as F(t) = F_r + (F_u − F_r) e^(−t/τ) exactly; [`CoverTrack::start`]
//! puts the points in the band at their relaxed state (w_v = w), the static equilibrium's.
//!
//! [`rolling`] gives the steady rolling state of one point passing a held penetration δ at a
//! surface speed, and from it the linearised nip of the barring analysis (`linear/barring.rs`):
//! the force per length after a step Δδ held for a revolution, k_c = ΔF/Δδ, and the force one
//! revolution after the step ends, −μ k_c Δδ (module doc of `linear/barring_machine.rs`).

use std::f64::consts::PI;

use crate::scene::CoverSpec;

/// One point's state at its last update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoverPoint {
    /// Internal (dashpot) compression w_v [m].
    pub wv: f64,
    /// Surface compression w [m].
    pub w: f64,
    /// Time of this state [s].
    pub t: f64,
}

const REST: CoverPoint = CoverPoint {
    wv: 0.0,
    w: 0.0,
    t: 0.0,
};

/// The SLS element's update rules, shared by the track and the rolling analysis.
#[derive(Debug, Clone, Copy)]
struct Sls {
    ku: f64,
    k1: f64,
    tau: f64,
    tau_sigma: f64,
}

impl Sls {
    fn new(c: &CoverSpec) -> Self {
        Self {
            ku: c.unrelaxed,
            k1: c.unrelaxed - c.relaxed,
            tau: c.relaxation_time,
            tau_sigma: c.relaxation_time * c.unrelaxed / c.relaxed,
        }
    }

    /// The free point brought to `t` by the exact decay.
    fn free(&self, p: CoverPoint, t: f64) -> CoverPoint {
        let wv = p.wv * (-(t - p.t).max(0.0) / self.tau_sigma).exp();
        CoverPoint {
            wv,
            w: self.k1 / self.ku * wv,
            t,
        }
    }

    /// The point from state `p` to time `t` at overlap `g` [m]: its new state, pressure [N/m²]
    /// and ∂p/∂g [N/m³] (module doc).
    fn step(&self, p: CoverPoint, t: f64, g: f64) -> (CoverPoint, f64, f64) {
        if g > 0.0 {
            let x = (t - p.t).max(0.0) / self.tau;
            let e = (-x).exp();
            let phi = if x > 1e-6 {
                (1.0 - e) / x
            } else {
                1.0 - 0.5 * x + x * x / 6.0
            };
            let wv = e * p.wv + (phi - e) * p.w + (1.0 - phi) * g;
            let pressure = self.ku * g - self.k1 * wv;
            if pressure > 0.0 {
                let q = CoverPoint { wv, w: g, t };
                return (q, pressure, self.ku - self.k1 * (1.0 - phi));
            }
        }
        (self.free(p, t), 0.0, 0.0)
    }
}

/// The points of one segment's cover and its anchor (the last accepted time).
#[derive(Debug, Clone)]
pub struct CoverTrack {
    spec: CoverSpec,
    sls: Sls,
    length: f64,
    points: Vec<CoverPoint>,
    /// Points in contact at the anchor.
    active: Vec<usize>,
    anchor: f64,
}

/// x wrapped into (−π, π].
fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * PI);
    if y > PI {
        y - 2.0 * PI
    } else {
        y
    }
}

impl CoverTrack {
    /// A fresh cover (every point at rest) on a segment of length `length` [m].
    pub fn new(spec: &CoverSpec, length: f64) -> Self {
        Self {
            spec: *spec,
            sls: Sls::new(spec),
            length,
            points: vec![REST; spec.points],
            active: Vec::new(),
            anchor: 0.0,
        }
    }

    /// Arc Δs [m] a point carries.
    pub fn spacing(&self) -> f64 {
        2.0 * PI * self.spec.cover_radius / self.spec.points as f64
    }

    /// The indices of the points inside the band |x| < √(2Rδ) at nip angle `psi`, with their
    /// overlaps g [m] (at most all N points).
    fn band(&self, psi: f64, delta: f64) -> Vec<(usize, f64)> {
        if delta <= 0.0 {
            return Vec::new();
        }
        let n = self.spec.points;
        let step = 2.0 * PI / n as f64;
        let half = (2.0 * self.spec.radius * delta).sqrt() / self.spec.cover_radius;
        let count = ((2.0 * half / step).ceil() as usize + 2).min(n);
        let first = ((psi - half) / step).floor() as i64;
        (0..count)
            .map(|k| (first + k as i64).rem_euclid(n as i64) as usize)
            .filter_map(|i| {
                let x = self.spec.cover_radius * wrap(i as f64 * step - psi);
                let g = delta - x * x / (2.0 * self.spec.radius);
                (g > 0.0).then_some((i, g))
            })
            .collect()
    }

    /// A point's state at the anchor (a free point brought forward from its last update).
    fn at_anchor(&self, i: usize) -> CoverPoint {
        let p = self.points[i];
        if p.t < self.anchor {
            self.sls.free(p, self.anchor)
        } else {
            p
        }
    }

    /// Every point at rest, those in the band at nip angle `psi` [rad] and penetration `delta`
    /// [m] relaxed there (w_v = w = g), anchored at `t` [s].
    pub fn start(&mut self, t: f64, psi: f64, delta: f64) {
        self.points.fill(CoverPoint { t, ..REST });
        self.active.clear();
        for (i, g) in self.band(psi, delta) {
            self.points[i] = CoverPoint { wv: g, w: g, t };
            self.active.push(i);
        }
        self.anchor = t;
    }

    /// The segment's force F [N] and dF/dδ [N/m] at time `t` [s], nip angle `psi` [rad] and
    /// penetration `delta` [m], from the anchor's states (module doc); no state changes.
    pub fn force(&self, t: f64, psi: f64, delta: f64) -> (f64, f64) {
        let (mut f, mut k) = (0.0, 0.0);
        for (i, g) in self.band(psi, delta) {
            let (_, p, dp) = self.sls.step(self.at_anchor(i), t, g);
            f += p;
            k += dp;
        }
        let w = self.length * self.spacing();
        (w * f, w * k)
    }

    /// Moves the anchor to the accepted time `t` [s] at `psi`, `delta`: the points in the band
    /// and those in contact at the old anchor take their states at `t`.
    pub fn commit(&mut self, t: f64, psi: f64, delta: f64) {
        let band = self.band(psi, delta);
        let mut active = Vec::with_capacity(band.len());
        for &(i, g) in &band {
            let (q, p, _) = self.sls.step(self.at_anchor(i), t, g);
            self.points[i] = q;
            if p > 0.0 {
                active.push(i);
            }
        }
        for &i in &self.active {
            if !band.iter().any(|(j, _)| *j == i) {
                let q = self.sls.free(self.at_anchor(i), t);
                self.points[i] = q;
            }
        }
        self.active = active;
        self.anchor = t;
    }

    /// Point `i`'s state at its last update.
    pub fn point(&self, i: usize) -> CoverPoint {
        self.points[i]
    }
}

/// The steady rolling of a cover past a held penetration, per unit length of nip.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Rolling {
    /// Steady force per length [N/m].
    pub force_n_per_m: f64,
    /// k_c per length [N/m²]: the force change per penetration change held for a revolution.
    pub stiffness_n_per_m2: f64,
    /// μ: the force change one revolution after the step ends, per −k_c Δδ.
    pub overlap: f64,
    /// Time a point spends in the band [s].
    pub dwell_s: f64,
    /// Time a point spends in contact (pressure > 0) [s]: from where the overlap exceeds its
    /// dent to where it lifts off, within the band (`dynamics/cover_response.rs`).
    pub contact_s: f64,
}

/// Steps a point takes across the band in [`rolling`].
pub const ROLLING_STEPS: usize = 4000;

/// Most revolutions [`rolling`] follows to reach the periodic state.
pub const ROLLING_REVOLUTIONS: usize = 10_000;

/// One pass of a point through the band |x| < a = √(2Rδ) at overlap δ − x²/2R, surface speed
/// `v` [m/s], entering with the internal compression `wv` [m] (free); the internal compression at
/// the exit, ∫p dx [N/m] (trapezoid) and the time the point is in contact (p > 0) [s].
fn pass(sls: &Sls, radius: f64, delta: f64, v: f64, wv: f64) -> (f64, f64, f64) {
    let a = (2.0 * radius * delta).sqrt();
    let dx = 2.0 * a / ROLLING_STEPS as f64;
    let mut q = CoverPoint {
        wv,
        w: sls.k1 / sls.ku * wv,
        t: 0.0,
    };
    let (mut last, mut sum, mut contact) = (0.0, 0.0, 0usize);
    for s in 1..=ROLLING_STEPS {
        let x = -a + s as f64 * dx;
        let g = delta - x * x / (2.0 * radius);
        let (next, pr, _) = sls.step(q, q.t + dx / v, g);
        sum += 0.5 * (last + pr) * dx;
        contact += usize::from(pr > 0.0);
        (q, last) = (next, pr);
    }
    (q.wv, sum, contact as f64 * dx / v)
}

/// Free decay of the internal compression `wv` over `dt` [s] (negative: back in time).
fn decay(sls: &Sls, wv: f64, dt: f64) -> f64 {
    wv * (-dt / sls.tau_sigma).exp()
}

/// Most Steffensen iterations of [`rolling`]'s periodic state.
pub const ROLLING_ITERATIONS: usize = 200;

/// The steady internal compression [m] at the band's entry, rolling at surface speed `v` with
/// period `period` past `delta`: the fixed point of pass + free recovery, by Steffensen's method.
fn steady_entry(sls: &Sls, radius: f64, delta: f64, v: f64, period: f64) -> Option<f64> {
    let free = period - 2.0 * (2.0 * radius * delta).sqrt() / v;
    let map = |wv: f64| decay(sls, pass(sls, radius, delta, v, wv).0, free);
    let mut e = 0.0;
    for _ in 0..ROLLING_ITERATIONS {
        let e1 = map(e);
        if (e1 - e).abs() <= 1e-13 * delta {
            return Some(e1);
        }
        let e2 = map(e1);
        let d = e2 - 2.0 * e1 + e;
        e = if d.abs() > 1e-300 {
            e - (e1 - e) * (e1 - e) / d
        } else {
            e2
        };
    }
    None
}

/// The steady rolling of the cover `c` at `speed_hz` [Hz] (revolutions of the covered roll) past
/// the penetration `delta` [m] and its linearisation (module doc): `None` when `delta` or
/// `speed_hz` ≤ 0 or the periodic state is not reached within [`ROLLING_ITERATIONS`].
pub fn rolling(c: &CoverSpec, delta: f64, speed_hz: f64) -> Option<Rolling> {
    if !(delta > 0.0 && speed_hz > 0.0) {
        return None;
    }
    let sls = Sls::new(c);
    let v = 2.0 * PI * c.cover_radius * speed_hz;
    let period = 1.0 / speed_hz;
    let half = |d: f64| (2.0 * c.radius * d).sqrt();
    let a = half(delta);
    let entry = steady_entry(&sls, c.radius, delta, v, period)?;
    let (_, force, contact) = pass(&sls, c.radius, delta, v, entry);
    // A step Δδ held for a revolution: every point in the band entered after it with the
    // steady history; the band edge moves with δ, so the point's free decay to the new edge
    // is shifted by (a − a')/v. Central difference.
    let d = 1e-5 * delta;
    let shifted = |dd: f64| {
        let a2 = half(delta + dd);
        pass(
            &sls,
            c.radius,
            delta + dd,
            v,
            decay(&sls, entry, (a - a2) / v),
        )
    };
    let (up_exit, up, _) = shifted(d);
    let (_, down, _) = shifted(-d);
    let stiffness = (up - down) / (2.0 * d);
    // One revolution later, back at δ: the points of the raised pass come in with their dent
    // (free from the exit at a' to the entry at −a: T − (a + a')/v).
    let a_up = half(delta + d);
    let back = decay(&sls, up_exit, period - (a + a_up) / v);
    let (_, after, _) = pass(&sls, c.radius, delta, v, back);
    let overlap = -(after - force) / (stiffness * d);
    Some(Rolling {
        force_n_per_m: force,
        stiffness_n_per_m2: stiffness,
        overlap,
        dwell_s: 2.0 * a / v,
        contact_s: contact,
    })
}
