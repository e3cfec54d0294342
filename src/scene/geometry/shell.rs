//! A roll shell's wall: nominal (`wall_thickness_mm`), a thickness map read from a CSV file
//! (`thickness_map`), a seeded synthetic map (`synthetic_map`) or a seeded random field
//! (`random_wall`: mean in mm, a standard deviation with a correlation length around (arc length
//! at the mean wall's mid radius) or a `spectrum` of standard deviations per whole harmonic
//! order in mm, an optional correlation length along the shell in mm, the grid) → the shell's
//! section.
//!
//! In: the `[roll.shell]` table (the wall in mm; a CSV path relative to the scene file; the
//! synthetic map's mean, min, max and standard deviation in mm, harmonics with phases in
//! degrees, the random share, the correlation length in mm, the grid), the shell's length and
//! outer diameter [m]. Out: the nominal wall [m], the [`ThicknessMap`] (m) and the shell's
//! [`SectionSpec`], or an [`InputError`] at the key (an error inside the CSV names the CSV and
//! its line, and where the scene names it). Method: a wall is nominal or a map, never both; the
//! synthetic map is drawn from its [`SyntheticSpec`] (min < mean < max); a map's wall must fit
//! the tube (0 < t < D/2), blamed on whichever of wall and diameter an override set.

use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use crate::error::InputError;
use crate::rotor::fe::SectionSpec;
use crate::rotor::wall::{
    Angular, AxialShape, HarmonicSpec, RandomFieldSpec, SyntheticSpec, ThicknessMap,
};
use crate::scene::check::Check;
use crate::scene::file::{RandomWallFile, RandomWallHarmonicFile, ShellFile, SyntheticMapFile};

/// The key of the shell's outer diameter, which its wall must fit.
const OUTER_KEY: &str = "roll.shell.outer_diameter_mm";

/// The shell's nominal wall [m], if it gives one (`wall_thickness_mm`): never beside a map, and
/// thinner than half the tube of diameter `outer` [m].
pub(super) fn nominal_wall(
    c: &Check,
    sh: &ShellFile,
    outer: f64,
) -> Result<Option<f64>, InputError> {
    // The wall is either nominal (uniform) or a map, never both: with a map, a nominal wall would
    // be ignored in favour of the map's, a silent change of the roll's mass and stiffness.
    let has_map =
        sh.thickness_map.is_some() || sh.synthetic_map.is_some() || sh.random_wall.is_some();
    Ok(match sh.wall_thickness_mm {
        Some(_) if has_map => {
            return Err(c.err(
                "roll.shell.wall_thickness_mm",
                "give either a nominal wall (wall_thickness_mm) or a thickness map \
                 (thickness_map, synthetic_map or random_wall), not both: with a map the wall, \
                 and so the shell's mass and stiffness, come from the map",
            ))
        }
        Some(w) => {
            let wall = 1e-3 * c.size_mm("roll.shell.wall_thickness_mm", w)?;
            if 2.0 * wall >= outer {
                return Err(c.err_among(
                    &["roll.shell.wall_thickness_mm", OUTER_KEY],
                    format!(
                        "a wall of {} mm does not fit in a {} mm tube",
                        wall * 1e3,
                        outer * 1e3
                    ),
                ));
            }
            Some(wall)
        }
        None => None,
    })
}

/// The shell's thickness map over its `length` [m], if it has one: read from the CSV file
/// (relative to the scene file) or drawn from the synthetic map; its wall must fit the tube of
/// diameter `outer` [m].
pub(super) fn thickness_map(
    c: &Check,
    sh: &ShellFile,
    length: f64,
    outer: f64,
) -> Result<Option<Arc<ThicknessMap>>, InputError> {
    let map = match (&sh.thickness_map, &sh.synthetic_map, &sh.random_wall) {
        (Some(_), Some(_), _) => {
            return Err(c.err(
                "roll.shell.synthetic_map",
                "give either thickness_map (a CSV file) or synthetic_map, not both",
            ))
        }
        (Some(_), None, Some(_)) | (None, Some(_), Some(_)) => {
            return Err(c.err(
                "roll.shell.random_wall",
                "give one thickness map: thickness_map (a CSV file), synthetic_map or \
                 random_wall, not two",
            ))
        }
        (Some(csv), None, None) => {
            let p = c.file.parent().unwrap_or(Path::new(".")).join(csv);
            // Errors inside the CSV name the CSV and its line, and where the scene names it; an
            // unreadable file is reported where the scene names it.
            let key = "roll.shell.thickness_map";
            // Read once per scene source (its doc says why).
            let map = c.source.thickness_map(&p, length, || {
                ThicknessMap::from_csv(&p, length).map_err(|mut e| match e.line {
                    Some(_) => {
                        let at = c.err(key, "");
                        let line = at.line.map(|l| format!(":{l}")).unwrap_or_default();
                        e.reason += &format!(" (the map of `{key}`, {}{line})", at.file.display());
                        e
                    }
                    None => c.err(key, format!("{}: {}", p.display(), e.reason)),
                })
            })?;
            Some(map)
        }
        (None, Some(s), None) => {
            let spec = synthetic_spec(c, s)?;
            spec.validate(length)
                .map_err(|r| c.err("roll.shell.synthetic_map", r))?;
            Some(Arc::new(ThicknessMap::synthetic(&spec, length)))
        }
        (None, None, Some(r)) => {
            let spec = random_wall_spec(c, r, outer)?;
            spec.validate(length)
                .map_err(|e| c.err("roll.shell.random_wall", e))?;
            Some(Arc::new(ThicknessMap::random_field(&spec, length)))
        }
        (None, None, None) => None,
    };
    if let Some(m) = &map {
        fits_tube(c, sh, m, outer)?;
    }
    Ok(map)
}

