//! Several reduced rolls in one system, coupled by their nips, and one simulation of it.
//!
//! In: a [`Machine`] (every roll's scene, position, arm force; the nips) and the first roll's
//! [`Model`] (the others are built here from their scenes). Out: a [`JobResult`] as for one
//! roll: each roll's channels named with the roll's name before the sensor, node or mode
//! (`runout/<roll>.<sensor>/vertical`, `journal/<roll>.<node>/x`, `speed/<roll>.hz`), and per
//! nip the fields `nips/<nip>/force` [N] and, for a law with a band, `nips/<nip>/width` [mm],
//! each [segments × time] along the axis `z_mm` of the segment centres.
//!
//! Method: q = (q of roll 1, q of roll 2, …), each roll's [`RollSystem`] as for a one-roll
//! scene (its own speed, supports, gravity), M block-diagonal; the force adds the loading arms'
//! and the nips' line loads' inertial forces Φ_jᵀ R(θ)ᵀ F(t) at the roll's support nodes, the
//! webs' line loads q(t) [N/m] over their ranges as Φ_wᵀ R(θ)ᵀ q(t) (Φ_w the lateral rows
//! integrated with the linear shape functions of each element over the range), both in time
//! as the scene's `LoadHistory` (constant, harmonic, table; the static equilibrium under their
//! steady parts), and the nips' segment forces ([`super::nip`], with the rolls' runout in a
//! run, not in the static equilibrium); the Newton matrix adds each segment's
//! Jᵀ[(b k + c c_d) J + b c_d J̃]. The run starts from the static equilibrium of the machine at
//! standstill (each roll's own equilibrium, then Newton on the coupled force, open segments
//! given the stiffness of a 1 µm penetration in the matrix only), or from rest at q = 0 when
//! the first roll's scene says `static_start = false`; the spin then jumps to speed with every
//! roll's deflected shape at rest in space. Roller lift-off events are each roll's; a nip's
//! segments open and close inside the steps.

use nalgebra::{DMatrix, DVector, Matrix2};

use super::job::{failed, hermite, start, Field, JobResult, Recorder};
use super::model::Model;
use super::nip::{band_width, law_force, NipSys, RollView, SegmentState};
use super::system::RollSystem;
use crate::integrators::{integrate, SecondOrder, StepView};
use crate::numerics::newton;
use crate::rotor::fe::NDOF;
use crate::scene::{LoadHistory, Machine, NipLaw};

/// A roll of the coupled system: its system, where its coordinates start, and the inertial
/// forces on it (arms, nips' line loads, webs).
struct Body {
    sys: RollSystem,
    offset: usize,
    loads: Vec<Load>,
}

/// An inertial load on a roll: the lateral rows (2 × nm) it acts through (a node's rows, or a
/// web's rows integrated over its range [m]), the load in time, and constant parts taken off
/// it in order (the nips' line loads on roll_b's support nodes).
struct Load {
    rows: DMatrix<f64>,
    history: LoadHistory,
    less: Vec<[f64; 2]>,
}

impl Load {
    /// The load at time `t` [s], or its steady part (`None`: the static equilibrium).
    fn at(&self, t: Option<f64>) -> [f64; 2] {
        let mut f = match t {
            Some(t) => self.history.at(t),
            None => self.history.steady,
        };
        for s in &self.less {
            f[0] -= s[0];
            f[1] -= s[1];
        }
        f
    }
}

/// The lateral rows (2 × nm) of a unit line load over [z0, z1] [m]: per FE element the load
/// on its overlap shared between its two nodes by the linear shape functions, ∫(1 − s) dz and
/// ∫s dz (the nips' interpolation, `rows_at`); rows × line load [N/m] is the generalized force.
fn line_rows(model: &Model, (z0, z1): (f64, f64)) -> DMatrix<f64> {
    let nz = &model.rotor.node_z;
    let phi = &model.reduced.phi;
    let mut rows = DMatrix::zeros(2, phi.ncols());
    for i in 0..nz.len().saturating_sub(1) {
        let (za, zb) = (nz[i], nz[i + 1]);
        let (a, b) = (z0.max(za), z1.min(zb));
        if b <= a || zb <= za {
            continue;
        }
        let upper = ((b - za).powi(2) - (a - za).powi(2)) / (2.0 * (zb - za));
        rows += (b - a - upper) * phi.rows(NDOF * i, 2) + upper * phi.rows(NDOF * (i + 1), 2);
    }
    rows
}

