//! Physics references for the tests: uniform tubes of a known steel, eigen-solutions of
//! constrained systems, state matrices, amplitude and slope fits, the damped oscillator with its
//! closed form, and solver settings for small systems. SI units.

use nalgebra::DMatrix;
use rotorsweep::rotor::fe::{Material, RotorSpec, SectionSpec, SegmentSpec};

/// Structural steel of physics.md §10.
pub const STEEL: Material = Material {
    youngs_modulus: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A uniform tube of `length` [m], outer/inner diameter [m], `n` elements, from z = 0.
pub fn tube(length: f64, outer: f64, inner: f64, n: usize) -> RotorSpec {
    RotorSpec {
        z_start: 0.0,
        segments: vec![SegmentSpec {
            length,
            section: SectionSpec::Tube {
                outer,
                inner,
                asymmetry: 0.0,
            },
            elements: n,
            material: STEEL,
        }],
        disks: Vec::new(),
        point_masses: Vec::new(),
        named_points: Vec::new(),
        balancing: None,
    }
}

/// Keeps the rows and columns of `keep`.
pub fn restrict(a: &DMatrix<f64>, keep: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(keep.len(), keep.len(), |i, j| a[(keep[i], keep[j])])
}

/// Natural frequencies [Hz] of K, M restricted to the DOFs not in `fixed`, ascending.
pub fn frequencies(k: &DMatrix<f64>, m: &DMatrix<f64>, fixed: &[usize]) -> Vec<f64> {
    let keep: Vec<usize> = (0..k.nrows()).filter(|i| !fixed.contains(i)).collect();
    let eig = rotorsweep::numerics::eigen::generalized_symmetric(
        &restrict(k, &keep),
        &restrict(m, &keep),
    )
    .expect("eigen-solution");
    eig.values
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// First-order state matrix [[0, I], [−M⁻¹K, −M⁻¹C]].
pub fn state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let minv = m.clone().cholesky().expect("M positive definite").inverse();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-&minv * k));
    a.view_mut((n, n), (n, n)).copy_from(&(-&minv * c));
    a
}

/// Inverse of the state matrix, [[−K⁻¹C, −K⁻¹M], [I, 0]] (K must be non-singular).
pub fn inverse_state_matrix(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    let lu = k.clone().lu();
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, 0), (n, n))
        .copy_from(&(-lu.solve(c).expect("K non-singular")));
    a.view_mut((0, n), (n, n))
        .copy_from(&(-lu.solve(m).expect("K non-singular")));
    a.view_mut((n, 0), (n, n)).fill_with_identity();
    a
}

/// Amplitude of the line at `f` [Hz] in `x` sampled at `fs` [Hz]: mean removed, periodic Hann
/// window, amplitude-correct scaling 2|Σ wₙ xₙ e^{−i2πf n/fs}| / Σ wₙ (physics.md §8). Exact for
/// a line on a bin of the record (record = whole number of its periods); Hann's sidelobes keep
/// the other lines' leakage small otherwise.
pub fn hann_amplitude(x: &[f64], fs: f64, f: f64) -> f64 {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let (mut re, mut im, mut wsum) = (0.0, 0.0, 0.0);
    for (i, xi) in x.iter().enumerate() {
        let w = 0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos());
        let ph = 2.0 * std::f64::consts::PI * f * i as f64 / fs;
        re += w * (xi - mean) * ph.cos();
        im -= w * (xi - mean) * ph.sin();
        wsum += w;
    }
    2.0 * (re * re + im * im).sqrt() / wsum
}

/// Least-squares slope of y against x.
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// The first vertical and horizontal bending frequencies [Hz] of a scene's model on its
/// linearised supports at standstill, as `rotorsweep modes` reports them.
pub fn first_bending_hz(
    scene: &rotorsweep::scene::Scene,
    model: &rotorsweep::dynamics::model::Model,
) -> (f64, f64) {
    use rotorsweep::dynamics::LinearSystem;
    use rotorsweep::rotor::reduction::ModeKind;
    let modes = LinearSystem::of_scene(scene, model)
        .expect("linear supports")
        .standstill_modes()
        .expect("eigen-solution");
    let first = |k: ModeKind| {
        modes
            .iter()
            .find(|m| m.kind == k && m.freq_hz > 1.0)
            .expect("a bending mode")
            .freq_hz
    };
    (first(ModeKind::BendingY), first(ModeKind::BendingX))
}

