//! `rotorsweep linear SCENE`: the linear rotordynamics of a scene (module doc of
//! [`rotorsweep::linear`]).
//!
//! In: a scene, `--speed-hz F` (that speed only) or `--speeds START:STOP:COUNT` [Hz] (default
//! 0:100:101; with a trailing `rpm` in rev/min), `--set KEY=VALUE`, `--modes`, `--max-freq-hz`,
//! `--unbalance`, `--floquet-cutoff-hz`, `--no-floquet`. A machine file (several rolls in nips)
//! gets the coupled analysis of [`rotorsweep::linear::machine`] with the same JSON keys for what
//! it has (`speeds_hz`, `modes` with `roll` and `energy_share` added, `critical_speeds_hz`,
//! `stability_threshold_hz`, `static` with `sag_um` per `roll.sensor` and `nips`, `frame`,
//! `warnings`) plus `rolls`; no `-o`.
//! Out: tables, or with `--json` one object: `speeds_hz`; `modes` (per speed, ascending:
//! `{freq_hz, damping_ratio, log_dec, whirl, kind, whirl_index}`, damped frequency [Hz]);
//! with `--shapes` each mode's `shape` `{x_re, x_im, y_re, y_im}` at the nodes of `node_z_mm`;
//! `critical_speeds_hz` (and `critical_speeds` with whirl and log decrement);
//! `stability_threshold_hz` (null: stable over the range); `unbalance_response` per sensor
//! `{vertical|horizontal: {amplitude_um, phase_deg}, major_um, minor_um}` over `speeds_hz`
//! (phase of x(t) = A cos(θ + φ) against roll angle θ = 0, as the study analysis), and the same
//! at every named node in `unbalance_response_nodes`;
//! `floquet` `{unstable_ranges_hz, speeds_hz, growth_per_rev, cutoff_hz, bands, frame}` (not
//! run with `--no-floquet`, nor where it cannot differ from the damped modes: an axisymmetric
//! rotor on isotropic supports; each band with its growth per revolution, the modes that combine
//! and its class, `marginal` or `unstable`); `static`
//! (sag per sensor [µm], journal positions [µm], support and contact forces [N]);
//! `critical_map` (undamped critical speeds against the supports' stiffness, actual marked);
//! `frame`, `phase_convention`, `warnings`, `times_s`. `-o OUT.h5` writes it
//! ([`rotorsweep::results::linear_file`]) as a study's `/linear/<scene>` group (module doc of
//! `src/study/run/assemble.rs`), extended by what `rotorsweep
//! report` and `scripts/plots.py` draw: per Campbell entry the damping ratio, log decrement,
//! whirl (code) and branch; the critical speeds' whirl and log decrement; the unbalance
//! response; Floquet growth and ranges; the static sag; the critical-speed map; with `--shapes`
//! the mode shapes at the nodes [speeds × modes × nodes] (docs/results.md, "Linear groups").

use std::path::PathBuf;

use rotorsweep::dynamics::model::Model;
use rotorsweep::error::InputError;
use rotorsweep::linear::machine::{MachineLinear, MACHINE_FRAME_NOTE};
use rotorsweep::linear::modes::Kind;
use rotorsweep::linear::request::{self, PointUnbalance, Request, Results, PHASE_NOTE};
use rotorsweep::linear::scene_system::{in_scene, scene_system};
use rotorsweep::linear::FRAME_NOTE;
use rotorsweep::results::linear_file;
use rotorsweep::scene::{Machine, NipLaw, Scene};
use rotorsweep::store;

use crate::error::CliError;
use crate::speeds;

/// Arguments of `rotorsweep linear`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// One spin speed [Hz]: only this speed is solved.
    #[arg(long, conflicts_with = "speeds")]
    speed_hz: Option<f64>,
    /// Spin speeds START:STOP:COUNT [Hz] (default 0:100:101), or in rev/min with a trailing
    /// `rpm` ("0:6000:101 rpm").
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
    /// Leave out the Floquet analysis (the costliest; the damped modes' stability threshold
    /// stays).
    #[arg(long, conflicts_with = "floquet_cutoff_hz")]
    no_floquet: bool,
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