/// The coupled system (module doc).
pub struct MachineSystem {
    bodies: Vec<Body>,
    nips: Vec<NipSys>,
    n: usize,
    m: DMatrix<f64>,
    weights: Vec<f64>,
}

type States = Vec<(f64, f64, f64)>;

impl MachineSystem {
    /// The system of `machine` on its rolls' models.
    pub fn new(machine: &Machine, models: &[Model]) -> Self {
        let mut bodies: Vec<Body> = Vec::new();
        let mut offset = 0;
        for (roll, model) in machine.rolls.iter().zip(models) {
            let sys = RollSystem::new(&roll.scene, model);
            let rows = |node: &str| {
                model
                    .reduced
                    .node_rows(model.rotor.named[node])
                    .rows(0, 2)
                    .into_owned()
            };
            let loads = roll
                .scene
                .supports
                .iter()
                .map(|s| Load {
                    rows: rows(&s.node),
                    history: roll.arm.clone(),
                    less: Vec::new(),
                })
                .collect();
            let n = sys.n;
            bodies.push(Body { sys, offset, loads });
            offset += n;
        }
        for nip in &machine.nips {
            let b = &mut bodies[nip.rolls.1];
            let share = nip.line_load * (nip.z.len() as f64 * nip.segment_length)
                / b.loads.len().max(1) as f64;
            for l in &mut b.loads {
                l.less.push([share * nip.normal[0], share * nip.normal[1]]);
            }
        }
        for web in &machine.webs {
            bodies[web.roll].loads.push(Load {
                rows: line_rows(&models[web.roll], web.z),
                history: web.load.clone(),
                less: Vec::new(),
            });
        }
        let nips = machine
            .nips
            .iter()
            .map(|n| NipSys::new(n, &models[n.rolls.0], &models[n.rolls.1]))
            .collect();
        let mut m = DMatrix::zeros(offset, offset);
        let mut weights = Vec::with_capacity(offset);
        for b in &bodies {
            m.view_mut((b.offset, b.offset), (b.sys.n, b.sys.n))
                .copy_from(b.sys.mass());
            weights.extend_from_slice(&b.sys.weights);
        }
        Self {
            bodies,
            nips,
            n: offset,
            m,
            weights,
        }
    }

    fn states(&self, t: f64) -> States {
        self.bodies.iter().map(|b| b.sys.speed.at(t)).collect()
    }

    fn part(&self, i: usize, x: &DVector<f64>) -> DVector<f64> {
        let b = &self.bodies[i];
        x.rows(b.offset, b.sys.n).into_owned()
    }

