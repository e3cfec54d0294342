//! `rotorsweep linear SCENE`: the linear rotordynamics of a scene (module doc of
//! [`rotorsweep::linear`]).
//!
//! In: a scene, `--speed-hz F` (that speed only) or `--speeds START:STOP:COUNT` [Hz] (default
//! 0:100:101), `--set KEY=VALUE`, `--modes`, `--max-freq-hz`, `--unbalance`, `--floquet-cutoff-hz`.
//! Out: tables, or with `--json` one object: `speeds_hz`; `modes` (per speed, ascending:
//! `{freq_hz, damping_ratio, log_dec, whirl, kind, whirl_index}`, damped frequency [Hz]);
//! with `--shapes` each mode's `shape` `{x_re, x_im, y_re, y_im}` at the nodes of `node_z_mm`;
//! `critical_speeds_hz` (and `critical_speeds` with whirl and log decrement);
//! `stability_threshold_hz` (null: stable over the range); `unbalance_response` per sensor
//! `{vertical|horizontal: {amplitude_um, phase_deg}, major_um, minor_um}` over `speeds_hz`
//! (phase of x(t) = A cos(θ + φ) against roll angle θ = 0, as the study analysis), and the same
//! at every named node in `unbalance_response_nodes`;
//! `floquet` `{unstable_ranges_hz, speeds_hz, growth_per_rev, cutoff_hz, frame}`; `static`
//! (sag per sensor [µm], journal positions [µm], support and contact forces [N]);
//! `critical_map` (undamped critical speeds against the supports' stiffness, actual marked);
//! `frame`, `phase_convention`, `warnings`, `times_s`. `-o OUT.h5` writes it as a study's
//! `/linear/<scene>` group (module doc of `src/study/campaign.rs`), extended by what `rotorsweep
//! report` and `scripts/plots.py` draw: per Campbell entry the damping ratio, log decrement,
//! whirl (code) and branch; the critical speeds' whirl and log decrement; the unbalance
//! response; Floquet growth and ranges; the static sag; the critical-speed map; with `--shapes`
//! the mode shapes at the nodes [speeds × modes × nodes] (README, `rotorsweep linear`).

use std::path::PathBuf;
use std::time::Instant;

use nalgebra::DVector;
use ndarray::Array3;
use rotorsweep::linear::campbell::{sweep, CampbellData};
use rotorsweep::linear::floquet::{growth_per_rev, scene_multipliers, unstable_ranges};
use rotorsweep::linear::map::{critical_map, CriticalMap};
use rotorsweep::linear::modes::{node_shape, Kind};
use rotorsweep::linear::response::{plane_response, point_unbalance, SensorResponse};
use rotorsweep::linear::statics::{self, Static};
use rotorsweep::linear::{LinearSystem, FRAME_NOTE};
use rotorsweep::model::Model;
use rotorsweep::scene::Scene;
use rotorsweep::store;
use serde::Serialize;
use serde_json::{json, Map, Value};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The phase convention of `unbalance_response`.
const PHASE_NOTE: &str = "x(t) = A cos(θ + φ), θ = Ω t the roll angle: φ against roll angle 0, \
as the study analysis's lines (/analysis/lines)";

/// Arguments of `rotorsweep linear`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// One spin speed [Hz]: only this speed is solved.
    #[arg(long, conflicts_with = "speeds")]
    speed_hz: Option<f64>,
    /// Spin speeds START:STOP:COUNT [Hz] (default 0:100:101).
    #[arg(long)]
    speeds: Option<String>,
    /// Override a scene value, `--set roll.shell.elements=60` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Modes to keep, "30n+12st" or a list "0-4,7" (default: the scene's).
    #[arg(long)]
    modes: Option<String>,
    /// List modes up to this damped frequency [Hz] (default: all).
    #[arg(long)]
    max_freq_hz: Option<f64>,
    /// An unbalance MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM instead of the scene's own.
    #[arg(long)]
    unbalance: Option<String>,
    /// Floquet: keep only the modes below this frequency [Hz] (default: all; see
    /// `linear::floquet` before cutting).
    #[arg(long)]
    floquet_cutoff_hz: Option<f64>,
    /// Add each mode's complex shape at the nodes to the JSON (`shape`, nodes at `node_z_mm`).
    #[arg(long)]
    shapes: bool,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    json: bool,
    /// Write the results to this HDF5 file (a study's `/linear` layout).
    #[arg(short = 'o', long)]
    output: Option<PathBuf>,
    /// Replace an existing output file (only a rotorsweep results file).
    #[arg(long, requires = "output")]
    overwrite: bool,
}

