//! Every linear analysis of one linear system, computed together: what `rotorsweep linear`
//! prints, returns as JSON and writes with `-o`, and what a study stores per distinct linear
//! system under `/linear/<id>` (its `[linear]` table asks which).
//!
//! In: a [`Scene`], its [`Model`], its [`LinearSystem`] and a [`Request`]: spin speeds [Hz],
//! which analyses, the unbalance (the scene's own or one point mass), the Floquet cut-off.
//! Out: [`Results`]; [`Results::to_json`] (the `rotorsweep linear --json` object: damped modes
//! per speed, critical speeds, stability threshold, unbalance response at the sensors and named
//! nodes with the orbit's axes, Floquet growth and unstable ranges, static sag and forces,
//! critical-speed map) and [`Results::write`] (the same in an HDF5 group, units in attributes).
//!
//! Units at the interfaces: Hz, µm, degrees, N, N/m. Phase convention: [`PHASE_NOTE`]. Frames:
//! [`FRAME_NOTE`] for everything but Floquet ([`floquet`](super::floquet): body frame, exact for
//! the asymmetric roll on anisotropic supports).
//!
//! Method: each analysis of its module; the Floquet unstable ranges are refined between the
//! sampled speeds by regula falsi, and a speed whose growth did not converge under step
//! doubling is named in `warnings` and counts as neither stable nor unstable.

use std::time::Instant;

use nalgebra::DVector;
use rayon::prelude::*;
use serde_json::{json, Map, Value};

use super::campbell::{lateral_modes, sweep, CampbellData};
use super::critical_map::{critical_map, CriticalMap};
use super::floquet::{
    band_modes, scene_growth, time_invariant, unstable_ranges, BandMode, Growth, UNDAMPED_ZETA,
    UNSTABLE_GROWTH,
};
use super::modes::node_shape;
use super::peaks::{peaks, Peak};
use super::response::{plane_response, point_unbalance, SensorResponse};
use super::statics::{self, Static};
use super::FRAME_NOTE;
use crate::dynamics::model::Model;
use crate::dynamics::{LinearError, LinearSystem};
use crate::scene::{Scene, SupportModel, MAX_SPEED_HZ};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The phase convention of the unbalance response.
pub const PHASE_NOTE: &str = "x(t) = A cos(θ + φ), θ = Ω t the roll angle: φ against roll angle \
0, as the study analysis's lines (/analysis/lines)";

/// The Floquet analysis's frame, as printed and stored.
pub const FLOQUET_FRAME: &str = "body frame, supports turning backwards: exact for the \
asymmetric rotor on anisotropic supports; modes below cutoff_hz (null: all)";

/// Support stiffnesses of the critical-speed map [N/m]: 1e5 … 1e11, four per decade.
pub fn map_stiffness() -> Vec<f64> {
    (0..=24)
        .map(|i| 10f64.powf(5.0 + 0.25 * i as f64))
        .collect()
}

/// One point unbalance: mass [g] at radius [mm], body angle [°] (0 = +x of the body frame),
/// axial position [mm].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointUnbalance {
    /// Mass [g].
    pub mass_g: f64,
    /// Radius [mm].
    pub radius_mm: f64,
    /// Body angle [°].
    pub angle_deg: f64,
    /// Axial position [mm].
    pub z_mm: f64,
}

impl PointUnbalance {
    /// Parses `MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let bad = || format!("unbalance `{text}`: expected MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM");
        let v: Vec<f64> = text
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad())?;
        if v.len() != 4 || v.iter().any(|x| !x.is_finite()) {
            return Err(bad());
        }
        Ok(Self {
            mass_g: v[0],
            radius_mm: v[1],
            angle_deg: v[2],
            z_mm: v[3],
        })
    }

    fn label(&self) -> String {
        format!(
            "{},{},{},{}",
            self.mass_g, self.radius_mm, self.angle_deg, self.z_mm
        )
    }

    fn load(&self, model: &Model) -> DVector<f64> {
        point_unbalance(
            model,
            1e-3 * self.mass_g,
            1e-3 * self.radius_mm,
            self.angle_deg.to_radians(),
            1e-3 * self.z_mm,
        )
    }
}