    fn view<'a>(
        &self,
        i: usize,
        st: &States,
        q: &'a DVector<f64>,
        v: &'a DVector<f64>,
    ) -> RollView<'a> {
        let b = &self.bodies[i];
        let (s, c) = st[i].0.sin_cos();
        let r = b.offset..b.offset + b.sys.nm;
        RollView {
            rot: Matrix2::new(c, -s, s, c),
            omega: st[i].1,
            p: &q.as_slice()[r.clone()],
            pd: &v.as_slice()[r],
        }
    }

    /// Every nip's segment states at time `t` [s], with the rolls' runout in a run (`runout`;
    /// not in the static equilibrium and the linearisation, which hold round rolls).
    fn segments(
        &self,
        (t, runout): (f64, bool),
        st: &States,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> Vec<Vec<SegmentState>> {
        self.nips
            .iter()
            .map(|n| {
                let (a, b) = n.nip.rolls;
                n.segments(t, &self.view(a, st, q, v), &self.view(b, st, q, v), runout)
            })
            .collect()
    }

    /// Sets the viscoelastic covers' points at the start state `q` (time 0).
    fn start_covers(&mut self, q: &DVector<f64>) {
        let st = self.states(0.0);
        let v = DVector::zeros(self.n);
        let views: Vec<(Matrix2<f64>, f64, std::ops::Range<usize>)> = (0..self.bodies.len())
            .map(|i| {
                let r = self.view(i, &st, q, &v);
                let b = &self.bodies[i];
                (r.rot, r.omega, b.offset..b.offset + b.sys.nm)
            })
            .collect();
        let view = |i: usize| RollView {
            rot: views[i].0,
            omega: views[i].1,
            p: &q.as_slice()[views[i].2.clone()],
            pd: &v.as_slice()[views[i].2.clone()],
        };
        for nip in &mut self.nips {
            let (a, b) = nip.nip.rolls;
            nip.start_covers(0.0, &view(a), &view(b));
        }
    }

    /// Carries the viscoelastic covers' points to the accepted step's end.
    fn commit(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        let st = self.states(t);
        for n in &self.nips {
            let (a, b) = n.nip.rolls;
            n.commit(t, &self.view(a, &st, q, v), &self.view(b, &st, q, v));
        }
    }

    /// The force at time `t` with the loads at `load_t` (`None`: their steady parts).
    fn force_with(
        &self,
        (t, load_t): (f64, Option<f64>),
        st: &States,
        q: &DVector<f64>,
        v: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        for (i, b) in self.bodies.iter().enumerate() {
            let mut f = DVector::zeros(b.sys.n);
            b.sys
                .force_at(st[i], &self.part(i, q), &self.part(i, v), &mut f);
            let (s, c) = st[i].0.sin_cos();
            let rt = Matrix2::new(c, s, -s, c);
            for load in &b.loads {
                let (rows, force) = (&load.rows, load.at(load_t));
                let fb = rt * nalgebra::Vector2::new(force[0], force[1]);
                for j in 0..b.sys.nm {
                    f[j] += rows[(0, j)] * fb.x + rows[(1, j)] * fb.y;
                }
            }
            out.rows_mut(b.offset, b.sys.n).copy_from(&f);
        }
        let runout = load_t.is_some();
        for (nip, seg) in self.nips.iter().zip(self.segments((t, runout), st, q, v)) {
            let (a, b) = nip.nip.rolls;
            let ra = self.view(a, st, q, v).rot;
            let rb = self.view(b, st, q, v).rot;
            let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
            let mut fa = vec![0.0; ba.sys.nm];
            let mut fb = vec![0.0; bb.sys.nm];
            nip.add_forces(&seg, (&ra, &rb), &mut fa, &mut fb);
            for (k, f) in fa.iter().enumerate() {
                out[ba.offset + k] += f;
            }
            for (k, f) in fb.iter().enumerate() {
                out[bb.offset + k] += f;
            }
        }
    }

    /// The Newton matrix at time `t`, with the runout in a run (`runout`), open segments
    /// given a small stiffness with `floor` (the static equilibrium).
    fn newton_with(
        &self,
        (t, runout, st): (f64, bool, &States),
        q: &DVector<f64>,
        v: &DVector<f64>,
        (a, b, c): (f64, f64, f64),
        floor: bool,
        out: &mut DMatrix<f64>,
    ) {
        out.fill(0.0);
        for (i, body) in self.bodies.iter().enumerate() {
            let mut m = DMatrix::zeros(body.sys.n, body.sys.n);
            body.sys
                .newton_matrix_at(st[i], &self.part(i, q), &self.part(i, v), (a, b, c), &mut m);
            out.view_mut((body.offset, body.offset), (body.sys.n, body.sys.n))
                .copy_from(&m);
        }
        for (nip, seg) in self.nips.iter().zip(self.segments((t, runout), st, q, v)) {
            let (ia, ib) = nip.nip.rolls;
            let (va, vb) = (self.view(ia, st, q, v), self.view(ib, st, q, v));
            let offs = (self.bodies[ia].offset, self.bodies[ib].offset, self.n);
            let open = law_force(&nip.nip.law, nip.nip.segment_length, 1e-6).1 * 1e-3;
            for (j, s) in seg.iter().enumerate() {
                let k = if floor && s.stiffness == 0.0 {
                    open
                } else {
                    s.stiffness
                };
                if k == 0.0 && s.damping == 0.0 {
                    continue;
                }
                let (row, rate) = nip.jacobian_rows(j, &va, &vb, offs);
                let inner = (b * k + c * s.damping) * &row + (b * s.damping) * rate;
                out.ger(1.0, &row, &inner, 1.0);
            }
        }
    }

    /// Static equilibrium at standstill from `q0` (module doc).
    fn static_equilibrium(&self, q0: DVector<f64>) -> Result<DVector<f64>, String> {
        self.equilibrium(q0, "static equilibrium of the machine", |_, _, _| {})
    }

    /// Newton's method at standstill from `q0` on the residual and matrix of the scene's laws
    /// with `change(q, f, jac)` applied to them; `what` names the problem in the errors.
    fn equilibrium(
        &self,
        q0: DVector<f64>,
        what: &str,
        mut change: impl FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
    ) -> Result<DVector<f64>, String> {
        let v = DVector::zeros(self.n);
        let st = vec![(0.0, 0.0, 0.0); self.bodies.len()];
        let eval = |q: &DVector<f64>, f: &mut DVector<f64>, jac: &mut DMatrix<f64>| {
            self.force_with((0.0, None), &st, q, &v, f);
            self.newton_with((0.0, false, &st), q, &v, (0.0, 1.0, 0.0), true, jac);
            change(q, f, jac);
        };
        newton::solve(q0, &self.weights, eval, what, "is every roll supported?")
    }
}

