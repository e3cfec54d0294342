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
//!
//! The files, in the order they build on each other: the contact law (`contact.rs`), the
//! supports (`supports.rs`), the system and its construction (`roll_system.rs`), the force
//! (`force.rs`), the Newton matrix (`newton.rs`), the rest states (`statics.rs`), the recorded
//! outputs (`outputs.rs`) and the integrators' view (`second_order.rs`).

mod contact;
mod force;
mod newton;
mod outputs;
mod roll_system;
mod second_order;
mod statics;
mod supports;

pub(crate) use contact::Profile;
pub use roll_system::RollSystem;
pub use supports::SupportState;