/// What to compute: the damped modes and critical speeds always, the rest on request.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// Spin speeds [Hz], ascending.
    pub speeds_hz: Vec<f64>,
    /// List modes up to this damped frequency [Hz] (`None`: all).
    pub max_freq_hz: Option<f64>,
    /// The unbalance of the response (`None`: the scene's own).
    pub unbalance: Option<PointUnbalance>,
    /// Unbalance response at the sensors and named nodes.
    pub response: bool,
    /// Floquet stability at every positive speed.
    pub floquet: bool,
    /// Floquet: keep only the modes below this frequency [Hz] (`None`: all).
    pub floquet_cutoff_hz: Option<f64>,
    /// Static sag, journal positions and forces.
    pub statics: bool,
    /// Undamped critical speeds against the support stiffness ([`map_stiffness`]).
    pub critical_map: bool,
    /// Each mode's complex shape at the nodes.
    pub shapes: bool,
}

/// Parses a speed range `START:STOP:COUNT` [Hz] into its evenly spaced speeds.
pub fn parse_speeds(text: &str) -> Result<Vec<f64>, String> {
    let bad = || format!("speeds `{text}`: expected START:STOP:COUNT, e.g. 0:100:101");
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 3 {
        return Err(bad());
    }
    let start: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let stop: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    let count: usize = parts[2].trim().parse().map_err(|_| bad())?;
    if !(start.is_finite() && stop.is_finite() && start >= 0.0 && stop > start && count >= 2) {
        return Err(format!("{}: need 0 ≤ START < STOP and COUNT ≥ 2", bad()));
    }
    if count > MAX_SPEEDS {
        return Err(format!("{}: at most {MAX_SPEEDS} speeds", bad()));
    }
    if stop > MAX_SPEED_HZ {
        return Err(format!(
            "speeds `{text}`: STOP {stop:e} Hz is above {MAX_SPEED_HZ:e} Hz, the highest spin speed \
             a scene may ask for (speed.hz)"
        ));
    }
    Ok((0..count)
        .map(|i| start + (stop - start) * i as f64 / (count - 1) as f64)
        .collect())
}

/// Most speeds of one linear analysis.
pub const MAX_SPEEDS: usize = 100_000;

/// The unbalance response over the speeds.
#[derive(Debug, Clone)]
pub struct Response {
    /// The planes: the sensors, then the named nodes.
    pub planes: Vec<String>,
    /// How many of `planes` are sensors.
    pub sensors: usize,
    /// Per speed, per plane.
    pub values: Vec<Vec<SensorResponse>>,
    /// `scene` or the point unbalance `MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM`.
    pub unbalance: String,
    /// The peaks near each critical speed at the sensors, refined ([`super::peaks`]).
    pub peaks: Vec<Peak>,
}

/// The Floquet analysis over the positive speeds.
#[derive(Debug, Clone)]
pub struct Floquet {
    /// The positive speeds of the request [Hz] (empty when not needed).
    pub speeds_hz: Vec<f64>,
    /// Growth per revolution per speed.
    pub growth: Vec<Growth>,
    /// Unstable speed ranges [Hz].
    pub ranges: Vec<[f64; 2]>,
    /// Per range: its growth and the modes that combine.
    pub bands: Vec<Band>,
    /// The cut-off [Hz] (`None`: all modes).
    pub cutoff_hz: Option<f64>,
    /// Why Floquet was not run, when the body-frame system is time-invariant.
    pub not_needed: Option<&'static str>,
}

/// Why Floquet is not run on an axisymmetric rotor on isotropic supports.
pub const FLOQUET_NOT_NEEDED: &str = "not needed: an axisymmetric rotor on isotropic supports \
has a time-invariant body-frame system, whose stability is the damped modes' (the stability \
threshold)";

/// One Floquet-unstable range with what makes it up.
#[derive(Debug, Clone)]
pub struct Band {
    /// The range [Hz].
    pub range_hz: [f64; 2],
    /// The largest growth per revolution sampled in it, and at which speed [Hz].
    pub growth_per_rev: f64,
    /// Speed of that growth [Hz].
    pub at_hz: f64,
    /// The modes of the growing motion there.
    pub modes: Vec<BandMode>,
    /// `marginal` when every mode in it is undamped (growth at the Magnus error's size on
    /// |μ| = 1), else `unstable`.
    pub class: &'static str,
}

