//! The supports of a scene: each `[[supports]]` table → a [`Support`] on a named node, with its
//! [`SupportModel`] in SI.
//!
//! In: a support's table as written (stiffness in N/m, damping in Ns/m, masses in kg, diameters
//! in mm, roundness amplitudes in µm, contact k in N/mm^e or the contact's geometry in mm with
//! its materials by name and loads in N, its damping in Ns/mm, its depth in µm), the rotor's
//! named nodes, the scene's materials. Out: a linear support (spring–dampers, optionally
//! speed-dependent and through a support mass) or a journal on rollers on a stand, in N/m, Ns/m,
//! kg, m, N/m^e, rad; or an [`InputError`] at the key. Method: each value checked where it is
//! read; at least one support, one per node; a rollers support takes the roll's journal
//! diameter unless it gives its own. A contact gives its law either as written (`k_n_per_mm_e`
//! and `exponent`) or by its `geometry`, whose law is fitted to the Roark line contact
//! ([`super::contact_fit`]): the journal's diameter as above, the rollers' mean diameter unless
//! it gives one, the roll's material for the journal unless it names one, the journal's for the
//! roller unless it names one.

use std::f64::consts::PI;

use super::check::Check;
use super::contact_fit::{ContactFit, ContactGeometry};
use super::file::*;
use super::geometry::Materials;
use super::types::{
    ContactLaw, Harmonic, LinearSupport, Roller, RollerPhase, RollerSupport, SpringDamper, Stand,
    Support, SupportModel,
};
use crate::error::InputError;

/// Every `[[supports]]` of `raw`, each on a node the rotor names (`named`), no node twice; a
/// contact's geometry names its bodies' `materials`.
pub(super) fn build_supports(
    c: &Check,
    raw: &SceneFile,
    named: &[&str],
    materials: &Materials,
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
        let roll = Roll {
            journal: roll_journal(raw),
            material: raw.roll.as_ref().map(|r| r.material.as_str()),
            materials,
        };
        let model = support_model(c, &key, s, &roll)?;
        supports.push(Support { node, model });
    }
    Ok(supports)
}

/// What a rollers support takes from the scene unless it gives its own.
struct Roll<'a> {
    /// The roll's journal diameter [m], if the scene is a roll.
    journal: Option<f64>,
    /// The roll's material, if the scene is a roll.
    material: Option<&'a str>,
    /// The scene's materials.
    materials: &'a Materials,
}

/// The journal diameter [m] of the scene's roll, if it is one.
fn roll_journal(raw: &SceneFile) -> Option<f64> {
    raw.roll.as_ref().map(|r| r.journal.diameter_mm * 1e-3)
}

/// The model of the support at `key` by its `type`; a rollers support takes from `roll` what it
/// does not give.
fn support_model(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll: &Roll,
) -> Result<SupportModel, InputError> {
    match s.kind.as_str() {
        "linear" => Ok(SupportModel::Linear(linear_support(c, key, s)?)),
        "rollers" => Ok(SupportModel::Rollers(roller_support(c, key, s, roll)?)),
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

/// A journal on rollers on a stand: the journal (its diameter, else the roll's) and its
/// roundness, the rollers, how their roundness is driven, the contact law (as written, or fitted
/// to its geometry) and the stand.
fn roller_support(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll: &Roll,
) -> Result<RollerSupport, InputError> {
    let need = |what: &str| c.err(key, format!("a rollers support needs `{what}`"));
    let stand_f = s.stand.as_ref().ok_or_else(|| need("stand"))?;
    let contact_f = s.contact.as_ref().ok_or_else(|| need("contact"))?;
    if s.rollers.is_empty() {
        return Err(need("rollers"));
    }
    let ck = format!("{key}.contact");
    let form = law_form(c, &ck, contact_f)?;
    let journal_diameter = match (s.journal_diameter_mm, roll.journal) {
        (Some(d), _) => 1e-3 * c.positive(&format!("{key}.journal_diameter_mm"), d)?,
        (None, Some(d)) => d,
        (None, None) => return Err(need("journal_diameter_mm")),
    };
    let rollers = rollers(c, key, &s.rollers)?;
    let (law, contact_fit) = match form {
        // N/mm^e → N/m^e: F = k (1000 δ)^e.
        LawForm::Written { k_mm, e } => ((k_mm * 1000f64.powf(e), e), None),
        LawForm::Geometry(g) => {
            let gk = format!("{ck}.geometry");
            let fit = fitted_law(c, &gk, g, journal_diameter, &rollers, roll)?;
            ((fit.k, fit.exponent), Some(fit))
        }
    };
    Ok(RollerSupport {
        journal_diameter,
        journal_roundness: harmonics(c, &format!("{key}.journal_roundness"), &s.journal_roundness)?,
        rollers,
        roller_phase: roller_phase(c, key, s.roller_phase.as_deref())?,
        contact: contact(c, &ck, contact_f, law)?,
        contact_fit,
        stand: stand(c, key, stand_f)?,
    })
}

/// How a contact gives its law.
enum LawForm<'a> {
    /// As written: k [N/mm^e] and e, checked.
    Written { k_mm: f64, e: f64 },
    /// By its geometry, to be fitted.
    Geometry(&'a ContactGeometryFile),
}

/// The form of the law at `ck`: exactly one of the two, a written one checked.
fn law_form<'a>(c: &Check, ck: &str, f: &'a ContactFile) -> Result<LawForm<'a>, InputError> {
    match (f.k_n_per_mm_e, f.exponent, &f.geometry) {
        (None, None, Some(g)) => Ok(LawForm::Geometry(g)),
        (Some(_), _, Some(_)) | (_, Some(_), Some(_)) => Err(c.err(
            &format!("{ck}.geometry"),
            "give the contact law either as written (`k_n_per_mm_e` and `exponent`) or by its \
             `geometry` (k and e fitted to the Roark line contact), not both",
        )),
        (k, e, None) => {
            let missing = |what: &str| {
                c.err(
                    ck,
                    format!("the contact needs `{what}` (or a `geometry` to fit k and e to)"),
                )
            };
            let e = e.ok_or_else(|| missing("exponent"))?;
            let k = k.ok_or_else(|| missing("k_n_per_mm_e"))?;
            let e = c.range(&format!("{ck}.exponent"), e, 1.0, 3.0)?;
            let k_mm = c.positive(&format!("{ck}.k_n_per_mm_e"), k)?;
            Ok(LawForm::Written { k_mm, e })
        }
    }
}

