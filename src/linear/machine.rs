//! The linear analysis of a machine: its rolls coupled by their nips, linearised at the
//! machine's static equilibrium with the nips loaded.
//!
//! In: a [`Machine`] and every roll's [`Model`]; spin speeds [Hz] of the first roll (every roll
//! with a speed of its own turns at that speed, a roll with `surface_speed_of` at its factor
//! −R_other/R_own of it). Out: [`MachineLinear`]: the static equilibrium at standstill (each
//! roll's sensor deflections [m], every nip's segment penetration [m], force [N] and tangent
//! stiffness [N/m]); per speed the damped modes of the coupled rolls ([`CoupledMode`]: damped
//! frequency [Hz], damping ratio, log decrement, whirl, kind, the roll that carries most of the
//! mode's kinetic energy); the stability threshold; crossings of the modes with the first roll's
//! speed; as JSON with the keys of the one-roll `linear` (`speeds_hz`, `modes`,
//! `critical_speeds_hz`, `stability_threshold_hz`, `static`, `frame`, `warnings`) plus `rolls`.
//!
//! Method: the coupled system of the time simulation ([`MachineSystem`], dynamics/bodies.rs) at
//! its static equilibrium under gravity, loading arms and line loads (Newton on the nonlinear
//! supports, rollers and nips), linearised there at standstill: M, the tangent stiffness K and
//! damping C (a closed nip segment adds Jᵀ(dF/dδ)J and Jᵀ c J, J its penetration row). At speed
//! the analysis is in the stationary frame as the one-roll analysis (module doc of
//! [`crate::linear`]): each roll's modal block adds its gyroscopic Ω_i G_s to C, the
//! circulatory −Ω_i skew(D Ŝ) of its rotating modal damping to K and, for a body with stress
//! stiffening, Ω_i² K_σ to K; supports and nips stay as
//! linearised at standstill (a support's `spring_by_speed` table is read at standstill; the
//! nip's kinematic term Ω S Φ of the body frame is absent in the stationary frame). Exact for
//! axisymmetric rolls on speed-independent supports. Eigenvalues of the state matrix
//! [[0, I], [−M⁻¹K, −M⁻¹C]] ([`eigen::general`], bounded); modes with |λ| below
//! [`ZERO_RAD_S`] (free rigid motion) are left out, those with ζ ≥ [`LISTED_ZETA`] not listed.
//! A mode's whirl is that of its dominant roll's node orbits (index as [`super::modes`]).

use nalgebra::{Complex, DMatrix, DVector};
use serde_json::{json, Map, Value};

use super::modes::{whirl_of_orbits, Kind, Whirl, LISTED_ZETA, UNSTABLE_ZETA, ZERO_RAD_S};
use crate::dynamics::bodies::{models, MachineSystem};
use crate::dynamics::linear_system::{lateral_rows, modal_damping, rotation_generator};
use crate::dynamics::model::Model;
use crate::dynamics::nip::SegmentState;
use crate::numerics::eigen;
use crate::scene::Machine;

type C64 = Complex<f64>;

/// The frame and approximation of the coupled analysis, as printed and stored.
pub const MACHINE_FRAME_NOTE: &str = "stationary frame; the coupled rolls linearised at the \
machine's static equilibrium at standstill (supports, rollers and nips loaded); each roll's \
gyroscopic and circulatory terms at its own speed; exact for axisymmetric rolls on \
speed-independent supports";

/// One roll of the coupled linear system.
struct RollPart {
    name: String,
    offset: usize,
    nm: usize,
    factor: f64,
    /// Stationary-frame gyroscopic matrix per rad/s (nm × nm).
    gs: DMatrix<f64>,
    /// Stress stiffening per (rad/s)² (nm × nm), if the roll's body has it.
    ks: Option<DMatrix<f64>>,
    /// skew(D Ŝ) = ½(DŜ − (DŜ)ᵀ) per rad/s (nm × nm).
    skew: DMatrix<f64>,
    /// u_x rows then u_y rows of Φ at every node (2·nodes × nm).
    lateral: DMatrix<f64>,
    family_mass: [DMatrix<f64>; 4],
}