/// A map's wall lies in (0, D/2) for a tube of diameter `outer` [m]; the error names the CSV
/// file the map came from.
fn fits_tube(c: &Check, sh: &ShellFile, m: &ThicknessMap, outer: f64) -> Result<(), InputError> {
    let st = m.stats();
    if st.min_m <= 0.0 || st.max_m >= 0.5 * outer {
        let source = match &sh.thickness_map {
            Some(csv) => format!(
                " ({})",
                c.file
                    .parent()
                    .unwrap_or(Path::new("."))
                    .join(csv)
                    .display()
            ),
            None => String::new(),
        };
        let map_key = map_key(sh);
        return Err(c.err_among(
            &[map_key, OUTER_KEY],
            format!(
                "map thickness {:.3}..{:.3} mm{source} does not fit a {} mm tube",
                st.min_m * 1e3,
                st.max_m * 1e3,
                outer * 1e3
            ),
        ));
    }
    Ok(())
}

/// The key of the shell's map, where errors about the map point.
fn map_key(sh: &ShellFile) -> &'static str {
    match (&sh.thickness_map, &sh.random_wall) {
        (Some(_), _) => "roll.shell.thickness_map",
        (None, Some(_)) => "roll.shell.random_wall",
        (None, None) => "roll.shell.synthetic_map",
    }
}

/// The shell's section, of diameter `outer` [m]: mapped when it has a map, else a tube of its
/// nominal wall; with neither it has no wall.
pub(super) fn shell_section(
    c: &Check,
    outer: f64,
    map: &Option<Arc<ThicknessMap>>,
    wall: Option<f64>,
) -> Result<SectionSpec, InputError> {
    Ok(match (map, wall) {
        (Some(m), _) => SectionSpec::Mapped {
            outer,
            map: Arc::clone(m),
            map_z0: 0.0,
        },
        (None, Some(w)) => SectionSpec::Tube {
            outer,
            inner: outer - 2.0 * w,
            asymmetry: 0.0,
        },
        (None, None) => {
            return Err(c.err(
                "roll.shell",
                "the shell needs its wall: wall_thickness_mm (uniform) or a thickness map \
                 (thickness_map, synthetic_map or random_wall)",
            ))
        }
    })
}

/// The synthetic map's spec in SI (m, rad) from `roll.shell.synthetic_map`.
fn synthetic_spec(c: &Check, s: &SyntheticMapFile) -> Result<SyntheticSpec, InputError> {
    let k = "roll.shell.synthetic_map";
    let mean = c.positive(&format!("{k}.mean_mm"), s.mean_mm)?;
    let min = c.positive(&format!("{k}.min_mm"), s.min_mm)?;
    let max = c.positive(&format!("{k}.max_mm"), s.max_mm)?;
    let std = c.positive(&format!("{k}.std_mm"), s.std_mm)?;
    if !(min < mean && mean < max) {
        return Err(c.err(k, "needs min_mm < mean_mm < max_mm"));
    }
    let mut harmonics = Vec::new();
    for (i, h) in s.harmonics.iter().enumerate() {
        let hk = format!("{k}.harmonics[{i}]");
        harmonics.push(HarmonicSpec {
            order: c.count(&format!("{hk}.order"), h.order as usize, 1, 64)? as u32,
            weight: c.non_negative(&format!("{hk}.weight"), h.weight)?,
            phase_rad: c.finite(&format!("{hk}.phase_deg"), h.phase_deg)? * PI / 180.0,
            phase_twist_rad: c.finite(&format!("{hk}.twist_deg"), h.twist_deg)? * PI / 180.0,
            axial_shape: match h.axial_shape.as_str() {
                "constant" => AxialShape::Constant,
                "half-sine" => AxialShape::HalfSine,
                "linear" => AxialShape::Linear,
                other => {
                    return Err(c.err(
                        &format!("{hk}.axial_shape"),
                        format!("`{other}`: expected constant, half-sine or linear"),
                    ))
                }
            },
        });
    }
    Ok(SyntheticSpec {
        seed: s.seed,
        mean_m: mean * 1e-3,
        std_m: std * 1e-3,
        min_m: min * 1e-3,
        max_m: max * 1e-3,
        harmonics,
        random_share: c.range(&format!("{k}.random_share"), s.random_share, 0.0, 1.0)?,
        correlation_length_m: 1e-3
            * c.positive(
                &format!("{k}.correlation_length_mm"),
                s.correlation_length_mm,
            )?,
        n_angles: c.count(&format!("{k}.angles"), s.angles, 8, 4096)?,
        n_stations: c.count(&format!("{k}.stations"), s.stations, 2, 4096)?,
    })
}

