//! The dynamic response of a viscoelastic cover rolling through a nip, with its memory of every
//! earlier revolution: the force per length of nip that answers a penetration change Δδ e^{λt}
//! about the steady rolling state.
//!
//! In: the cover (`CoverSpec`: the Winkler moduli k_r, k_u [N/m³], the relaxation time τ [s],
//! the covered roll's outer radius R_c [m]), its steady rolling state at the held penetration
//! ([`Rolling`], `dynamics/cover.rs`: the time D [s] a point is in contact), the covered roll's
//! revolution frequency f_c [Hz] and a complex rate λ [1/s]. Out: H(λ) [N/m²]: ΔF/L = H(λ) Δδ.
//!
//! Method: every point of the cover follows the same steady path shifted in time: in contact
//! for D (from where the overlap exceeds its dent to where it lifts off), free for T − D
//! (T = 1/f_c). A change Δδ of the penetration changes every contact point's surface
//! compression by Δδ (the overlap is δ − x²/2R); at the ends of the contact the pressure is zero
//! and the internal state's rate is the same in and out of contact, so the ends' shift adds
//! nothing to first order. With Δδ = e^{λt}, a point that entered at t_e with the internal
//! perturbation Δw_v = c e^{λt_e} has, at age s in contact,
//! Δw_v = e^{λt_e} [c e^{−s/τ} + (e^{λs} − e^{−s/τ})/(1 + λτ)], and its pressure change is
//! Δp = k_u Δδ − k_1 Δw_v (k_1 = k_u − k_r). Free, Δw_v decays with τ_σ = τ k_u/k_r; coming back
//! one revolution later the point must enter with c e^{λ(t_e + T)}, which fixes
//! c = ρ' (e^{λD} − e^{−D/τ}) / ((1 + λτ)(e^{λT} − ρ)), ρ' = e^{−(T − D)/τ_σ},
//! ρ = e^{−D/τ} ρ' (the geometric series of all earlier revolutions). Integrating Δp over the
//! contact arc v D (v = 2π R_c f_c, the points at ages 0…D):
//! H(λ) = v [D E*(λ) + k_1 B(λ) (1/(1 + λτ) − c)], E*(λ) = k_u − k_1/(1 + λτ) the SLS complex
//! modulus, B(λ) = (1 − e^{−(λ + 1/τ)D})/(λ + 1/τ). The quasi-static k_c (1 − μ e^{−λT}) of
//! `linear/barring.rs` (a step held for a revolution, and the revolution after it) leaves out
//! the cover's response within the contact at the vibration frequency (λD of order 1 for a
//! roll's mode on its cover) and the deeper revolutions; the barring map roots the
//! characteristic equation with this H instead (`linear/barring_machine.rs`).

use nalgebra::Complex;

use super::cover::Rolling;
use crate::scene::CoverSpec;

/// H(λ) [N/m²] of the cover `c` rolling at `speed_hz` (the covered roll's revolutions [Hz]) in
/// the steady state `r` (module doc).
pub fn response(c: &CoverSpec, r: &Rolling, speed_hz: f64, lambda: Complex<f64>) -> Complex<f64> {
    let (ku, k1, tau) = (c.unrelaxed, c.unrelaxed - c.relaxed, c.relaxation_time);
    let tau_sigma = tau * c.unrelaxed / c.relaxed;
    let period = 1.0 / speed_hz;
    let d = r.contact_s;
    let v = 2.0 * std::f64::consts::PI * c.cover_radius * speed_hz;
    let one = Complex::new(1.0, 0.0);
    let lt = one + lambda * tau;
    let rho_free = (-(period - d) / tau_sigma).exp();
    let rho = (-d / tau).exp() * rho_free;
    let entry =
        rho_free * ((lambda * d).exp() - (-d / tau).exp()) / (lt * ((lambda * period).exp() - rho));
    let s = lambda + 1.0 / tau;
    let b = if s.norm() * d > 1e-8 {
        (one - (-s * d).exp()) / s
    } else {
        Complex::new(d, 0.0) * (one - s * d * 0.5)
    };
    let modulus = ku - k1 / lt;
    v * (modulus * d + k1 * b * (one / lt - entry))
}
