//! The integrators' own parameters: which integrator, its tolerance, step limits, order, budgets.
//!
//! In: values the scene's `[solver]` table gives (validated there; SI: metres for the
//! displacement tolerance, seconds for steps and budgets). Out: [`SolverSettings`], which every
//! integrator of this stage reads; the meaning of each setting is in the module doc of
//! [`integrators`](crate::integrators).

/// Which integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Variable-step, variable-order BDF (1–5).
    Bdf,
    /// Generalized-α (Chung–Hulbert).
    GenAlpha,
    /// Explicit Dormand–Prince 5(4).
    Rk45,
    /// SUNDIALS CVODE's BDF (built with the `cvode` feature only).
    #[cfg(feature = "cvode")]
    Cvode,
}

impl IntegratorKind {
    /// The name used in scene files and results.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Bdf => "bdf",
            Self::GenAlpha => "gen-alpha",
            Self::Rk45 => "rk45",
            #[cfg(feature = "cvode")]
            Self::Cvode => "cvode",
        }
    }
}

/// Solver settings (meaning of each in `integrators`).
#[derive(Debug, Clone, PartialEq)]
pub struct SolverSettings {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Local error tolerance [m] of displacement (see `integrators`).
    pub tolerance: f64,
    /// Largest step [s].
    pub hmax: f64,
    /// Smallest step [s]: below it the run ends `diverged`.
    pub hmin: f64,
    /// First step [s].
    pub h0: f64,
    /// Highest BDF order (1–5).
    pub max_order: usize,
    /// Generalized-α spectral radius at infinity ρ∞ ∈ [0, 1].
    pub rho_inf: f64,
    /// Generalized-α with fixed step h = hmax (no error control).
    pub fixed_step: bool,
    /// Step budget: more accepted + rejected steps end the run with status `budget`.
    pub max_steps: u64,
    /// CPU budget [s].
    pub cpu_budget: Option<f64>,
    /// BDF ends a step at a contact onset or lift-off inside it (`integrators`, contacts).
    pub contact_events: bool,
}