/// One nip at the static equilibrium.
#[derive(Debug, Clone)]
pub struct NipRest {
    /// Its name.
    pub name: String,
    /// Segment centres [m].
    pub z: Vec<f64>,
    /// Every segment's state.
    pub segments: Vec<SegmentState>,
}

/// A mode of the coupled rolls.
#[derive(Debug, Clone)]
pub struct CoupledMode {
    /// Damped frequency [Hz].
    pub freq_hz: f64,
    /// Damping ratio [-].
    pub damping_ratio: f64,
    /// Logarithmic decrement [-].
    pub log_dec: f64,
    /// Whirl of the dominant roll.
    pub whirl: Whirl,
    /// Its amplitude-weighted whirl index in [−1, 1].
    pub whirl_index: f64,
    /// Kind by kinetic energy.
    pub kind: Kind,
    /// The roll with the largest share of the kinetic energy.
    pub roll: String,
    /// That share [-].
    pub share: f64,
}

/// The modes at one speed.
#[derive(Debug, Clone)]
pub struct CoupledSet {
    /// The first roll's speed [Hz].
    pub speed_hz: f64,
    /// Oscillatory modes, ascending in damped frequency.
    pub modes: Vec<CoupledMode>,
    /// Largest Re λ / |λ| (> 0: unstable).
    pub max_growth: f64,
}

/// The linear analysis of a machine (module doc).
pub struct MachineLinear {
    parts: Vec<RollPart>,
    m_inv: DMatrix<f64>,
    k: DMatrix<f64>,
    c: DMatrix<f64>,
    m: DMatrix<f64>,
    /// Each roll's sensors' static deflection (x, y) [m] (roll name, sensor, x, y).
    pub sag: Vec<(String, String, f64, f64)>,
    /// The nips at the static equilibrium.
    pub nips: Vec<NipRest>,
}

impl MachineLinear {
    /// The machine linearised at its static equilibrium (module doc); `first` is the first
    /// roll's model. An error says what could not be solved.
    pub fn new(machine: &Machine, first: &Model) -> Result<Self, String> {
        let mut machine = machine.clone();
        for r in &mut machine.rolls {
            r.scene.simulation.static_start = true;
        }
        let models = models(&machine, first)?;
        let sys = MachineSystem::new(&machine, &models);
        let q = sys.initial(&machine, &models, true)?;
        let (m, k, c, states) = sys.at_rest(&q);
        let m_inv = m
            .clone()
            .lu()
            .try_inverse()
            .ok_or("the machine's mass matrix is singular")?;
        let mut parts = Vec::new();
        let mut sag = Vec::new();
        for ((roll, model), (offset, nm)) in machine.rolls.iter().zip(&models).zip(sys.blocks()) {
            let red = &model.reduced;
            let ds = modal_damping(red, &roll.scene.damping) * rotation_generator(&red.phi);
            let lateral = lateral_rows(&red.phi);
            let p = q.rows(offset, nm);
            for s in &roll.scene.sensors {
                let u = red.node_rows(model.rotor.named[s]).rows(0, 2) * p;
                sag.push((roll.name.clone(), s.clone(), u[0], u[1]));
            }
            parts.push(RollPart {
                name: roll.name.clone(),
                offset,
                nm,
                factor: roll.speed_factor,
                gs: red.gs.clone(),
                ks: red.ks.clone(),
                skew: 0.5 * (&ds - ds.transpose()),
                lateral,
                family_mass: red.family_mass.clone(),
            });
        }
        let nips = machine
            .nips
            .iter()
            .zip(states)
            .map(|(n, segments)| NipRest {
                name: n.name.clone(),
                z: n.z.clone(),
                segments,
            })
            .collect();
        Ok(Self {
            parts,
            m_inv,
            k,
            c,
            m,
            sag,
            nips,
        })
    }

    /// Every roll's name and speed per speed of the first roll.
    pub fn rolls(&self) -> Vec<(String, f64)> {
        let first = self.parts.first().map_or(1.0, |p| p.factor);
        (self.parts.iter())
            .map(|p| (p.name.clone(), p.factor / first))
            .collect()
    }