fn parse_speeds(a: &Args) -> Result<Vec<f64>, String> {
    if let Some(f) = a.speed_hz {
        if !(f.is_finite() && f >= 0.0) {
            return Err("--speed-hz must be zero or positive".into());
        }
        return Ok(vec![f]);
    }
    let text = a.speeds.as_deref().unwrap_or("0:100:101");
    let bad = || format!("--speeds `{text}`: expected START:STOP:COUNT, e.g. 0:100:101");
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
    Ok((0..count)
        .map(|i| start + (stop - start) * i as f64 / (count - 1) as f64)
        .collect())
}

fn parse_unbalance(model: &Model, text: &str) -> Result<DVector<f64>, String> {
    let bad = || format!("--unbalance `{text}`: expected MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM");
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    if v.len() != 4 || v.iter().any(|x| !x.is_finite()) {
        return Err(bad());
    }
    Ok(point_unbalance(
        model,
        1e-3 * v[0],
        1e-3 * v[1],
        v[2].to_radians(),
        1e-3 * v[3],
    ))
}

#[derive(Serialize)]
struct ModeOut {
    freq_hz: f64,
    damping_ratio: f64,
    log_dec: f64,
    whirl: String,
    kind: String,
    whirl_index: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    shape: Option<ShapeOut>,
}

/// A mode's shape at the nodes of `node_z_mm`, largest translation 1.
#[derive(Serialize)]
struct ShapeOut {
    x_re: Vec<f64>,
    x_im: Vec<f64>,
    y_re: Vec<f64>,
    y_im: Vec<f64>,
}

/// Every result, computed once.
struct Results {
    campbell: CampbellData,
    responses: Vec<Vec<SensorResponse>>,
    floquet_speeds: Vec<f64>,
    floquet_growth: Vec<f64>,
    floquet_ranges: Vec<[f64; 2]>,
    statics: Result<Static, String>,
    supported: (Vec<f64>, Vec<f64>),
    times: Map<String, Value>,
}

fn compute(a: &Args, scene: &Scene, model: &Model, sys: &LinearSystem) -> Result<Results, String> {
    let speeds = parse_speeds(a)?;
    let fc = match &a.unbalance {
        Some(t) => parse_unbalance(model, t)?,
        None => sys.unbalance.clone(),
    };
    let mut times = Map::new();
    let t0 = Instant::now();
    let campbell = sweep(sys, &speeds, a.max_freq_hz).map_err(|e| e.to_string())?;
    times.insert("campbell".into(), json!(t0.elapsed().as_secs_f64()));
    let t0 = Instant::now();
    let planes: Vec<_> = sys.sensors.iter().chain(&sys.named).cloned().collect();
    let responses = speeds
        .iter()
        .map(|s| plane_response(sys, TAU * s, &fc, &planes))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    times.insert("unbalance".into(), json!(t0.elapsed().as_secs_f64()));
    let t0 = Instant::now();
    let floquet_speeds: Vec<f64> = speeds.iter().copied().filter(|s| *s > 0.0).collect();
    let eval = |s: f64| {
        scene_multipliers(sys, TAU * s, a.floquet_cutoff_hz.unwrap_or(f64::INFINITY))
            .map(|mu| growth_per_rev(&mu))
    };
    let floquet_growth = floquet_speeds
        .iter()
        .map(|s| eval(*s))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let floquet_ranges = if floquet_speeds.len() >= 2 {
        unstable_ranges(&floquet_speeds, &floquet_growth, eval).map_err(|e| e.to_string())?
    } else {
        floquet_speeds
            .iter()
            .zip(&floquet_growth)
            .filter(|(_, g)| **g > rotorsweep::linear::floquet::UNSTABLE_GROWTH)
            .map(|(s, _)| [*s, *s])
            .collect()
    };
    times.insert("floquet".into(), json!(t0.elapsed().as_secs_f64()));
    let t0 = Instant::now();
    let statics = statics::solve(scene, model);
    times.insert("static".into(), json!(t0.elapsed().as_secs_f64()));
    let supported = sys.supported_hz().map_err(|e| e.to_string())?;
    Ok(Results {
        campbell,
        responses,
        floquet_speeds,
        floquet_growth,
        floquet_ranges,
        statics,
        supported,
        times,
    })
}