fn request(a: &Args) -> Result<Request, String> {
    if a.floquet_cutoff_hz
        .is_some_and(|c| !(c.is_finite() && c > 0.0))
    {
        return Err("--floquet-cutoff-hz must be positive".into());
    }
    let speeds_hz = match a.speed_hz {
        Some(f) => vec![speeds::hz("speed-hz", f)?],
        None => speeds::sweep(a.speeds.as_deref().unwrap_or("0:100:101"))?,
    };
    Ok(Request {
        speeds_hz,
        max_freq_hz: a.max_freq_hz,
        unbalance: a
            .unbalance
            .as_deref()
            .map(PointUnbalance::parse)
            .transpose()
            .map_err(|e| format!("--{e}"))?,
        response: true,
        floquet: !a.no_floquet,
        floquet_cutoff_hz: a.floquet_cutoff_hz,
        statics: true,
        critical_map: true,
        shapes: a.shapes,
    })
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), CliError> {
    let req = request(a).map_err(CliError::input)?;
    let (scene, model) = Model::load(&a.scene, &a.set, a.modes.as_deref())?;
    if let Some(m) = &scene.machine {
        return machine(a, &req, &scene, m, &model);
    }
    // The output is claimed before the work (store::output): one writer, nothing replaced
    // that is not a rotorsweep results file.
    let _lock = a
        .output
        .as_deref()
        .map(|p| store::output::claim(p, a.overwrite))
        .transpose()?;
    let sys = scene_system(&scene, &model)?;
    let r = request::compute(&req, &scene, &model, &sys).map_err(in_scene(&scene))?;
    if let Some(path) = &a.output {
        let command = std::env::args().collect::<Vec<_>>().join(" ");
        linear_file::write(path, &scene, &r, &command)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&r.to_json(true))?);
    } else {
        print_tables(&r);
    }
    Ok(())
}

/// A machine file: its rolls coupled by their nips ([`rotorsweep::linear::machine`]); the
/// one-roll analyses (unbalance response, Floquet, critical-speed map, shapes, HDF5) are not
/// run on a machine, a warning says so.
fn machine(
    a: &Args,
    req: &Request,
    scene: &Scene,
    m: &Machine,
    first: &Model,
) -> Result<(), CliError> {
    if a.output.is_some() {
        return Err(CliError::input(
            "-o: the linear analysis of a machine (several rolls) is printed only (--json); \
             its HDF5 layout is not defined",
        ));
    }
    let lin = MachineLinear::new(m, first)
        .map_err(|e| InputError::new(&scene.source, format!("linear analysis: {e}")))?;
    let mut json = lin
        .to_json(&scene.name, &req.speeds_hz)
        .map_err(|e| InputError::new(&scene.source, format!("linear analysis: {e}")))?;
    let mut warnings = Vec::new();
    if a.unbalance.is_some() || a.floquet_cutoff_hz.is_some() || a.shapes {
        warnings.push(
            "--unbalance, --floquet-cutoff-hz and --shapes apply to one roll; a machine's \
             analysis has the static equilibrium and the damped modes only"
                .to_string(),
        );
    }
    // Which equilibrium a viscoelastic cover is linearised at: the standstill one, relaxed.
    for n in &m.nips {
        if matches!(n.law, NipLaw::Viscoelastic { .. }) {
            warnings.push(format!(
                "nip `{}` has a viscoelastic cover: linearised at the standstill equilibrium \
                 with its relaxed modulus at every speed; rolling, the cover is stiffer \
                 (`rotorsweep barring` linearises at the rolling equilibrium)",
                n.name
            ));
        }
    }
    json["warnings"] = serde_json::json!(warnings);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
        return Ok(());
    }
    println!(
        "machine {}: linear analysis of the coupled rolls",
        scene.name
    );
    println!("({MACHINE_FRAME_NOTE})");
    for (name, f) in lin.rolls() {
        println!("  roll {name}: speed {f:+.4} × the first roll's");
    }
    println!("\nstatic deflection at the sensors [µm] (vertical / horizontal):");
    for (roll, s, x, y) in &lin.sag {
        println!("  {roll}.{s}: {:.2} / {:.2}", 1e6 * y, 1e6 * x);
    }
    for n in &lin.nips {
        let total: f64 = n.segments.iter().map(|s| s.force).sum();
        println!("\nnip {}: {total:.1} N over {} segments", n.name, n.z.len());
        for (z, s) in n.z.iter().zip(&n.segments) {
            println!(
                "  z {:8.1} mm: force {:10.2} N, penetration {:8.3} µm, stiffness {:.4e} N/m",
                1e3 * z,
                s.force,
                1e6 * s.delta,
                s.stiffness
            );
        }
    }
    println!("\nlowest modes per speed of the first roll: damped frequency [Hz] / log dec / whirl / roll");
    let modes = json["modes"].as_array().cloned().unwrap_or_default();
    for (s, set) in req.speeds_hz.iter().zip(&modes) {
        let row: Vec<String> = (set.as_array().into_iter().flatten())
            .filter(|m| m["kind"] == "lateral")
            .take(6)
            .map(|m| {
                format!(
                    "{:8.3} {:+.4} {:<8} {}",
                    m["freq_hz"].as_f64().unwrap_or(f64::NAN),
                    m["log_dec"].as_f64().unwrap_or(f64::NAN),
                    m["whirl"].as_str().unwrap_or(""),
                    m["roll"].as_str().unwrap_or("")
                )
            })
            .collect();
        println!("  {}: {}", speeds::with_rpm(*s), row.join(" | "));
    }
    match json["stability_threshold_hz"].as_f64() {
        Some(t) => println!("stability threshold: {t:.4} Hz"),
        None => println!("stability threshold: none (stable over the range)"),
    }
    for w in warnings {
        println!("warning: {w}");
    }
    Ok(())
}