    /// K(Ω) and C(Ω) with the first roll at `omega` [rad/s] (module doc).
    pub fn at(&self, omega: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let mut k = self.k.clone();
        let mut c = self.c.clone();
        let first = self.parts.first().map_or(1.0, |p| p.factor);
        for p in &self.parts {
            let w = omega * p.factor / first;
            let mut kv = k.view_mut((p.offset, p.offset), (p.nm, p.nm));
            kv -= w * &p.skew;
            if let Some(ks) = &p.ks {
                kv += (w * w) * ks;
            }
            let mut cv = c.view_mut((p.offset, p.offset), (p.nm, p.nm));
            cv += w * &p.gs;
        }
        (k, c)
    }

    /// The damped modes with the first roll at `speed_hz` (module doc).
    pub fn modes(&self, speed_hz: f64) -> Result<CoupledSet, String> {
        let n = self.m.nrows();
        let (k, c) = self.at(2.0 * std::f64::consts::PI * speed_hz);
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        a.view_mut((n, 0), (n, n)).copy_from(&(-&self.m_inv * k));
        a.view_mut((n, n), (n, n)).copy_from(&(-&self.m_inv * c));
        let (values, vectors) =
            eigen::general(&a).map_err(|e| format!("damped modes at {speed_hz} Hz: {e}"))?;
        let mut max_growth = f64::NEG_INFINITY;
        let mut modes = Vec::new();
        for (j, l) in values.iter().enumerate() {
            let lam = C64::new(l.re, l.im);
            if lam.norm() < ZERO_RAD_S {
                continue;
            }
            max_growth = max_growth.max(lam.re / lam.norm());
            if lam.im <= 1e-9 * lam.norm() || -lam.re / lam.norm() >= LISTED_ZETA {
                continue;
            }
            let v = DVector::from_fn(n, |r, _| {
                let z = vectors[(r, j)];
                C64::new(z.re, z.im)
            });
            modes.push(self.mode(lam, &v));
        }
        modes.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
        Ok(CoupledSet {
            speed_hz,
            modes,
            max_growth: if max_growth.is_finite() {
                max_growth
            } else {
                0.0
            },
        })
    }

    fn mode(&self, lam: C64, v: &DVector<C64>) -> CoupledMode {
        let energy = |from: usize, len: usize| -> f64 {
            let mut e = 0.0;
            for r in from..from + len {
                for s in from..from + len {
                    e += self.m[(r, s)] * (v[r].conj() * v[s]).re;
                }
            }
            e
        };
        let shares: Vec<f64> = (0..self.parts.len())
            .map(|i| {
                let end = self.parts.get(i + 1).map_or(self.m.nrows(), |p| p.offset);
                energy(self.parts[i].offset, end - self.parts[i].offset)
            })
            .collect();
        let total: f64 = shares.iter().sum();
        let (top, _) =
            shares.iter().enumerate().fold(
                (0, f64::MIN),
                |b, (i, e)| if *e > b.1 { (i, *e) } else { b },
            );
        let part = &self.parts[top];
        let p = v.rows(part.offset, part.nm).into_owned();
        let fam: Vec<f64> = (part.family_mass.iter())
            .map(|fm| {
                let fm = fm.map(|x| C64::new(x, 0.0));
                (p.adjoint() * fm * &p)[0].re
            })
            .collect();
        let modal: f64 = fam.iter().sum();
        let lateral = fam[0] + fam[1] + (shares[top] - modal).max(0.0);
        let kind = if lateral >= fam[2] && lateral >= fam[3] {
            Kind::Lateral
        } else if fam[2] >= fam[3] {
            Kind::Axial
        } else {
            Kind::Torsion
        };
        let (whirl, whirl_index) = whirl(&part.lateral, &p);
        CoupledMode {
            freq_hz: lam.im / (2.0 * std::f64::consts::PI),
            damping_ratio: -lam.re / lam.norm(),
            log_dec: -2.0 * std::f64::consts::PI * lam.re / lam.im,
            whirl: if kind == Kind::Lateral {
                whirl
            } else {
                Whirl::Mixed
            },
            whirl_index,
            kind,
            roll: part.name.clone(),
            share: if total > 0.0 {
                shares[top] / total
            } else {
                1.0
            },
        }
    }

