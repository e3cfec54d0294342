//! The supports of a scene: each `[[supports]]` table → a [`SupportModel`] in SI.
//!
//! In: a support's table as written (stiffness in N/m, damping in Ns/m, masses in kg, diameters
//! in mm, roundness amplitudes in µm, contact k in N/mm^e, its damping in Ns/mm, its depth in
//! µm). Out: a linear support (spring–dampers, optionally speed-dependent and through a support
//! mass) or a journal on rollers on a stand, in N/m, Ns/m, kg, m, N/m^e, rad; or an
//! [`InputError`] at the key. Method: each value checked where it is read; a rollers support
//! takes the roll's journal diameter unless it gives its own.

use std::f64::consts::PI;

use super::check::Check;
use super::file::*;
use super::types::{
    ContactLaw, Harmonic, LinearSupport, Roller, RollerPhase, RollerSupport, SpringDamper, Stand,
    SupportModel,
};
use crate::error::InputError;

fn spring(c: &Check, key: &str, s: &SpringFile) -> Result<SpringDamper, InputError> {
    Ok(SpringDamper {
        kx: c.non_negative(&format!("{key}.kx_n_per_m"), s.kx_n_per_m)?,
        ky: c.non_negative(&format!("{key}.ky_n_per_m"), s.ky_n_per_m)?,
        kxy: c.finite(&format!("{key}.kxy_n_per_m"), s.kxy_n_per_m)?,
        kyx: c.finite(&format!("{key}.kyx_n_per_m"), s.kyx_n_per_m)?,
        cx: c.non_negative(&format!("{key}.cx_ns_per_m"), s.cx_ns_per_m)?,
        cy: c.non_negative(&format!("{key}.cy_ns_per_m"), s.cy_ns_per_m)?,
        cxy: c.finite(&format!("{key}.cxy_ns_per_m"), s.cxy_ns_per_m)?,
        cyx: c.finite(&format!("{key}.cyx_ns_per_m"), s.cyx_ns_per_m)?,
    })
}

fn harmonics(c: &Check, key: &str, list: &[HarmonicFile]) -> Result<Vec<Harmonic>, InputError> {
    list.iter()
        .enumerate()
        .map(|(i, h)| {
            let k = format!("{key}[{i}]");
            Ok(Harmonic {
                order: c.count(&format!("{k}.order"), h.order as usize, 1, 256)? as u32,
                amplitude: 1e-6 * c.non_negative(&format!("{k}.amplitude_um"), h.amplitude_um)?,
                phase: c.finite(&format!("{k}.phase_rad"), h.phase_rad)?,
            })
        })
        .collect()
}