/// Every result of a [`Request`].
#[derive(Debug, Clone)]
pub struct Results {
    /// Scene name.
    pub scene: String,
    /// Damped modes, branches, critical speeds, threshold.
    pub campbell: CampbellData,
    /// Undamped standstill frequencies on the supports [Hz]: vertical, horizontal bending.
    pub supported: (Vec<f64>, Vec<f64>),
    /// Node positions [m].
    pub node_z: Vec<f64>,
    /// Unbalance response.
    pub response: Option<Response>,
    /// Floquet stability.
    pub floquet: Option<Floquet>,
    /// Static analysis (its failure as text).
    pub statics: Option<Result<Static, String>>,
    /// Critical-speed map and the support nodes it marks.
    pub map: Option<(CriticalMap, Vec<String>)>,
    /// Per support (scene order): what its journal spring is and its stand's stiffness.
    pub stands: Vec<StandMark>,
    /// Mode shapes per speed and lateral mode (x, y complex at the nodes), when asked for.
    pub shapes: Option<Vec<Vec<ShapeAtNodes>>>,
    /// Warnings of every analysis.
    pub warnings: Vec<String>,
    /// Wall time per analysis [s] (not stored by a study: its bytes must not depend on it).
    pub times: Vec<(&'static str, f64)>,
}

/// What the critical-speed map marks for one support: the journal spring the map varies is a
/// bearing's (`bearing`) or, on rollers, the contact's linearised tangent stiffness (`contact`),
/// in series with the stand, whose own stiffness (kx, ky) [N/m] is marked apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandMark {
    /// `bearing` or `contact`.
    pub spring: &'static str,
    /// The stand's (support mass's ground spring) kx, ky [N/m], if the support has one.
    pub stand: Option<(f64, f64)>,
}

fn stand_marks(scene: &Scene) -> Vec<StandMark> {
    scene
        .supports
        .iter()
        .map(|s| match &s.model {
            SupportModel::Rollers(r) => StandMark {
                spring: "contact",
                stand: Some((r.stand.spring.kx, r.stand.spring.ky)),
            },
            SupportModel::Linear(l) => StandMark {
                spring: "bearing",
                stand: l.mass.map(|(_, g)| (g.kx, g.ky)),
            },
        })
        .collect()
}

/// A mode's shape at the nodes: x and y as (re, im), largest translation 1.
pub type ShapeAtNodes = Vec<[f64; 4]>;

