//! A machine: several rolls, each its own scene, placed in one machine frame and pressed
//! together in nips.
//!
//! In: a machine file (`[[rolls]]` and `[[nips]]`, keys in `docs/scene-keys.md`) read with its
//! `--set` overrides; each roll's scene file (relative to the machine file) with its own
//! overrides (`set`). Out: the first roll's [`Scene`] carrying the [`Machine`] (every roll's
//! scene, axis position [m], loading-arm force [N]; every nip's segments, direction, gap and
//! contact law in SI), or an [`InputError`] naming the file, key and line.
//!
//! Method and assumptions: the rolls' axes are parallel to z and their z frames coincide (z = 0
//! at the tending end of every roll); a roll's axis is at `position_mm` = (x, y) of the inertial
//! frame. The first roll's scene sets the run window, sampling, solver and outputs of the whole
//! machine. A nip's direction is the unit vector from roll_a's axis to roll_b's; its contact runs
//! over [from_mm, to_mm] in `segments` equal segments, each on one outer diameter of both rolls
//! (plus the cover's thickness on the covered roll). Rolls may not overlap (axes closer than the
//! sum of their outer radii); a gap closes under load. A roll with `surface_speed_of` turns the
//! other way at the speed profile of that roll times R_other/R_own (the radii at their nip).
//! Contact laws per segment of length L_s:
//! - `linear`: F = k L_s δ (k [N/m²] per length per penetration, tension too: for closed forms);
//! - `hertz`: steel on steel, the source's Roark line contact fitted to F = k δ^e as for the
//!   rollers (`ContactGeometry`), over 0.1–10 times the nip's line load (1–100 kN/m without one);
//! - `cover`: a Winkler layer on one roll, foundation modulus k = E/((1 − ν²) h) [N/m³]
//!   (plane strain, thin layer); with R = R_a R_b/(R_a + R_b) the band is 2a, a = √(2Rδ), and
//!   the force per length ∫k(δ − x²/2R)dx = (4√2/3) k √R δ^1.5. With
//!   `cover_unrelaxed_modulus_mpa` E_u (or `cover_loss_factor` η at `cover_loss_frequency_hz`,
//!   mapped to E_u by [`sls_ratio`]) and `cover_relaxation_time_s` τ the cover is a standard
//!   linear solid (`cover_modulus_mpa` its relaxed modulus E_r < E_u; both as foundation
//!   moduli as above), tracked at `cover_points` points round the covered roll per segment
//!   (`dynamics/cover.rs`).
//!
//! Runout: a roll's `roundness` and a cover's `cover_roundness` (harmonics as the journals',
//! µm → m) give each roll's outer surface at the nip (`Nip::surfaces`, the cover's after the
//! roll's own); `cover_roundness` only on a `cover` nip.
//!
//! Crown: `crown_um` C (the rolls' outer surfaces together, at the middle of the contact range
//! against its ends; negative: concave) narrows the gap at a segment centre z by
//! C (1 − ((z − z_m)/(½(to − from)))²), z_m the range's middle (a parabolic crown, the usual
//! grinding form); |C| below the smaller radius.
//!
//! `--set` on a machine: its own keys (`rolls[i].…`, `nips[i].…`); `simulation.*`, `solver.*`,
//! `outputs.*` and `speed.*` go to the first roll's scene (after its `set`); any other key is an
//! error saying so.
//!
//! The line load q [N/m] presses roll_b toward roll_a: q (to − from) split evenly over roll_b's
//! supports' nodes, beside the arms' forces of `arm_force_n` on every support node of a roll
//! (constant, harmonic or a table in time) and the webs' line loads (`machine_loads.rs`).

use std::path::Path;
use std::sync::Arc;

use super::check::Check;
use super::contact_fit::ContactGeometry;
use super::locate;
use super::machine_file::{MachineFile, NipFile};
use super::machine_loads;
use super::overrides::{override_error_key, parse_override, with_overrides, COMMAND_LINE};
use super::source::Source;
use super::supports::harmonics;
use super::types::{CoverSpec, Machine, MachineRoll, Nip, NipLaw, Scene};
use crate::error::InputError;
use crate::rotor::fe::{RotorSpec, SectionSpec};