/// The law fitted to the contact geometry at `gk` (module doc): the journal of diameter
/// `journal_diameter` [m] on `rollers`, materials and the journal's defaults from `roll`.
fn fitted_law(
    c: &Check,
    gk: &str,
    g: &ContactGeometryFile,
    journal_diameter: f64,
    rollers: &[Roller],
    roll: &Roll,
) -> Result<ContactFit, InputError> {
    let length = 1e-3 * c.positive(&format!("{gk}.contact_length_mm"), g.contact_length_mm)?;
    let roller_diameter = match g.roller_diameter_mm {
        Some(d) => 1e-3 * c.positive(&format!("{gk}.roller_diameter_mm"), d)?,
        None => rollers.iter().map(|r| r.diameter).sum::<f64>() / rollers.len() as f64,
    };
    let journal_key = format!("{gk}.journal_material");
    let journal_name = match (&g.journal_material, roll.material) {
        (Some(n), _) => n.as_str(),
        (None, Some(n)) => n,
        (None, None) => {
            return Err(c.err(
                &journal_key,
                "required for a [rotor] (a [roll] takes `roll.material`)",
            ))
        }
    };
    let journal = roll.materials.get(c, &journal_key, journal_name)?;
    let roller = match &g.roller_material {
        Some(n) => roll.materials.get(c, &format!("{gk}.roller_material"), n)?,
        None => journal,
    };
    let lk = format!("{gk}.fit_loads_n");
    let [lo, hi] = g.fit_loads_n[..] else {
        return Err(c.err(&lk, "give two loads, [smallest, largest]"));
    };
    let lo = c.positive(&lk, lo)?;
    if !(hi.is_finite() && hi > lo) {
        return Err(c.err(
            &lk,
            format!("the largest load must exceed the smallest, got {hi}"),
        ));
    }
    let geometry = ContactGeometry {
        journal_diameter,
        roller_diameter,
        length,
        journal: (journal.youngs_modulus, journal.poisson),
        roller: (roller.youngs_modulus, roller.poisson),
        loads: (lo, hi),
        points: c.count(&format!("{gk}.fit_points"), g.fit_points, 2, 1_000_000)?,
    };
    let b = geometry.half_width(hi);
    let radius = 0.5 * journal_diameter.min(roller_diameter);
    if b.is_nan() || b > 0.1 * radius {
        return Err(c.err(
            gk,
            format!(
                "under the largest load the contact band's half-width is {:.3} mm, not small \
                 against the radius {:.1} mm (over a tenth): the Hertz line contact does not \
                 apply; a longer contact or a smaller largest load",
                b * 1e3,
                radius * 1e3
            ),
        ));
    }
    let fit = geometry.fit();
    if !((1.0..=3.0).contains(&fit.exponent) && fit.k.is_finite() && fit.k > 0.0) {
        return Err(c.err(
            gk,
            format!(
                "the fitted law (k {:e} N/m^e, e {}) is outside what the contact accepts \
                 (k > 0, e in [1, 3])",
                fit.k, fit.exponent
            ),
        ));
    }
    Ok(fit)
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

/// The contact law at `ck` in SI, its stiffness `k` [N/m^e] and exponent `e` checked or fitted
/// before.
fn contact(
    c: &Check,
    ck: &str,
    contact: &ContactFile,
    (k, e): (f64, f64),
) -> Result<ContactLaw, InputError> {
    Ok(ContactLaw {
        k,
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
pub(super) fn harmonics(
    c: &Check,
    key: &str,
    list: &[HarmonicFile],
) -> Result<Vec<Harmonic>, InputError> {
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