fn timed<T>(times: &mut Vec<(&'static str, f64)>, name: &'static str, f: impl FnOnce() -> T) -> T {
    let t0 = Instant::now();
    let out = f();
    times.push((name, t0.elapsed().as_secs_f64()));
    out
}

/// Runs the analyses of `req` on `sys` (module doc).
pub fn compute(
    req: &Request,
    scene: &Scene,
    model: &Model,
    sys: &LinearSystem,
) -> Result<Results, LinearError> {
    let mut times = Vec::new();
    let campbell = timed(&mut times, "campbell", || {
        sweep(sys, &req.speeds_hz, req.max_freq_hz)
    })?;
    let mut warnings = campbell.warnings.clone();
    let response = if req.response {
        let fc = match &req.unbalance {
            Some(u) => u.load(model),
            None => sys.unbalance.clone(),
        };
        let planes: Vec<_> = sys.sensors.iter().chain(&sys.named).cloned().collect();
        let values = timed(&mut times, "unbalance", || {
            req.speeds_hz
                .iter()
                .map(|s| plane_response(sys, TAU * s, &fc, &planes))
                .collect::<Result<Vec<_>, _>>()
        })?;
        let ns = sys.sensors.len();
        let sampled: Vec<Vec<f64>> = (0..ns)
            .map(|p| values.iter().map(|v| v[p].major()).collect())
            .collect();
        let critical: Vec<(f64, f64)> = campbell
            .critical
            .iter()
            .map(|c| (c.speed_hz, c.log_dec))
            .collect();
        let peaks = timed(&mut times, "peaks", || {
            if fc.iter().all(|x| *x == 0.0) {
                return Ok(Vec::new());
            }
            peaks(sys, &fc, &planes[..ns], &critical, &req.speeds_hz, &sampled)
        })?;
        Some(Response {
            planes: planes.into_iter().map(|p| p.0).collect(),
            sensors: ns,
            peaks,
            values,
            unbalance: req
                .unbalance
                .map_or_else(|| "scene".to_string(), |u| u.label()),
        })
    } else {
        None
    };
    let floquet = if req.floquet {
        let f = timed(&mut times, "floquet", || floquet(req, model, sys))?;
        for (s, g) in f.speeds_hz.iter().zip(&f.growth) {
            if !g.converged {
                warnings.push(format!(
                    "Floquet at {s} Hz: growth {:.3e} per revolution not converged at {} steps",
                    g.growth, g.steps
                ));
            }
        }
        Some(f)
    } else {
        None
    };
    let statics = req
        .statics
        .then(|| timed(&mut times, "static", || statics::solve(scene, model)));
    if let Some(Err(e)) = &statics {
        warnings.push(format!("static analysis: {e}"));
    }
    let map = if req.critical_map {
        let m = timed(&mut times, "critical_map", || {
            critical_map(sys, &map_stiffness(), req.speeds_hz.last().copied())
        })?;
        Some((m, scene.supports.iter().map(|s| s.node.clone()).collect()))
    } else {
        None
    };
    let shapes = req.shapes.then(|| {
        let (lateral, nb) = lateral_modes(&campbell);
        lateral
            .iter()
            .map(|l| {
                l[..nb]
                    .iter()
                    .map(|(_, m)| {
                        let (x, y) = node_shape(sys, m);
                        x.iter()
                            .zip(&y)
                            .map(|(x, y)| [x.re, x.im, y.re, y.im])
                            .collect()
                    })
                    .collect()
            })
            .collect()
    });
    Ok(Results {
        scene: scene.name.clone(),
        supported: sys.supported_hz()?,
        node_z: sys.node_z.clone(),
        campbell,
        response,
        floquet,
        statics,
        map,
        stands: stand_marks(scene),
        shapes,
        warnings,
        times,
    })
}

fn floquet(req: &Request, model: &Model, sys: &LinearSystem) -> Result<Floquet, LinearError> {
    let cutoff = req.floquet_cutoff_hz.unwrap_or(f64::INFINITY);
    let speeds_hz: Vec<f64> = req.speeds_hz.iter().copied().filter(|s| *s > 0.0).collect();
    if !speeds_hz.is_empty()
        && speeds_hz
            .iter()
            .all(|s| time_invariant(sys, &model.rotor, TAU * s))
    {
        return Ok(Floquet {
            speeds_hz: Vec::new(),
            growth: Vec::new(),
            ranges: Vec::new(),
            bands: Vec::new(),
            cutoff_hz: req.floquet_cutoff_hz,
            not_needed: Some(FLOQUET_NOT_NEEDED),
        });
    }
    // Speeds are independent: in parallel, collected in order (the same bytes on any pool).
    let growth = speeds_hz
        .par_iter()
        .map(|s| scene_growth(sys, TAU * s, cutoff))
        .collect::<Result<Vec<_>, _>>()?;
    // An unconverged speed counts as neither: it does not start or end a range.
    let values: Vec<f64> = growth.iter().map(|g| g.growth).collect();
    let ranges = if speeds_hz.len() >= 2 {
        let known: Vec<usize> = (0..speeds_hz.len())
            .filter(|&i| growth[i].converged)
            .collect();
        let s: Vec<f64> = known.iter().map(|&i| speeds_hz[i]).collect();
        let g: Vec<f64> = known.iter().map(|&i| values[i]).collect();
        unstable_ranges(&s, &g, |x| {
            scene_growth(sys, TAU * x, cutoff).map(|g| g.growth)
        })?
    } else {
        speeds_hz
            .iter()
            .zip(&growth)
            .filter(|(_, g)| g.converged && g.growth > UNSTABLE_GROWTH)
            .map(|(s, _)| [*s, *s])
            .collect()
    };
    let bands = ranges
        .iter()
        .map(|r| band(sys, *r, &speeds_hz, &values, cutoff))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Floquet {
        speeds_hz,
        growth,
        ranges,
        bands,
        cutoff_hz: req.floquet_cutoff_hz,
        not_needed: None,
    })
}

/// The band of an unstable range: its fastest-growing sampled speed (the middle when no sample
/// falls inside) and the modes there ([`band_modes`]).
fn band(
    sys: &LinearSystem,
    range_hz: [f64; 2],
    speeds_hz: &[f64],
    growth: &[f64],
    cutoff: f64,
) -> Result<Band, LinearError> {
    let at_hz = speeds_hz
        .iter()
        .zip(growth)
        .filter(|(s, _)| **s >= range_hz[0] && **s <= range_hz[1])
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0.5 * (range_hz[0] + range_hz[1]), |(s, _)| *s);
    let (growth_per_rev, modes) = band_modes(sys, TAU * at_hz, cutoff)?;
    let marginal = modes.iter().all(|m| m.damping_ratio.abs() < UNDAMPED_ZETA);
    Ok(Band {
        range_hz,
        growth_per_rev,
        at_hz,
        modes,
        class: if marginal { "marginal" } else { "unstable" },
    })
}