/// Reads a machine file (`source`, with `--set` overrides) and its rolls' scenes (module doc).
pub(super) fn load(source: &Source, overrides: &[String]) -> Result<Scene, InputError> {
    let path = source.path();
    let (overrides, first_roll) = split_overrides(overrides)?;
    let (table, keys) = with_overrides(source, &overrides)?;
    let raw: MachineFile = match source.layers.as_slice() {
        [only] if overrides.is_empty() => {
            toml::from_str(&only.text).map_err(|e| locate::toml_error(path, &only.text, &e))?
        }
        _ => table.clone().try_into().map_err(|e: toml::de::Error| {
            let err = InputError::new(path, locate::plain_type_error(e.message()));
            match override_error_key(&table) {
                Some(k) => err.with_key(k),
                None => err,
            }
        })?,
    };
    let c = Check {
        file: path,
        source,
        overridden: &keys,
    };
    let machine = build(&c, &raw, &first_roll)?;
    let first = &machine.rolls[0].scene;
    let mut scene = first.clone();
    scene.name = raw.name.clone().unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    });
    scene.description = raw.description.clone().unwrap_or_default();
    scene.source = path.to_path_buf();
    scene.bases = source.layers[1..].iter().map(|l| l.path.clone()).collect();
    scene.machine = Some(Arc::new(machine));
    Ok(scene)
}

/// The top-level keys of a machine file.
const MACHINE_KEYS: [&str; 5] = ["name", "description", "rolls", "nips", "webs"];

/// The scene tables whose `--set` overrides a machine passes to its first roll's scene: the run
/// window, solver and outputs (the machine's, module doc) and the first roll's speed (rolls with
/// `surface_speed_of` it follow).
const FIRST_ROLL_TABLES: [&str; 4] = ["simulation", "solver", "outputs", "speed"];

/// Splits a machine's overrides into its own and those for its first roll's scene
/// ([`FIRST_ROLL_TABLES`]); any other key is an error naming it and saying where it belongs.
fn split_overrides(overrides: &[String]) -> Result<(Vec<String>, Vec<String>), InputError> {
    let (mut own, mut first) = (Vec::new(), Vec::new());
    for o in overrides {
        let Ok((k, _)) = parse_override(o) else {
            own.push(o.clone());
            continue;
        };
        let head = match locate::parse_path(&k).first() {
            Some(locate::Step::Key(h)) => h.clone(),
            _ => String::new(),
        };
        if FIRST_ROLL_TABLES.contains(&head.as_str()) {
            first.push(o.clone());
        } else if MACHINE_KEYS.contains(&head.as_str()) {
            own.push(o.clone());
        } else {
            return Err(InputError::new(
                Path::new(COMMAND_LINE),
                format!(
                    "`{k}` is not a key of a machine file ({}): a roll's scene keys go in its \
                     `rolls[i].set`; `simulation.*`, `solver.*`, `outputs.*` (the machine's run \
                     window, solver and outputs, read from the first roll's scene) and `speed.*` \
                     (the first roll's speed) may be set on the machine",
                    MACHINE_KEYS.join(", ")
                ),
            )
            .with_key(k));
        }
    }
    Ok((own, first))
}

/// The outer diameter [m] and material (E [Pa], ν) of `rotor` over [z0, z1] [m], if one
/// segment's outer diameter covers it all.
fn surface(rotor: &RotorSpec, z0: f64, z1: f64) -> Option<(f64, (f64, f64))> {
    let mut start = rotor.z_start;
    let mut found: Option<(f64, (f64, f64))> = None;
    for seg in &rotor.segments {
        let end = start + seg.length;
        if end > z0 && start < z1 {
            let outer = match &seg.section {
                SectionSpec::Tube { outer, .. } | SectionSpec::Mapped { outer, .. } => *outer,
            };
            let mat = (seg.material.youngs_modulus, seg.material.poisson);
            match found {
                Some((d, _)) if d != outer => return None,
                _ => found = Some((outer, mat)),
            }
        }
        start = end;
    }
    let covered = rotor.z_start <= z0 + 1e-12 && start >= z1 - 1e-12;
    found.filter(|_| covered)
}