/// The random wall's spec in SI (m) from `roll.shell.random_wall`, on a shell of diameter
/// `outer` [m]: the correlation around is an arc length at the mean wall's mid radius; a
/// spectrum gives a standard deviation per harmonic instead (`spectrum_lines`).
fn random_wall_spec(
    c: &Check,
    r: &RandomWallFile,
    outer: f64,
) -> Result<RandomFieldSpec, InputError> {
    let k = "roll.shell.random_wall";
    let mean = 1e-3 * c.positive(&format!("{k}.mean_mm"), r.mean_mm)?;
    if 2.0 * mean >= outer {
        return Err(c.err_among(
            &[&format!("{k}.mean_mm"), OUTER_KEY],
            format!(
                "a mean wall of {} mm does not fit in a {} mm tube",
                mean * 1e3,
                outer * 1e3
            ),
        ));
    }
    let n_angles = c.count(&format!("{k}.angles"), r.angles, 8, 4096)?;
    let angular = match (&r.spectrum, r.std_mm, r.correlation_around_mm) {
        (None, Some(std), Some(around)) => Angular::Correlation {
            std_m: 1e-3 * c.positive(&format!("{k}.std_mm"), std)?,
            around_m: 1e-3 * c.positive(&format!("{k}.correlation_around_mm"), around)?,
            radius_m: 0.5 * (outer - mean),
        },
        (None, _, _) => {
            return Err(c.err(
                k,
                "give std_mm with correlation_around_mm (a correlation around the shell), or \
                 spectrum (a standard deviation per circumferential harmonic)",
            ))
        }
        (Some(_), std, around) if std.is_some() || around.is_some() => {
            let extra = if std.is_some() {
                "std_mm"
            } else {
                "correlation_around_mm"
            };
            return Err(c.err(
                &format!("{k}.{extra}"),
                "give either spectrum (its harmonics' standard deviations make the wall's) or \
                 std_mm with correlation_around_mm, not both",
            ));
        }
        (Some(lines), _, _) => Angular::Spectrum(spectrum_lines(c, lines, n_angles)?),
    };
    Ok(RandomFieldSpec {
        seed: r.seed,
        mean_m: mean,
        angular,
        along_m: r
            .correlation_along_mm
            .map(|l| c.positive(&format!("{k}.correlation_along_mm"), l))
            .transpose()?
            .map(|l| 1e-3 * l),
        n_angles,
        n_stations: c.count(&format!("{k}.stations"), r.stations, 2, 1000)?,
    })
}

/// A random wall's `spectrum`: (order, σ [m]) per line, each order a whole number the grid of
/// `n_angles` resolves (1 … ⌊(n_angles − 1)/2⌋), given once, each σ ≥ 0 and one above 0.
fn spectrum_lines(
    c: &Check,
    lines: &[RandomWallHarmonicFile],
    n_angles: usize,
) -> Result<Vec<(usize, f64)>, InputError> {
    let k = "roll.shell.random_wall";
    let top = (n_angles - 1) / 2;
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(lines.len());
    for (i, h) in lines.iter().enumerate() {
        let key = format!("{k}.spectrum[{i}].order");
        let n = h.order;
        let why = if !n.is_finite() || n.fract() != 0.0 {
            Some(format!(
                "must be a whole number (a circumferential harmonic), got {}",
                crate::text::number_text(n)
            ))
        } else if n < 1.0 {
            Some(format!(
                "must be at least 1, got {n}: order 0 is the mean wall, `{k}.mean_mm`"
            ))
        } else if n > top as f64 {
            Some(format!(
                "order {n} needs at least {} angles around; the grid has {n_angles} \
                 (`{k}.angles`), which resolve the orders 1 … {top}",
                2.0 * n + 1.0
            ))
        } else {
            None
        };
        if let Some(why) = why {
            return Err(c.err(&key, why));
        }
        let order = n as usize;
        if let Some(j) = out.iter().position(|&(m, _)| m == order) {
            return Err(c.err(
                &key,
                format!("order {order} is given twice (also `{k}.spectrum[{j}]`)"),
            ));
        }
        let std = c.non_negative(&format!("{k}.spectrum[{i}].std_mm"), h.std_mm)?;
        out.push((order, 1e-3 * std));
    }
    if !out.iter().any(|&(_, s)| s > 0.0) {
        return Err(c.err(
            &format!("{k}.spectrum"),
            "needs a harmonic with a positive std_mm: without one the wall is uniform \
             (give wall_thickness_mm for that)",
        ));
    }
    Ok(out)
}