/// A band's modes as text: `axial 37.91 Hz ζ 0 (98 %)`.
pub fn band_modes_text(b: &Band) -> String {
    b.modes
        .iter()
        .map(|m| {
            format!(
                "{} {:.2} Hz ζ {:.2e} ({:.0} %)",
                m.kind,
                m.freq_hz,
                m.damping_ratio,
                100.0 * m.share
            )
        })
        .collect::<Vec<_>>()
        .join(" + ")
}

fn response_json(r: &Response, planes: std::ops::Range<usize>) -> Value {
    let mut out = Map::new();
    for i in planes {
        let col = |f: &dyn Fn(&SensorResponse) -> f64| -> Vec<f64> {
            r.values.iter().map(|s| f(&s[i])).collect()
        };
        out.insert(
            r.planes[i].clone(),
            json!({
                "vertical": {
                    "amplitude_um": col(&|s| 1e6 * s.vertical.norm()),
                    "phase_deg": col(&|s| s.vertical.arg().to_degrees()),
                },
                "horizontal": {
                    "amplitude_um": col(&|s| 1e6 * s.horizontal.norm()),
                    "phase_deg": col(&|s| s.horizontal.arg().to_degrees()),
                },
                "major_um": col(&|s| 1e6 * s.major()),
                "minor_um": col(&|s| 1e6 * s.minor()),
            }),
        );
    }
    Value::Object(out)
}

fn static_json(s: &Result<Static, String>) -> Value {
    let s = match s {
        Err(e) => return json!({ "error": e }),
        Ok(s) => s,
    };
    let mut sag = Map::new();
    for (name, d) in &s.sensors {
        sag.insert(
            name.clone(),
            json!({"vertical": 1e6 * d.y, "horizontal": 1e6 * d.x}),
        );
    }
    let mut journal = Map::new();
    let mut forces = Map::new();
    let mut contact = Map::new();
    for sp in &s.supports {
        journal.insert(
            sp.node.clone(),
            json!({"x": 1e6 * sp.journal.x, "y": 1e6 * sp.journal.y}),
        );
        forces.insert(sp.node.clone(), json!({"x": sp.force.x, "y": sp.force.y}));
        if !sp.contact.is_empty() {
            let m: Map<String, Value> = sp
                .contact
                .iter()
                .map(|(n, f)| (n.clone(), json!(f)))
                .collect();
            contact.insert(sp.node.clone(), Value::Object(m));
        }
    }
    json!({
        "sag_um": sag,
        "journal_um": journal,
        "support_forces_n": forces,
        "contact_forces_n": contact,
        "weight_n": s.weight,
    })
}