fn print_tables(r: &Results) {
    println!("scene {}: linear analysis", r.scene);
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
        println!("  {}: {}", speeds::with_rpm(*s), row.join(" | "));
    }
    let crit: Vec<String> = r
        .campbell
        .critical
        .iter()
        .map(|c| {
            format!(
                "{:.3} ({}, {:.1} rpm)",
                c.speed_hz,
                c.whirl,
                60.0 * c.speed_hz
            )
        })
        .collect();
    println!("\ncritical speeds [Hz]: {}", crit.join(", "));
    match r.campbell.threshold_hz {
        Some(t) => println!("stability threshold: {t:.4} Hz"),
        None => println!("stability threshold: none (stable over the range)"),
    }
    if let Some(resp) = &r.response {
        print_response(resp, &r.campbell.speeds_hz);
        print_peaks(resp);
    }
    if let Some(f) = &r.floquet {
        if let Some(why) = f.not_needed {
            println!("\nFloquet (body frame): {why}");
        } else if f.bands.is_empty() {
            println!("\nFloquet (body frame): unstable nowhere in the range");
        } else {
            println!("\nFloquet (body frame):");
            for b in &f.bands {
                println!(
                    "  {} {:.4}–{:.4} Hz: growth {:.3e} per revolution at {:.4} Hz; modes {}",
                    b.class,
                    b.range_hz[0],
                    b.range_hz[1],
                    b.growth_per_rev,
                    b.at_hz,
                    request::band_modes_text(b)
                );
            }
        }
    }
    match &r.statics {
        Some(Ok(s)) => {
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
        Some(Err(e)) => println!("\nstatic analysis: {e}"),
        None => {}
    }
    for w in &r.warnings {
        println!("warning: {w}");
    }
}

fn print_peaks(r: &request::Response) {
    if r.peaks.is_empty() {
        return;
    }
    println!("\nresponse peaks near the critical speeds (orbit major semi-axis, refined):");
    for p in &r.peaks {
        println!(
            "  {} at {:.4} Hz (critical {:.4} Hz): {:.3} µm; the sweep shows {:.3} µm{}",
            p.plane,
            p.speed_hz,
            p.critical_hz,
            p.major_um,
            p.sampled_um,
            if p.coarse {
                " — coarse: the sweep misses this peak"
            } else {
                ""
            }
        );
    }
}

fn print_response(r: &request::Response, speeds_hz: &[f64]) {
    println!("\nunbalance response ({PHASE_NOTE}): amplitude [µm] ∠ phase [°]");
    for (i, name) in r.planes.iter().enumerate().take(r.sensors) {
        println!("  {name}:");
        for (s, resp) in speeds_hz.iter().zip(&r.values) {
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
}