pub(super) fn support_model(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll_journal: Option<f64>,
) -> Result<SupportModel, InputError> {
    match s.kind.as_str() {
        "linear" => {
            let spring_f = s
                .spring
                .as_ref()
                .ok_or_else(|| c.err(key, "a linear support needs a `spring` table"))?;
            let spring_v = spring(c, &format!("{key}.spring"), spring_f)?;
            let mass = match (&s.mass_kg, &s.ground) {
                (Some(m), Some(g)) => Some((
                    c.positive(&format!("{key}.mass_kg"), *m)?,
                    spring(c, &format!("{key}.ground"), g)?,
                )),
                (None, None) => None,
                _ => {
                    return Err(c.err(
                        key,
                        "a support mass needs both `mass_kg` and a `ground` spring table",
                    ))
                }
            };
            let mut by_speed = Vec::new();
            for (i, sp) in s.spring_by_speed.iter().enumerate() {
                let k = format!("{key}.spring_by_speed[{i}]");
                let hz = c.non_negative(&format!("{k}.hz"), sp.hz)?;
                if by_speed.last().is_some_and(|(w, _)| 2.0 * PI * hz <= *w) {
                    return Err(c.err(&format!("{k}.hz"), "speeds must ascend"));
                }
                by_speed.push((2.0 * PI * hz, spring(c, &k, &sp.spring)?));
            }
            Ok(SupportModel::Linear(LinearSupport {
                spring: spring_v,
                by_speed,
                mass,
            }))
        }
        "rollers" => {
            let need = |what: &str| c.err(key, format!("a rollers support needs `{what}`"));
            let stand = s.stand.as_ref().ok_or_else(|| need("stand"))?;
            let contact = s.contact.as_ref().ok_or_else(|| need("contact"))?;
            if s.rollers.is_empty() {
                return Err(need("rollers"));
            }
            let ck = format!("{key}.contact");
            let e = c.range(&format!("{ck}.exponent"), contact.exponent, 1.0, 3.0)?;
            let k_mm = c.positive(&format!("{ck}.k_n_per_mm_e"), contact.k_n_per_mm_e)?;
            let journal_diameter = match (s.journal_diameter_mm, roll_journal) {
                (Some(d), _) => 1e-3 * c.positive(&format!("{key}.journal_diameter_mm"), d)?,
                (None, Some(d)) => d,
                (None, None) => return Err(need("journal_diameter_mm")),
            };
            let mut rollers = Vec::new();
            for (i, r) in s.rollers.iter().enumerate() {
                let rk = format!("{key}.rollers[{i}]");
                if s.rollers[..i].iter().any(|o| o.name == r.name) {
                    return Err(c.err(
                        &format!("{rk}.name"),
                        format!("roller name `{}` is used twice in this support", r.name),
                    ));
                }
                rollers.push(Roller {
                    name: r.name.clone(),
                    angle: c.range(&format!("{rk}.angle_deg"), r.angle_deg, -89.0, 89.0)? * PI
                        / 180.0,
                    diameter: 1e-3 * c.positive(&format!("{rk}.diameter_mm"), r.diameter_mm)?,
                    roundness: harmonics(c, &format!("{rk}.roundness"), &r.roundness)?,
                });
            }
            Ok(SupportModel::Rollers(RollerSupport {
                journal_diameter,
                journal_roundness: harmonics(
                    c,
                    &format!("{key}.journal_roundness"),
                    &s.journal_roundness,
                )?,
                rollers,
                roller_phase: match s.roller_phase.as_deref().unwrap_or("roll-angle") {
                    "roll-angle" => RollerPhase::RollAngle,
                    "roller-angle" => RollerPhase::RollerAngle,
                    other => {
                        return Err(c.err(
                            &format!("{key}.roller_phase"),
                            format!("`{other}`: expected roll-angle or roller-angle"),
                        ))
                    }
                },
                contact: ContactLaw {
                    // N/mm^e → N/m^e: F = k (1000 δ)^e.
                    k: k_mm * 1000f64.powf(e),
                    exponent: e,
                    c_max: 1e3
                        * c.non_negative(
                            &format!("{ck}.c_max_ns_per_mm"),
                            contact.c_max_ns_per_mm,
                        )?,
                    d: 1e-6 * c.positive(&format!("{ck}.d_um"), contact.d_um)?,
                },
                stand: Stand {
                    mass: c.positive(&format!("{key}.stand.mass_kg"), stand.mass_kg)?,
                    spring: SpringDamper {
                        kx: c.positive(&format!("{key}.stand.kx_n_per_m"), stand.kx_n_per_m)?,
                        ky: c.positive(&format!("{key}.stand.ky_n_per_m"), stand.ky_n_per_m)?,
                        cx: c
                            .non_negative(&format!("{key}.stand.cx_ns_per_m"), stand.cx_ns_per_m)?,
                        cy: c
                            .non_negative(&format!("{key}.stand.cy_ns_per_m"), stand.cy_ns_per_m)?,
                        ..SpringDamper::default()
                    },
                },
            }))
        }
        other => Err(c.err(
            &format!("{key}.type"),
            format!("`{other}`: expected `linear` or `rollers`"),
        )),
    }
}