impl SecondOrder for MachineSystem {
    fn n(&self) -> usize {
        self.n
    }

    fn mass(&self) -> &DMatrix<f64> {
        &self.m
    }

    fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.force_with((t, Some(t)), &self.states(t), q, v, out);
    }

    fn newton_matrix(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        coef: (f64, f64, f64),
        out: &mut DMatrix<f64>,
    ) {
        self.newton_with((t, true, &self.states(t)), q, v, coef, false, out);
    }

    fn weights(&self) -> &[f64] {
        &self.weights
    }

    fn linear_in_state(&self) -> bool {
        self.bodies.iter().all(|b| b.sys.linear_in_state())
            && self
                .nips
                .iter()
                .all(|n| matches!(n.nip.law, NipLaw::Linear { .. }))
    }

    fn n_events(&self) -> usize {
        self.bodies.iter().map(|b| b.sys.n_events()).sum()
    }

    fn events(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut [f64]) {
        let mut at = 0;
        for (i, b) in self.bodies.iter().enumerate() {
            let k = b.sys.n_events();
            b.sys
                .events(t, &self.part(i, q), &self.part(i, v), &mut out[at..at + k]);
            at += k;
        }
    }
}

/// `name` with the roll's name before its second part: `runout/centre/vertical` →
/// `runout/<roll>.centre/vertical`.
fn rename(name: &str, roll: &str) -> String {
    match name.split_once('/') {
        Some((head, rest)) => format!("{head}/{roll}.{rest}"),
        None => format!("{roll}.{name}"),
    }
}

/// Every roll's model: `first` for the first roll, the others built from their scenes (their
/// own mode selections); an error names the roll.
pub fn models(machine: &Machine, first: &Model) -> Result<Vec<Model>, String> {
    let mut models = vec![first.clone()];
    for roll in &machine.rolls[1..] {
        models.push(
            Model::build(&roll.scene, None).map_err(|e| format!("roll `{}`: {e}", roll.name))?,
        );
    }
    Ok(models)
}

impl MachineSystem {
    /// The state a run starts from (module doc): with `statics`, each roll's own static start
    /// and then the machine's static equilibrium at standstill; without, rest at q = 0.
    pub fn initial(
        &self,
        machine: &Machine,
        models: &[Model],
        statics: bool,
    ) -> Result<DVector<f64>, String> {
        let mut q0 = DVector::zeros(self.n);
        if !statics {
            return Ok(q0);
        }
        for (roll, (b, model)) in machine.rolls.iter().zip(self.bodies.iter().zip(models)) {
            let q = start(&roll.scene, model, &b.sys)
                .map_err(|e| format!("roll `{}`: {e}", roll.name))?;
            q0.rows_mut(b.offset, b.sys.n).copy_from(&q);
        }
        self.static_equilibrium(q0)
    }