fn modes_json(sys: &LinearSystem, r: &Results, shapes: bool) -> Vec<Vec<ModeOut>> {
    r.campbell
        .sets
        .iter()
        .map(|s| {
            s.modes
                .iter()
                .map(|m| ModeOut {
                    freq_hz: m.freq_hz,
                    damping_ratio: m.damping_ratio,
                    log_dec: m.log_dec,
                    whirl: m.whirl.to_string(),
                    kind: m.kind.to_string(),
                    whirl_index: m.whirl_index,
                    shape: shapes.then(|| {
                        let (x, y) = node_shape(sys, m);
                        ShapeOut {
                            x_re: x.iter().map(|z| z.re).collect(),
                            x_im: x.iter().map(|z| z.im).collect(),
                            y_re: y.iter().map(|z| z.re).collect(),
                            y_im: y.iter().map(|z| z.im).collect(),
                        }
                    }),
                })
                .collect()
        })
        .collect()
}

/// The responses at `names`, which sit from column `offset` on in each speed's responses.
fn response_json(names: &[(String, nalgebra::DMatrix<f64>)], offset: usize, r: &Results) -> Value {
    let mut out = Map::new();
    for (j, (name, _)) in names.iter().enumerate() {
        let i = offset + j;
        let col = |f: &dyn Fn(&SensorResponse) -> f64| -> Vec<f64> {
            r.responses.iter().map(|s| f(&s[i])).collect()
        };
        out.insert(
            name.clone(),
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

fn static_json(r: &Results) -> Value {
    match &r.statics {
        Err(e) => json!({ "error": e }),
        Ok(s) => {
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
    }
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), Box<dyn std::error::Error>> {
    if a.floquet_cutoff_hz
        .is_some_and(|c| !(c.is_finite() && c > 0.0))
    {
        return Err("--floquet-cutoff-hz must be positive".into());
    }
    let (scene, model) = crate::modes::load_model(&a.scene, &a.set, a.modes.as_deref())?;
    // The output is claimed before the work (store::output): one writer, nothing replaced
    // that is not a rotorsweep results file.
    let _lock = a
        .output
        .as_deref()
        .map(|p| store::output::claim(p, a.overwrite))
        .transpose()?;
    let sys = LinearSystem::of_scene(&scene, &model).map_err(|e| {
        rotorsweep::error::InputError::new(&a.scene, format!("linear analysis: {e}"))
    })?;
    let r = compute(a, &scene, &model, &sys)?;
    let c = &r.campbell;
    let stiff: Vec<f64> = (0..=24)
        .map(|i| 10f64.powf(5.0 + 0.25 * i as f64))
        .collect();
    let map = critical_map(&sys, &stiff)?;
    let mut warnings = c.warnings.clone();
    if let Err(e) = &r.statics {
        warnings.push(format!("static analysis: {e}"));
    }
    let floquet_note = if r.floquet_speeds.is_empty() {
        "not applicable at standstill (no revolution)"
    } else {
        "body frame, supports turning backwards: exact for the asymmetric rotor on anisotropic \
         supports; modes below cutoff_hz (null: all)"
    };
    let out = json!({
        "scene": scene.name,
        "frame": FRAME_NOTE,
        "speeds_hz": c.speeds_hz,
        "modes": modes_json(&sys, &r, a.shapes),
        "node_z_mm": sys.node_z.iter().map(|z| 1e3 * z).collect::<Vec<_>>(),
        "supported_hz": {"vertical": r.supported.0, "horizontal": r.supported.1},
        "critical_speeds_hz": c.critical.iter().map(|x| x.speed_hz).collect::<Vec<_>>(),
        "critical_speeds": c.critical.iter().map(|x| json!({
            "speed_hz": x.speed_hz, "whirl": x.whirl.to_string(), "log_dec": x.log_dec
        })).collect::<Vec<_>>(),
        "stability_threshold_hz": c.threshold_hz,
        "unbalance": a.unbalance.clone().unwrap_or_else(|| "scene".into()),
        "phase_convention": PHASE_NOTE,
        "unbalance_response": response_json(&sys.sensors, 0, &r),
        "unbalance_response_nodes": response_json(&sys.named, sys.sensors.len(), &r),
        "floquet": {
            "unstable_ranges_hz": r.floquet_ranges,
            "speeds_hz": r.floquet_speeds,
            "growth_per_rev": r.floquet_growth,
            "cutoff_hz": a.floquet_cutoff_hz,
            "frame": floquet_note,
        },
        "static": static_json(&r),
        "critical_map": {
            "stiffness_n_per_m": map.stiffness,
            "critical_speeds_hz": map.critical_hz,
            "actual_n_per_m": scene.supports.iter().zip(&map.actual).map(|(s, k)| json!({
                "node": s.node, "kx": k.0, "ky": k.1
            })).collect::<Vec<_>>(),
        },
        "warnings": warnings,
        "times_s": r.times,
    });
    if let Some(path) = &a.output {
        if let Err(e) = write_h5(path, &scene, &sys, &out, &r, &map, a.shapes) {
            let _ = std::fs::remove_file(store::with_suffix(path, ".tmp"));
            return Err(store::output::OutputError::Write(path.clone(), e.to_string()).into());
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        print_tables(&sys, &out, &r);
    }
    Ok(())
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect())
        .unwrap_or_default()
}

fn print_tables(sys: &LinearSystem, out: &Value, r: &Results) {
    println!(
        "scene {}: linear analysis",
        out["scene"].as_str().unwrap_or("")
    );
    println!("({})", FRAME_NOTE);
    println!("\nlowest lateral modes per speed: damped frequency [Hz] / log dec / whirl");
    for (s, set) in r.campbell.speeds_hz.iter().zip(&r.campbell.sets) {
        let row: Vec<String> = set
            .modes
            .iter()
            .filter(|m| m.kind == Kind::Lateral)
            .take(6)
            .map(|m| {
                format!(
                    "{:8.3} {:+.4} {:<8}",
                    m.freq_hz,
                    m.log_dec,
                    m.whirl.to_string()
                )
            })
            .collect();
        println!("  {s:7.2} Hz: {}", row.join(" | "));
    }
    let crit: Vec<String> = r
        .campbell
        .critical
        .iter()
        .map(|c| format!("{:.3} ({})", c.speed_hz, c.whirl))
        .collect();
    println!("\ncritical speeds [Hz]: {}", crit.join(", "));
    match r.campbell.threshold_hz {
        Some(t) => println!("stability threshold: {t:.4} Hz"),
        None => println!("stability threshold: none (stable over the range)"),
    }
    println!("\nunbalance response ({PHASE_NOTE}): amplitude [µm] ∠ phase [°]");
    for (i, (name, _)) in sys.sensors.iter().enumerate() {
        println!("  {name}:");
        for (s, resp) in r.campbell.speeds_hz.iter().zip(&r.responses) {
            let x = resp[i];
            println!(
                "    {s:7.2} Hz: vertical {:9.3} ∠ {:7.2}, horizontal {:9.3} ∠ {:7.2}",
                1e6 * x.vertical.norm(),
                x.vertical.arg().to_degrees(),
                1e6 * x.horizontal.norm(),
                x.horizontal.arg().to_degrees()
            );
        }
    }
    let ranges: Vec<String> = r
        .floquet_ranges
        .iter()
        .map(|[a, b]| format!("{a:.4}–{b:.4} Hz"))
        .collect();
    println!(
        "\nFloquet (body frame): unstable {}",
        if ranges.is_empty() {
            "nowhere in the range".to_string()
        } else {
            ranges.join(", ")
        }
    );
    match &r.statics {
        Ok(s) => {
            println!("\nstatic sag under gravity [µm] (vertical / horizontal):");
            for (name, d) in &s.sensors {
                println!("  {name}: {:.2} / {:.2}", 1e6 * d.y, 1e6 * d.x);
            }
            println!(
                "support forces on the journals [N] (x / y), weight {:.1} N:",
                s.weight
            );
            for sp in &s.supports {
                let contact: Vec<String> = sp
                    .contact
                    .iter()
                    .map(|(n, f)| format!("{n} {f:.1}"))
                    .collect();
                println!(
                    "  {}: {:.1} / {:.1}{}",
                    sp.node,
                    sp.force.x,
                    sp.force.y,
                    if contact.is_empty() {
                        String::new()
                    } else {
                        format!(" (rollers: {})", contact.join(", "))
                    }
                );
            }
        }
        Err(e) => println!("\nstatic analysis: {e}"),
    }
    for w in out["warnings"].as_array().into_iter().flatten() {
        println!("warning: {}", w.as_str().unwrap_or(""));
    }
}

/// How `campbell/whirl` codes a mode's whirl (its `codes` attribute).
/// A 3-D float dataset `data` under `group` with a `units` attribute (deflated).
fn dataset_3d(
    group: &hdf5::Group,
    name: &str,
    data: &Array3<f64>,
    units: &str,
) -> hdf5::Result<()> {
    let mut b = group.new_dataset_builder();
    if !data.is_empty() {
        b = b.chunk(data.dim()).shuffle().deflate(4);
    }
    let ds = b.with_data(data.view()).create(name)?;
    store::attr_str(&ds, "units", units)
}

/// Writes `/linear/<scene>` (module doc; the `--shapes` group only with `shapes`).
fn write_h5(
    path: &std::path::Path,
    scene: &Scene,
    sys: &LinearSystem,
    out: &Value,
    r: &Results,
    map: &CriticalMap,
    shapes: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(&scene.source).unwrap_or_default();
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let (file, jobs) = store::create_file(path, &command, &text)?;
    let g = store::subgroup(&file, &format!("linear/{}", scene.name))?;
    store::attr_str(&g, "frame", FRAME_NOTE)?;
    store::attr_str(&g, "phase_convention", PHASE_NOTE)?;
    let first = |v: &[f64]| v.first().copied().unwrap_or(f64::NAN);
    store::attr_f64(&g, "vertical_hz", first(&r.supported.0))?;
    store::attr_f64(&g, "horizontal_hz", first(&r.supported.1))?;
    rotorsweep::linear::campbell::write(&g, &r.campbell)?;
    let (lateral, nb) = rotorsweep::linear::campbell::lateral_modes(&r.campbell);
    let ns = r.campbell.speeds_hz.len();
    for (sensor, v) in out["unbalance_response"].as_object().into_iter().flatten() {
        for dir in ["vertical", "horizontal"] {
            let p = format!("unbalance_response/{sensor}/{dir}");
            store::dataset(
                &g,
                &format!("{p}/amplitude_um"),
                &f64s(&v[dir]["amplitude_um"]),
                "um",
            )?;
            store::dataset(
                &g,
                &format!("{p}/phase_deg"),
                &f64s(&v[dir]["phase_deg"]),
                "deg",
            )?;
        }
    }
    store::dataset(&g, "floquet/speed_hz", &r.floquet_speeds, "Hz")?;
    store::dataset(&g, "floquet/growth_per_rev", &r.floquet_growth, "1")?;
    store::scales::attach_axis(&g.group("floquet")?, "speed_hz", &["growth_per_rev"], 0)?;
    let flat_ranges: Vec<f64> = r.floquet_ranges.iter().flatten().copied().collect();
    store::dataset_2d(
        &g,
        "floquet/unstable_ranges_hz",
        (r.floquet_ranges.len(), 2),
        &flat_ranges,
        "Hz",
    )?;
    if let Ok(s) = &r.statics {
        let names: Vec<String> = s.sensors.iter().map(|x| x.0.clone()).collect();
        store::string_dataset(&g, "static/sensors", &names)?;
        let v: Vec<f64> = s.sensors.iter().map(|x| 1e6 * x.1.y).collect();
        let h: Vec<f64> = s.sensors.iter().map(|x| 1e6 * x.1.x).collect();
        store::dataset(&g, "static/sag_vertical_um", &v, "um")?;
        store::dataset(&g, "static/sag_horizontal_um", &h, "um")?;
    }
    // The critical-speed map, NaN-padded to the most critical speeds of any stiffness.
    let width = map.critical_hz.iter().map(Vec::len).max().unwrap_or(0);
    let padded: Vec<f64> = map
        .critical_hz
        .iter()
        .flat_map(|row| (0..width).map(|i| row.get(i).copied().unwrap_or(f64::NAN)))
        .collect();
    store::dataset(&g, "critical_map/stiffness_n_per_m", &map.stiffness, "N/m")?;
    store::dataset_2d(
        &g,
        "critical_map/critical_speeds_hz",
        (map.stiffness.len(), width),
        &padded,
        "Hz",
    )?;
    let kx: Vec<f64> = map.actual.iter().map(|k| k.0).collect();
    let ky: Vec<f64> = map.actual.iter().map(|k| k.1).collect();
    store::dataset(&g, "critical_map/actual_kx_n_per_m", &kx, "N/m")?;
    store::dataset(&g, "critical_map/actual_ky_n_per_m", &ky, "N/m")?;
    let nodes: Vec<String> = scene.supports.iter().map(|s| s.node.clone()).collect();
    store::string_dataset(
        &store::subgroup(&g, "critical_map")?,
        "support_nodes",
        &nodes,
    )?;
    if shapes {
        let sg = store::subgroup(&g, "shapes")?;
        let z: Vec<f64> = sys.node_z.iter().map(|z| 1e3 * z).collect();
        store::dataset(&sg, "node_z_mm", &z, "mm")?;
        let nn = z.len();
        let mut parts: [Array3<f64>; 4] = std::array::from_fn(|_| Array3::zeros((ns, nb, nn)));
        for (s, l) in lateral.iter().enumerate() {
            for (k, (_, m)) in l[..nb].iter().enumerate() {
                let (x, y) = node_shape(sys, m);
                for n in 0..nn {
                    let v = [x[n].re, x[n].im, y[n].re, y[n].im];
                    for (p, value) in parts.iter_mut().zip(v) {
                        p[(s, k, n)] = value;
                    }
                }
            }
        }
        for (name, p) in ["x_re", "x_im", "y_re", "y_im"].iter().zip(&parts) {
            dataset_3d(&sg, name, p, "1")?;
        }
    }
    store::attr_str(&g, "json", &out.to_string())?;
    store::finish_file(path, file, jobs)?;
    Ok(())
}