fn build(c: &Check, raw: &MachineFile, first_roll: &[String]) -> Result<Machine, InputError> {
    if raw.rolls.is_empty() {
        return Err(c.err("rolls", "a machine needs at least one roll"));
    }
    let dir = c.file.parent().unwrap_or(Path::new("."));
    let mut rolls: Vec<MachineRoll> = Vec::new();
    for (i, r) in raw.rolls.iter().enumerate() {
        let key = |k: &str| format!("rolls[{i}].{k}");
        if rolls.iter().any(|o| o.name == r.name) {
            return Err(c.err(&key("name"), format!("a second roll named `{}`", r.name)));
        }
        let mut set = r.set.clone();
        if i == 0 {
            set.extend_from_slice(first_roll);
        }
        // Read once per machine source (Source::named_scene says why).
        let roll_source = c.source.named_scene(&dir.join(&r.scene))?;
        let mut scene = Scene::from_source(&roll_source, &set)?;
        if scene.machine.is_some() {
            return Err(c.err(&key("scene"), "a roll's scene is one roll, not a machine"));
        }
        if let Some(first) = rolls.first() {
            scene.simulation = first.scene.simulation.clone();
            scene.solver = first.scene.solver.clone();
            scene.outputs = first.scene.outputs;
        }
        let pair = |k: &str, v: &[f64]| match v {
            [x, y] => Ok([c.finite(&key(k), *x)?, c.finite(&key(k), *y)?]),
            _ => Err(c.err(&key(k), format!("must be [x, y], got {} numbers", v.len()))),
        };
        let [x, y] = pair("position_mm", &r.position_mm)?;
        let position = [1e-3 * x, 1e-3 * y];
        let arm = machine_loads::arm(c, i, r)?;
        rolls.push(MachineRoll {
            name: r.name.clone(),
            scene,
            set,
            position,
            arm,
            speed_factor: 1.0,
            roundness: harmonics(c, &key("roundness"), &r.roundness)?,
        });
    }
    let names: Vec<&str> = raw.rolls.iter().map(|r| r.name.as_str()).collect();
    let mut nips = Vec::new();
    for (i, n) in raw.nips.iter().enumerate() {
        nips.push(nip(c, i, n, &names, &rolls)?);
    }
    overlaps(c, &rolls, &nips)?;
    tie_speeds(c, raw, &mut rolls, &nips)?;
    let extents: Vec<(f64, f64)> = rolls.iter().map(|r| extent(&r.scene.rotor)).collect();
    let webs = (raw.webs.iter().enumerate())
        .map(|(i, w)| machine_loads::web(c, i, w, &names, &extents))
        .collect::<Result<_, _>>()?;
    Ok(Machine { rolls, nips, webs })
}

/// The axial extent [m] of `rotor`: from its start to the end of its last segment.
fn extent(rotor: &RotorSpec) -> (f64, f64) {
    let length: f64 = rotor.segments.iter().map(|s| s.length).sum();
    (rotor.z_start, rotor.z_start + length)
}

/// The roll named `name` under `key`.
fn roll_index(c: &Check, key: &str, name: &str, names: &[&str]) -> Result<usize, InputError> {
    names.iter().position(|n| *n == name).ok_or_else(|| {
        c.err(
            key,
            format!("unknown roll `{name}` (rolls: {})", names.join(", ")),
        )
    })
}