    /// The analysis over `speeds_hz` as JSON (module doc).
    pub fn to_json(&self, scene: &str, speeds_hz: &[f64]) -> Result<Value, String> {
        let sets = speeds_hz
            .iter()
            .map(|s| self.modes(*s))
            .collect::<Result<Vec<_>, _>>()?;
        let modes: Vec<Vec<Value>> = (sets.iter())
            .map(|set| {
                (set.modes.iter())
                    .map(|m| {
                        json!({
                            "freq_hz": m.freq_hz,
                            "damping_ratio": m.damping_ratio,
                            "log_dec": m.log_dec,
                            "whirl": m.whirl.to_string(),
                            "kind": m.kind.to_string(),
                            "whirl_index": m.whirl_index,
                            "roll": m.roll,
                            "energy_share": m.share,
                        })
                    })
                    .collect()
            })
            .collect();
        let threshold = sets
            .iter()
            .find(|s| s.max_growth > -UNSTABLE_ZETA)
            .map(|s| s.speed_hz);
        let mut sag = Map::new();
        for (roll, s, x, y) in &self.sag {
            sag.insert(
                format!("{roll}.{s}"),
                json!({"vertical": 1e6 * y, "horizontal": 1e6 * x}),
            );
        }
        let nips: Vec<Value> = (self.nips.iter())
            .map(|n| {
                json!({
                    "name": n.name,
                    "z_mm": n.z.iter().map(|z| 1e3 * z).collect::<Vec<_>>(),
                    "force_n": n.segments.iter().map(|s| s.force).collect::<Vec<_>>(),
                    "penetration_um": n.segments.iter().map(|s| 1e6 * s.delta).collect::<Vec<_>>(),
                    "stiffness_n_per_m": n.segments.iter().map(|s| s.stiffness).collect::<Vec<_>>(),
                    "total_force_n": n.segments.iter().map(|s| s.force).sum::<f64>(),
                })
            })
            .collect();
        let rolls: Vec<Value> = (self.rolls().into_iter())
            .map(|(name, f)| json!({"name": name, "speed_per_first": f}))
            .collect();
        Ok(json!({
            "scene": scene,
            "frame": MACHINE_FRAME_NOTE,
            "speeds_hz": speeds_hz,
            "modes": modes,
            "critical_speeds_hz": crossings(&sets),
            "stability_threshold_hz": threshold,
            "static": {"sag_um": sag, "nips": nips},
            "rolls": rolls,
            "warnings": Vec::<String>::new(),
        }))
    }
}

/// Speeds [Hz] where the k-th lowest lateral mode's frequency crosses the first roll's speed
/// between two speeds of the sweep (linear between them; modes followed by their order), equal
/// ones (within 1e-6) once.
pub fn crossings(sets: &[CoupledSet]) -> Vec<f64> {
    let lateral = |s: &CoupledSet| -> Vec<f64> {
        (s.modes.iter())
            .filter(|m| m.kind == Kind::Lateral)
            .map(|m| m.freq_hz)
            .collect()
    };
    let mut out = Vec::new();
    for w in sets.windows(2) {
        let (a, b) = (lateral(&w[0]), lateral(&w[1]));
        for (fa, fb) in a.iter().zip(&b) {
            let (ga, gb) = (fa - w[0].speed_hz, fb - w[1].speed_hz);
            if ga > 0.0 && gb <= 0.0 {
                let s = ga / (ga - gb);
                out.push(w[0].speed_hz + s * (w[1].speed_hz - w[0].speed_hz));
            }
        }
    }
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() <= 1e-6 * b.abs());
    out
}

/// Whirl label and index of a roll's modal shape `p` from its node orbits.
fn whirl(lateral: &DMatrix<f64>, p: &DVector<C64>) -> (Whirl, f64) {
    let nodes = lateral.nrows() / 2;
    let xy = lateral.map(|x| C64::new(x, 0.0)) * p;
    let x = DMatrix::from_fn(nodes, 1, |r, _| xy[r]);
    let y = DMatrix::from_fn(nodes, 1, |r, _| xy[nodes + r]);
    whirl_of_orbits(&x, &y)
}
