//! The supports of a scene: each `[[supports]]` table → a [`Support`] on a named node, with its
//! [`SupportModel`] in SI.
//!
//! In: a support's table as written (stiffness in N/m, damping in Ns/m, masses in kg, diameters
//! in mm, roundness amplitudes in µm, contact k in N/mm^e, its damping in Ns/mm, its depth in
//! µm), the rotor's named nodes. Out: a linear support (spring–dampers, optionally
//! speed-dependent and through a support mass) or a journal on rollers on a stand, in N/m, Ns/m,
//! kg, m, N/m^e, rad; or an [`InputError`] at the key. Method: each value checked where it is
//! read; at least one support, one per node; a rollers support takes the roll's journal
//! diameter unless it gives its own.

use std::f64::consts::PI;

use super::check::Check;
use super::file::*;
use super::types::{
    ContactLaw, Harmonic, LinearSupport, Roller, RollerPhase, RollerSupport, SpringDamper, Stand,
    Support, SupportModel,
};
use crate::error::InputError;

/// Every `[[supports]]` of `raw`, each on a node the rotor names (`named`), no node twice.
pub(super) fn build_supports(
    c: &Check,
    raw: &SceneFile,
    named: &[&str],
) -> Result<Vec<Support>, InputError> {
    if raw.supports.is_empty() {
        return Err(c.err(
            "supports",
            "a scene needs at least one support ([[supports]]): without supports the rotor falls",
        ));
    }
    let mut supports = Vec::new();
    for (i, s) in raw.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        let node = c.node(&format!("{key}.node"), &s.node, named)?;
        if supports.iter().any(|x: &Support| x.node == node) {
            return Err(c.err(
                &format!("{key}.node"),
                format!("node `{node}` already has a support"),
            ));
        }
        let model = support_model(c, &key, s, roll_journal(raw))?;
        supports.push(Support { node, model });
    }
    Ok(supports)
}

/// The journal diameter [m] of the scene's roll, if it is one.
fn roll_journal(raw: &SceneFile) -> Option<f64> {
    raw.roll.as_ref().map(|r| r.journal.diameter_mm * 1e-3)
}

/// The model of the support at `key` by its `type`; `roll_journal` [m] is the journal diameter a
/// rollers support takes unless it gives its own.
fn support_model(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll_journal: Option<f64>,
) -> Result<SupportModel, InputError> {
    match s.kind.as_str() {
        "linear" => Ok(SupportModel::Linear(linear_support(c, key, s)?)),
        "rollers" => Ok(SupportModel::Rollers(roller_support(
            c,
            key,
            s,
            roll_journal,
        )?)),
        other => Err(c.err(
            &format!("{key}.type"),
            format!("`{other}`: expected `linear` or `rollers`"),
        )),
    }
}

/// A linear support: its spring, an optional support mass with its ground spring, and the
/// spring by speed (speeds ascending, Hz → rad/s).
fn linear_support(c: &Check, key: &str, s: &SupportFile) -> Result<LinearSupport, InputError> {
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
    Ok(LinearSupport {
        spring: spring_v,
        by_speed,
        mass,
    })
}

/// A journal on rollers on a stand: the journal (its diameter, else `roll_journal` [m]) and its
/// roundness, the rollers, how their roundness is driven, the contact law and the stand.
fn roller_support(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll_journal: Option<f64>,
) -> Result<RollerSupport, InputError> {
    let need = |what: &str| c.err(key, format!("a rollers support needs `{what}`"));
    let stand_f = s.stand.as_ref().ok_or_else(|| need("stand"))?;
    let contact_f = s.contact.as_ref().ok_or_else(|| need("contact"))?;
    if s.rollers.is_empty() {
        return Err(need("rollers"));
    }
    let ck = format!("{key}.contact");
    let e = c.range(&format!("{ck}.exponent"), contact_f.exponent, 1.0, 3.0)?;
    let k_mm = c.positive(&format!("{ck}.k_n_per_mm_e"), contact_f.k_n_per_mm_e)?;
    let journal_diameter = match (s.journal_diameter_mm, roll_journal) {
        (Some(d), _) => 1e-3 * c.positive(&format!("{key}.journal_diameter_mm"), d)?,
        (None, Some(d)) => d,
        (None, None) => return Err(need("journal_diameter_mm")),
    };
    let rollers = rollers(c, key, &s.rollers)?;
    Ok(RollerSupport {
        journal_diameter,
        journal_roundness: harmonics(c, &format!("{key}.journal_roundness"), &s.journal_roundness)?,
        rollers,
        roller_phase: roller_phase(c, key, s.roller_phase.as_deref())?,
        contact: contact(c, &ck, contact_f, (k_mm, e))?,
        stand: stand(c, key, stand_f)?,
    })
}