fn nip(
    c: &Check,
    i: usize,
    n: &NipFile,
    names: &[&str],
    rolls: &[MachineRoll],
) -> Result<Nip, InputError> {
    let key = |k: &str| format!("nips[{i}].{k}");
    let a = roll_index(c, &key("roll_a"), &n.roll_a, names)?;
    let b = roll_index(c, &key("roll_b"), &n.roll_b, names)?;
    if a == b {
        return Err(c.err(&key("roll_b"), "a nip needs two different rolls"));
    }
    if n.segments == 0 || n.segments > 10_000 {
        return Err(c.err(
            &key("segments"),
            format!("must lie in [1, 10000], got {}", n.segments),
        ));
    }
    let z0 = 1e-3 * c.finite(&key("from_mm"), n.from_mm)?;
    let z1 = 1e-3 * c.finite(&key("to_mm"), n.to_mm)?;
    if z1 <= z0 {
        return Err(c.err(&key("to_mm"), "must be beyond from_mm"));
    }
    let on = |r: usize| {
        surface(&rolls[r].scene.rotor, z0, z1).ok_or_else(|| {
            c.err(
                &key("from_mm"),
                format!(
                    "the range {}–{} mm must lie on one outer diameter of roll `{}`",
                    n.from_mm, n.to_mm, rolls[r].name
                ),
            )
        })
    };
    let ((da, mat_a), (db, mat_b)) = (on(a)?, on(b)?);
    let (mut ra, mut rb) = (0.5 * da, 0.5 * db);
    let segment_length = (z1 - z0) / n.segments as f64;
    let line_load = 1e3
        * c.non_negative(
            &key("line_load_kn_per_m"),
            n.line_load_kn_per_m.unwrap_or(0.0),
        )?;
    let mut surfaces = (rolls[a].roundness.clone(), rolls[b].roundness.clone());
    let law = match n.law.as_str() {
        "linear" => NipLaw::Linear {
            stiffness: c.positive(
                &key("stiffness_n_per_m2"),
                n.stiffness_n_per_m2.unwrap_or(f64::NAN),
            )?,
        },
        "hertz" => {
            let q = if line_load > 0.0 { line_load } else { 1e4 };
            let geometry = ContactGeometry {
                journal_diameter: da,
                roller_diameter: db,
                length: segment_length,
                journal: mat_a,
                roller: mat_b,
                loads: (0.1 * q * segment_length, 10.0 * q * segment_length),
                points: 200,
            };
            NipLaw::Hertz {
                fit: geometry.fit(),
            }
        }
        "cover" => {
            let covered = n.cover_on.as_deref().unwrap_or("");
            let r = roll_index(c, &key("cover_on"), covered, names)?;
            if r != a && r != b {
                return Err(c.err(&key("cover_on"), "the cover must be on roll_a or roll_b"));
            }
            let h = 1e-3
                * c.positive(
                    &key("cover_thickness_mm"),
                    n.cover_thickness_mm.unwrap_or(f64::NAN),
                )?;
            let steel = if r == a { ra } else { rb };
            if h >= steel {
                return Err(c.err(
                    &key("cover_thickness_mm"),
                    format!(
                        "the cover ({} mm) must be thinner than the radius of roll `{covered}` ({} mm)",
                        1e3 * h,
                        1e3 * steel
                    ),
                ));
            }
            let e = 1e6
                * c.positive(
                    &key("cover_modulus_mpa"),
                    n.cover_modulus_mpa.unwrap_or(f64::NAN),
                )?;
            let nu = c.range(
                &key("cover_poisson"),
                n.cover_poisson.unwrap_or(f64::NAN),
                0.0,
                0.499,
            )?;
            let cover = harmonics(c, &key("cover_roundness"), &n.cover_roundness)?;
            if r == a {
                ra += h;
                surfaces.0.extend(cover);
            } else {
                rb += h;
                surfaces.1.extend(cover);
            }
            let foundation = e / ((1.0 - nu * nu) * h);
            let radius = ra * rb / (ra + rb);
            match viscoelastic(c, i, n, e)? {
                None => NipLaw::Cover {
                    foundation,
                    radius,
                    thickness: h,
                },
                Some((e_u, tau, points)) => NipLaw::Viscoelastic {
                    cover: CoverSpec {
                        relaxed: foundation,
                        unrelaxed: e_u / ((1.0 - nu * nu) * h),
                        relaxation_time: tau,
                        radius,
                        cover_radius: if r == a { ra } else { rb },
                        thickness: h,
                        on_b: r == b,
                        points,
                    },
                },
            }
        }
        other => {
            return Err(c.err(
                &key("law"),
                format!("unknown law `{other}` (linear, hertz, cover)"),
            ))
        }
    };
    if !n.cover_roundness.is_empty() && n.law != "cover" {
        return Err(c.err(
            &key("cover_roundness"),
            "only for a nip with a cover (law = \"cover\")",
        ));
    }
    let (pa, pb) = (rolls[a].position, rolls[b].position);
    let d = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
    if d == 0.0 {
        return Err(c.err(&format!("rolls[{b}].position_mm"), "on the axis of roll_a"));
    }
    let z: Vec<f64> = (0..n.segments)
        .map(|j| z0 + (j as f64 + 0.5) * segment_length)
        .collect();
    let crown = match n.crown_um {
        None => Vec::new(),
        Some(v) => {
            let c_m = 1e-6 * c.finite(&key("crown_um"), v)?;
            if c_m.abs() >= ra.min(rb) {
                return Err(c.err(
                    &key("crown_um"),
                    format!(
                        "must be smaller than the rolls' radii ({} mm), got {} mm",
                        1e3 * ra.min(rb),
                        1e3 * c_m
                    ),
                ));
            }
            let (mid, half) = (0.5 * (z0 + z1), 0.5 * (z1 - z0));
            (z.iter())
                .map(|zj| c_m * (1.0 - ((zj - mid) / half).powi(2)))
                .collect()
        }
    };
    Ok(Nip {
        name: n.name.clone(),
        rolls: (a, b),
        z,
        segment_length,
        normal: [(pb[0] - pa[0]) / d, (pb[1] - pa[1]) / d],
        gap: d - ra - rb,
        radii: (ra, rb),
        law,
        damping: c.non_negative(
            &key("damping_ns_per_m2"),
            n.damping_ns_per_m2.unwrap_or(0.0),
        )?,
        line_load,
        surfaces,
        crown,
    })
}