    /// Nip `k`'s segment rows J (each of length n: δ_j = J_j q − gap) at rest, roll angles 0.
    pub fn nip_rows_at_rest(&self, k: usize, q: &DVector<f64>) -> Vec<DVector<f64>> {
        let v = DVector::zeros(self.n);
        let st = vec![(0.0, 0.0, 0.0); self.bodies.len()];
        let nip = &self.nips[k];
        let (ia, ib) = nip.nip.rolls;
        let (va, vb) = (self.view(ia, &st, q, &v), self.view(ib, &st, q, &v));
        let offs = (self.bodies[ia].offset, self.bodies[ib].offset, self.n);
        (0..nip.nip.z.len())
            .map(|j| nip.jacobian_rows(j, &va, &vb, offs).0)
            .collect()
    }

    /// The static equilibrium at standstill from `q0` with nip `k`'s segments following
    /// `law(j, δ)` → (F [N], dF/dδ [N/m]) instead of the scene's law (the barring map's
    /// steady rolling cover, `linear/barring_machine.rs`): Newton on f(q) + Σ_j J_j (F_j − F'_j)
    /// with the matrix K + Σ_j J_jᵀ J_j (k'_j − k_j), F_j, k_j the scene law's (zero for an open
    /// segment), F'_j, k'_j the law's. An error of the law (its first) or of Newton's method.
    pub fn equilibrium_with(
        &self,
        q0: DVector<f64>,
        k: usize,
        law: impl Fn(usize, f64) -> Result<(f64, f64), String>,
    ) -> Result<DVector<f64>, String> {
        let v = DVector::zeros(self.n);
        let st = vec![(0.0, 0.0, 0.0); self.bodies.len()];
        let mut failure: Option<String> = None;
        let change = |q: &DVector<f64>, f: &mut DVector<f64>, jac: &mut DMatrix<f64>| {
            let seg = &self.segments((0.0, false), &st, q, &v)[k];
            for (j, (s, row)) in seg.iter().zip(self.nip_rows_at_rest(k, q)).enumerate() {
                let (force, stiffness) = match law(j, s.delta) {
                    Ok(x) => x,
                    Err(e) => {
                        failure.get_or_insert(e);
                        (s.force, s.stiffness)
                    }
                };
                f.axpy(s.force - force, &row, 1.0);
                jac.ger(stiffness - s.stiffness, &row, &row, 1.0);
            }
        };
        let q = self.equilibrium(
            q0,
            "static equilibrium of the machine with the rolling nip",
            change,
        );
        match failure {
            Some(e) => Err(e),
            None => q,
        }
    }

    /// Number of coordinates.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Per roll, where its coordinates start and its number of modal coordinates (the first of
    /// its block).
    pub fn blocks(&self) -> Vec<(usize, usize)> {
        self.bodies.iter().map(|b| (b.offset, b.sys.nm)).collect()
    }

    /// The system linearised at rest (standstill, roll angles 0) about `q`: M, the tangent
    /// stiffness K = −∂f/∂q and damping C = −∂f/∂q̇ (supports, modal damping, nips: a closed
    /// segment with its dF/dδ and damping, an open one nothing), and every nip's segment states.
    pub fn at_rest(
        &self,
        q: &DVector<f64>,
    ) -> (
        DMatrix<f64>,
        DMatrix<f64>,
        DMatrix<f64>,
        Vec<Vec<SegmentState>>,
    ) {
        let v = DVector::zeros(self.n);
        let st = vec![(0.0, 0.0, 0.0); self.bodies.len()];
        let mut k = DMatrix::zeros(self.n, self.n);
        let mut c = DMatrix::zeros(self.n, self.n);
        self.newton_with((0.0, false, &st), q, &v, (0.0, 1.0, 0.0), false, &mut k);
        self.newton_with((0.0, false, &st), q, &v, (0.0, 0.0, 1.0), false, &mut c);
        (
            self.m.clone(),
            k,
            c,
            self.segments((0.0, false), &st, q, &v),
        )
    }
}