/// The rollers of the support at `key`: names unique within it, angles within ±89°.
fn rollers(c: &Check, key: &str, list: &[RollerFile]) -> Result<Vec<Roller>, InputError> {
    let mut rollers = Vec::new();
    for (i, r) in list.iter().enumerate() {
        let rk = format!("{key}.rollers[{i}]");
        if list[..i].iter().any(|o| o.name == r.name) {
            return Err(c.err(
                &format!("{rk}.name"),
                format!("roller name `{}` is used twice in this support", r.name),
            ));
        }
        rollers.push(Roller {
            name: r.name.clone(),
            angle: c.range(&format!("{rk}.angle_deg"), r.angle_deg, -89.0, 89.0)? * PI / 180.0,
            diameter: 1e-3 * c.positive(&format!("{rk}.diameter_mm"), r.diameter_mm)?,
            roundness: harmonics(c, &format!("{rk}.roundness"), &r.roundness)?,
        });
    }
    Ok(rollers)
}

/// `roller_phase`: roll-angle (the default, as the source did) or roller-angle.
fn roller_phase(c: &Check, key: &str, phase: Option<&str>) -> Result<RollerPhase, InputError> {
    match phase.unwrap_or("roll-angle") {
        "roll-angle" => Ok(RollerPhase::RollAngle),
        "roller-angle" => Ok(RollerPhase::RollerAngle),
        other => Err(c.err(
            &format!("{key}.roller_phase"),
            format!("`{other}`: expected roll-angle or roller-angle"),
        )),
    }
}

/// The contact law at `ck` in SI, its stiffness `k_mm` [N/mm^e] and exponent `e` checked
/// before the journal and rollers.
fn contact(
    c: &Check,
    ck: &str,
    contact: &ContactFile,
    (k_mm, e): (f64, f64),
) -> Result<ContactLaw, InputError> {
    Ok(ContactLaw {
        // N/mm^e → N/m^e: F = k (1000 δ)^e.
        k: k_mm * 1000f64.powf(e),
        exponent: e,
        c_max: 1e3 * c.non_negative(&format!("{ck}.c_max_ns_per_mm"), contact.c_max_ns_per_mm)?,
        d: 1e-6 * c.positive(&format!("{ck}.d_um"), contact.d_um)?,
    })
}

/// The stand of the support at `key`: its mass, direct stiffness and damping (no cross terms).
fn stand(c: &Check, key: &str, stand: &StandFile) -> Result<Stand, InputError> {
    Ok(Stand {
        mass: c.positive(&format!("{key}.stand.mass_kg"), stand.mass_kg)?,
        spring: SpringDamper {
            kx: c.positive(&format!("{key}.stand.kx_n_per_m"), stand.kx_n_per_m)?,
            ky: c.positive(&format!("{key}.stand.ky_n_per_m"), stand.ky_n_per_m)?,
            cx: c.non_negative(&format!("{key}.stand.cx_ns_per_m"), stand.cx_ns_per_m)?,
            cy: c.non_negative(&format!("{key}.stand.cy_ns_per_m"), stand.cy_ns_per_m)?,
            ..SpringDamper::default()
        },
    })
}

/// A spring–damper table at `key` (stiffness N/m, damping Ns/m; the direct terms not negative).
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

/// Roundness harmonics at `key`: orders 1..=256, amplitudes µm → m, phases in rad.
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