/// Cover points round the circumference per segment without `cover_points`: 1.07 mm apart on
/// the shipped covered roll's 175 mm radius, 15 of them across its 16 mm band.
pub const DEFAULT_COVER_POINTS: usize = 1024;

/// The viscoelastic keys of a `cover` nip: `None` for an elastic cover (none of them given),
/// else the unrelaxed modulus E_u [Pa] (above the relaxed `cover_modulus_mpa`, `e` [Pa]), the
/// relaxation time τ [s] and the cover points per segment.
fn viscoelastic(
    c: &Check,
    i: usize,
    n: &NipFile,
    e: f64,
) -> Result<Option<(f64, f64, usize)>, InputError> {
    let key = |k: &str| format!("nips[{i}].{k}");
    let loss = (n.cover_loss_factor, n.cover_loss_frequency_hz);
    let unrelaxed = match pair(c, i, ("cover_loss_factor", "cover_loss_frequency_hz"), loss)? {
        None => n.cover_unrelaxed_modulus_mpa,
        Some((eta, f)) => Some(1e-6 * e * sls_ratio(c, i, n, eta, f)?),
    };
    let keys = ("cover_unrelaxed_modulus_mpa", "cover_relaxation_time_s");
    let Some((e_u, tau)) = pair(c, i, keys, (unrelaxed, n.cover_relaxation_time_s))? else {
        return match n.cover_points {
            None => Ok(None),
            Some(_) => Err(c.err(
                &key("cover_points"),
                "only for a viscoelastic cover (with cover_unrelaxed_modulus_mpa and \
                 cover_relaxation_time_s)",
            )),
        };
    };
    let e_u = 1e6 * c.positive(&key("cover_unrelaxed_modulus_mpa"), e_u)?;
    if e_u <= e {
        return Err(c.err(
            &key("cover_unrelaxed_modulus_mpa"),
            format!(
                "the unrelaxed modulus ({} MPa) must exceed the relaxed cover_modulus_mpa ({} MPa)",
                1e-6 * e_u,
                1e-6 * e
            ),
        ));
    }
    let tau = c.positive(&key("cover_relaxation_time_s"), tau)?;
    let points = n.cover_points.unwrap_or(DEFAULT_COVER_POINTS);
    if !(16..=1_000_000).contains(&points) {
        return Err(c.err(
            &key("cover_points"),
            format!("must lie in [16, 1000000], got {points}"),
        ));
    }
    Ok(Some((e_u, tau, points)))
}

/// Two keys of nip `i` that go together: both values, neither (`None`), or an error at the one
/// given alone saying that it needs the other.
fn pair(
    c: &Check,
    i: usize,
    (ka, kb): (&str, &str),
    values: (Option<f64>, Option<f64>),
) -> Result<Option<(f64, f64)>, InputError> {
    let alone = |k: &str, other: &str| {
        c.err(
            &format!("nips[{i}].{k}"),
            format!("a viscoelastic cover: it needs {other} too"),
        )
    };
    match values {
        (None, None) => Ok(None),
        (Some(_), None) => Err(alone(ka, kb)),
        (None, Some(_)) => Err(alone(kb, ka)),
        (Some(a), Some(b)) => Ok(Some((a, b))),
    }
}