/// The samples of the channel `name` of a job result.
pub fn channel<'a>(r: &'a rotorsweep::dynamics::simulation::JobResult, name: &str) -> &'a [f64] {
    &r.channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| {
            let names: Vec<&str> = r.channels.iter().map(|c| c.name.as_str()).collect();
            panic!("no channel `{name}` (have: {})", names.join(", "))
        })
        .data
}

/// The damped oscillator m q̈ = −m(ω² q + 2ζω q̇), ω = 2π·10 Hz, ζ = 2 %, of mass `mass` [kg]
/// (a mass other than 1 exercises M⁻¹): a smooth problem with a closed form
/// ([`Oscillator::exact`]), free of a rotor's stiff spectrum, for the integrator tests.
pub struct Oscillator {
    m: nalgebra::DMatrix<f64>,
    mass: f64,
    w: Vec<f64>,
}

impl Oscillator {
    pub const OMEGA: f64 = 2.0 * std::f64::consts::PI * 10.0;
    pub const ZETA: f64 = 0.02;

    pub fn new(mass: f64) -> Self {
        Self {
            m: nalgebra::DMatrix::from_element(1, 1, mass),
            mass,
            w: vec![1.0],
        }
    }

    /// Free decay from q(0) = q0, q̇(0) = 0: q = q0 e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t),
    /// ω_d = ω√(1 − ζ²) (any vibrations text, e.g. Rao, Mechanical Vibrations, §2.6).
    pub fn exact(q0: f64, t: f64) -> f64 {
        let (w, z) = (Self::OMEGA, Self::ZETA);
        let wd = w * (1.0 - z * z).sqrt();
        q0 * (-z * w * t).exp() * ((wd * t).cos() + z * w / wd * (wd * t).sin())
    }
}

impl rotorsweep::integrators::SecondOrder for Oscillator {
    fn n(&self) -> usize {
        1
    }
    fn mass(&self) -> &nalgebra::DMatrix<f64> {
        &self.m
    }
    fn force(
        &self,
        _t: f64,
        q: &nalgebra::DVector<f64>,
        v: &nalgebra::DVector<f64>,
        out: &mut nalgebra::DVector<f64>,
    ) {
        let (w, z) = (Self::OMEGA, Self::ZETA);
        out[0] = -self.mass * (w * w * q[0] + 2.0 * z * w * v[0]);
    }
    fn newton_matrix(
        &self,
        _t: f64,
        _q: &nalgebra::DVector<f64>,
        _v: &nalgebra::DVector<f64>,
        (a, b, c): (f64, f64, f64),
        out: &mut nalgebra::DMatrix<f64>,
    ) {
        let (m, w, z) = (self.mass, Self::OMEGA, Self::ZETA);
        out[(0, 0)] = a * m + b * m * w * w + c * m * 2.0 * z * w;
    }
    fn weights(&self) -> &[f64] {
        &self.w
    }
}

/// Solver settings for the integrator tests on small systems: `integrator` at `tolerance` [m]
/// and `hmax` [s], hmin 1e-12 s, h0 1e-6 s, orders up to 5, ρ∞ 0.8, error-controlled, 10⁶ steps,
/// no CPU budget, no event location.
pub fn solver(
    integrator: rotorsweep::integrators::IntegratorKind,
    tolerance: f64,
    hmax: f64,
) -> rotorsweep::integrators::SolverSettings {
    rotorsweep::integrators::SolverSettings {
        integrator,
        tolerance,
        hmax,
        hmin: 1e-12,
        h0: 1e-6,
        max_order: 5,
        rho_inf: 0.8,
        fixed_step: false,
        max_steps: 1_000_000,
        cpu_budget: None,
        contact_events: false,
    }
}

/// The complex amplitude A e^{iα} of the line A cos(2π f t + α) in `x` sampled at `t` [s], over
/// the samples in [t0, t0 + span) [s] (a whole number of periods of every line here, so the
/// lines are orthogonal).
pub fn line(t: &[f64], x: &[f64], f: f64, (t0, span): (f64, f64)) -> nalgebra::Complex<f64> {
    let (mut sum, mut n) = (nalgebra::Complex::new(0.0, 0.0), 0usize);
    for (ti, xi) in t.iter().zip(x) {
        if *ti >= t0 - 1e-9 && *ti < t0 + span - 1e-9 {
            sum += xi * nalgebra::Complex::from_polar(1.0, -std::f64::consts::TAU * f * ti);
            n += 1;
        }
    }
    2.0 * sum / n as f64
}