/// Runs a machine (module doc); `first` is the model of its first roll.
pub fn run(machine: &Machine, first: &Model) -> JobResult {
    let models = match models(machine, first) {
        Ok(m) => m,
        Err(e) => return failed(e, first, 0),
    };
    let mut sys = MachineSystem::new(machine, &models);
    let n = sys.n;
    let scene0 = &machine.rolls[0].scene;
    let q0 = match sys.initial(machine, &models, scene0.simulation.static_start) {
        Ok(q) => q,
        Err(e) => return failed(e, first, n),
    };
    sys.start_covers(&q0);
    let sys = sys;
    let mut v0 = DVector::zeros(n);
    let st0 = sys.states(0.0);
    for (i, b) in sys.bodies.iter().enumerate() {
        let v = b.sys.quiescent_velocity(&sys.part(i, &q0), st0[i].1);
        v0.rows_mut(b.offset, b.sys.n).copy_from(&v);
    }
    let mut recs: Vec<Recorder> = (sys.bodies.iter().zip(&machine.rolls).enumerate())
        .map(|(i, (b, r))| Recorder::new(&b.sys, &r.scene).with_surface(&machine.outer_surface(i)))
        .collect();
    let (settle, dt, t_end) = (recs[0].next, recs[0].dt, recs[0].t_end);
    let mut next = settle;
    let mut samples = 0usize;
    let mut nip_force: Vec<Vec<Vec<f64>>> = sys
        .nips
        .iter()
        .map(|nip| vec![Vec::new(); nip.nip.z.len()])
        .collect();
    let mut nip_width = nip_force.clone();
    let bound = scene0.simulation.runout_bound;
    let mut observer = |s: &StepView| -> Result<(), String> {
        if let Some(x) =
            s.q1.iter()
                .zip(&sys.weights)
                .map(|(q, w)| (q * w).abs())
                .find(|x| *x > bound)
        {
            return Err(format!(
                "a modal displacement of {:.3} mm beyond the bound of {:.3} mm at t = {:.6} s",
                x * 1e3,
                bound * 1e3,
                s.t1
            ));
        }
        while next <= s.t1 + 1e-12 && next <= t_end + 1e-12 {
            let t = next;
            let (q, v) = hermite(s, t);
            for (i, rec) in recs.iter_mut().enumerate() {
                rec.sample(t, &sys.part(i, &q), &sys.part(i, &v));
            }
            let st = sys.states(t);
            for (k, seg) in sys.segments((t, true), &st, &q, &v).iter().enumerate() {
                for (j, sg) in seg.iter().enumerate() {
                    nip_force[k][j].push(sg.force);
                    let w = band_width(&sys.nips[k].nip.law, sg.delta, sg.force);
                    nip_width[k][j].push(1e3 * w.unwrap_or(0.0));
                }
            }
            samples += 1;
            next = settle + samples as f64 * dt;
        }
        sys.commit(s.t1, s.q1, s.v1);
        Ok(())
    };
    let (_, _, stats) = integrate(&sys, &scene0.solver, 0.0, t_end, q0, v0, &mut observer);
    let mut channels = Vec::new();
    let mut lift_off_s = None;
    let time = recs[0].time.clone();
    for (rec, roll) in recs.into_iter().zip(&machine.rolls) {
        lift_off_s = match (lift_off_s, rec.lift_off) {
            (Some(a), Some(b)) => Some(f64::min(a, b)),
            (a, b) => a.or(b),
        };
        for mut c in rec.channels {
            c.name = rename(&c.name, &roll.name);
            channels.push(c);
        }
    }
    let mut fields = Vec::new();
    for ((nip, force), width) in sys.nips.iter().zip(nip_force).zip(nip_width) {
        let z_mm: Vec<f64> = nip.nip.z.iter().map(|z| 1e3 * z).collect();
        let name = &nip.nip.name;
        fields.push(Field {
            name: format!("nips/{name}/force"),
            units: "N",
            axis: "z_mm",
            axis_units: "mm",
            axis_values: z_mm.clone(),
            data: force.concat(),
        });
        if !matches!(nip.nip.law, NipLaw::Linear { .. }) {
            fields.push(Field {
                name: format!("nips/{name}/width"),
                units: "mm",
                axis: "z_mm",
                axis_units: "mm",
                axis_values: z_mm,
                data: width.concat(),
            });
        }
    }
    let modes = models
        .iter()
        .map(|m| m.reduced.counts_label())
        .collect::<Vec<_>>()
        .join(" | ");
    JobResult {
        stats,
        modes,
        coordinates: n,
        time,
        channels,
        lift_off_s,
        fields,
    }
}