/// E_u/E_r of the standard linear solid whose loss factor E″/E′ at `f` [Hz] is `eta`, with the
/// nip's relaxation time τ: E′ = (E_r + E_u x²)/(1 + x²), E″ = (E_u − E_r) x/(1 + x²), x = 2πfτ
/// (Zener 1948), so E_u/E_r = (x + η)/(x (1 − η x)); it exists for η < 1/x (the loss factor
/// of E_u → ∞). Errors name the key: the unrelaxed modulus given too, no relaxation time, η or
/// f not positive, or η ≥ 1/x.
fn sls_ratio(c: &Check, i: usize, n: &NipFile, eta: f64, f: f64) -> Result<f64, InputError> {
    let key = |k: &str| format!("nips[{i}].{k}");
    if n.cover_unrelaxed_modulus_mpa.is_some() {
        return Err(c.err(
            &key("cover_loss_factor"),
            "give either cover_unrelaxed_modulus_mpa or cover_loss_factor with \
             cover_loss_frequency_hz, not both",
        ));
    }
    let Some(tau) = n.cover_relaxation_time_s else {
        return Err(c.err(
            &key("cover_loss_factor"),
            "a viscoelastic cover needs cover_relaxation_time_s too",
        ));
    };
    let eta = c.positive(&key("cover_loss_factor"), eta)?;
    let f = c.positive(&key("cover_loss_frequency_hz"), f)?;
    let tau = c.positive(&key("cover_relaxation_time_s"), tau)?;
    let x = 2.0 * std::f64::consts::PI * f * tau;
    if eta * x >= 1.0 {
        return Err(c.err(
            &key("cover_loss_factor"),
            format!(
                "a standard linear solid of relaxation time {tau} s has a loss factor below \
                 1/(2π f τ) = {} at {f} Hz, got {eta}",
                1.0 / x
            ),
        ));
    }
    Ok((x + eta) / (x * (1.0 - eta * x)))
}

/// Rolls overlap when their axes are closer than their outer radii (at a nip: the nip's radii,
/// a cover included; elsewhere the largest outer diameter of each roll) by more than 1 µm.
fn overlaps(c: &Check, rolls: &[MachineRoll], nips: &[Nip]) -> Result<(), InputError> {
    let largest = |r: &MachineRoll| {
        (r.scene.rotor.segments.iter())
            .map(|s| match &s.section {
                SectionSpec::Tube { outer, .. } | SectionSpec::Mapped { outer, .. } => 0.5 * outer,
            })
            .fold(0.0, f64::max)
    };
    for j in 0..rolls.len() {
        for i in 0..j {
            let radii = nips
                .iter()
                .find(|n| n.rolls == (i, j) || n.rolls == (j, i))
                .map(|n| n.radii.0 + n.radii.1)
                .unwrap_or_else(|| largest(&rolls[i]) + largest(&rolls[j]));
            let (p, q) = (rolls[i].position, rolls[j].position);
            let d = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            if d < radii - 1e-6 {
                return Err(c.err(
                    &format!("rolls[{j}].position_mm"),
                    format!(
                        "roll `{}` overlaps roll `{}`: axes {:.3} mm apart, outer radii {:.3} mm together",
                        rolls[j].name,
                        rolls[i].name,
                        1e3 * d,
                        1e3 * radii
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Ties the speed of each roll with `surface_speed_of` to that roll through their nip.
fn tie_speeds(
    c: &Check,
    raw: &MachineFile,
    rolls: &mut [MachineRoll],
    nips: &[Nip],
) -> Result<(), InputError> {
    let names: Vec<&str> = raw.rolls.iter().map(|r| r.name.as_str()).collect();
    for (i, r) in raw.rolls.iter().enumerate() {
        let Some(other) = &r.surface_speed_of else {
            continue;
        };
        let key = format!("rolls[{i}].surface_speed_of");
        let o = roll_index(c, &key, other, &names)?;
        if raw.rolls[o].surface_speed_of.is_some() || o == i {
            return Err(c.err(&key, format!("roll `{other}` must have a speed of its own")));
        }
        let nip = nips
            .iter()
            .find(|n| n.rolls == (i, o) || n.rolls == (o, i))
            .ok_or_else(|| c.err(&key, format!("no nip joins this roll and `{other}`")))?;
        let (own, theirs) = if nip.rolls.0 == i {
            (nip.radii.0, nip.radii.1)
        } else {
            (nip.radii.1, nip.radii.0)
        };
        rolls[i].scene.speed = rolls[o].scene.speed.scaled(-theirs / own);
        rolls[i].speed_factor = -theirs / own;
    }
    Ok(())
}