impl Results {
    /// The `rotorsweep linear --json` object (docs/linear.md; analyses not asked for are `null`, the
    /// lists of `unbalance_response` and `floquet.unstable_ranges_hz` empty, with the reason).
    pub fn to_json(&self, with_times: bool) -> Value {
        let c = &self.campbell;
        // Once for every speed: the lateral modes index the shapes.
        let (lateral, nb) = lateral_modes(c);
        let modes: Vec<Vec<Value>> = c
            .sets
            .iter()
            .enumerate()
            .map(|(s, set)| {
                let shape_of = |j: usize| -> Option<Value> {
                    let shapes = self.shapes.as_ref()?;
                    let k = lateral[s][..nb].iter().position(|(i, _)| *i == j)?;
                    let sh = &shapes[s][k];
                    let part = |p: usize| sh.iter().map(|v| v[p]).collect::<Vec<_>>();
                    Some(
                        json!({"x_re": part(0), "x_im": part(1), "y_re": part(2), "y_im": part(3)}),
                    )
                };
                set.modes
                    .iter()
                    .enumerate()
                    .map(|(j, m)| {
                        let mut v = json!({
                            "freq_hz": m.freq_hz,
                            "damping_ratio": m.damping_ratio,
                            "log_dec": m.log_dec,
                            "whirl": m.whirl.to_string(),
                            "kind": m.kind.to_string(),
                            "whirl_index": m.whirl_index,
                        });
                        if let Some(sh) = shape_of(j) {
                            v["shape"] = sh;
                        }
                        v
                    })
                    .collect()
            })
            .collect();
        let (response, response_nodes, unbalance) = match &self.response {
            Some(r) => (
                response_json(r, 0..r.sensors),
                response_json(r, r.sensors..r.planes.len()),
                json!(r.unbalance),
            ),
            None => (json!({}), json!({}), json!("not computed")),
        };
        let peaks: Vec<Value> = self
            .response
            .iter()
            .flat_map(|r| &r.peaks)
            .map(|p| {
                json!({
                    "sensor": p.plane, "critical_hz": p.critical_hz, "speed_hz": p.speed_hz,
                    "major_um": p.major_um, "sampled_um": p.sampled_um, "coarse": p.coarse,
                })
            })
            .collect();
        let floquet = match &self.floquet {
            Some(f) => {
                let frame = if let Some(why) = f.not_needed {
                    why
                } else if f.speeds_hz.is_empty() {
                    "not applicable at standstill (no revolution)"
                } else {
                    FLOQUET_FRAME
                };
                let bands: Vec<Value> = f
                    .bands
                    .iter()
                    .map(|b| {
                        json!({
                            "range_hz": b.range_hz,
                            "growth_per_rev": b.growth_per_rev,
                            "at_hz": b.at_hz,
                            "class": b.class,
                            "modes": b.modes.iter().map(|m| json!({
                                "freq_hz": m.freq_hz, "kind": m.kind,
                                "damping_ratio": m.damping_ratio, "share": m.share,
                            })).collect::<Vec<_>>(),
                        })
                    })
                    .collect();
                json!({
                    "unstable_ranges_hz": f.ranges,
                    "speeds_hz": f.speeds_hz,
                    "growth_per_rev": f.growth.iter().map(|g| g.growth).collect::<Vec<_>>(),
                    "steps_per_rev": f.growth.iter().map(|g| g.steps).collect::<Vec<_>>(),
                    "converged": f.growth.iter().map(|g| g.converged).collect::<Vec<_>>(),
                    "cutoff_hz": f.cutoff_hz,
                    "bands": bands,
                    "frame": frame,
                })
            }
            None => json!({"unstable_ranges_hz": [], "frame": "not computed"}),
        };
        let map = self.map.as_ref().map(|(m, nodes)| {
            json!({
                "stiffness_n_per_m": m.stiffness,
                "critical_speeds_hz": m.critical_hz,
                "actual_n_per_m": nodes.iter().zip(&m.actual).zip(&self.stands)
                    .map(|((n, k), st)| json!({
                        "node": n, "kx": k.0, "ky": k.1, "spring": st.spring,
                    })).collect::<Vec<_>>(),
                "stands_n_per_m": nodes.iter().zip(&self.stands)
                    .filter_map(|(n, st)| st.stand.map(|(kx, ky)| json!({
                        "node": n, "kx": kx, "ky": ky,
                    }))).collect::<Vec<_>>(),
            })
        });
        let mut out = json!({
            "scene": self.scene,
            "frame": FRAME_NOTE,
            "speeds_hz": c.speeds_hz,
            "modes": modes,
            "node_z_mm": self.node_z.iter().map(|z| 1e3 * z).collect::<Vec<_>>(),
            "supported_hz": {"vertical": self.supported.0, "horizontal": self.supported.1},
            "critical_speeds_hz": c.critical.iter().map(|x| x.speed_hz).collect::<Vec<_>>(),
            "critical_speeds": c.critical.iter().map(|x| json!({
                "speed_hz": x.speed_hz, "whirl": x.whirl.to_string(), "log_dec": x.log_dec
            })).collect::<Vec<_>>(),
            "stability_threshold_hz": c.threshold_hz,
            "unbalance": unbalance,
            "phase_convention": PHASE_NOTE,
            "unbalance_response": response,
            "unbalance_response_nodes": response_nodes,
            "unbalance_peaks": peaks,
            "floquet": floquet,
            "static": self.statics.as_ref().map(static_json),
            "critical_map": map,
            "warnings": self.warnings,
        });
        if with_times {
            let t: Map<String, Value> = self
                .times
                .iter()
                .map(|(k, v)| (k.to_string(), json!(v)))
                .collect();
            out["times_s"] = Value::Object(t);
        }
        out
    }
}
