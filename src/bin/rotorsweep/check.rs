//! `rotorsweep check SCENE|STUDY [--set KEY=VALUE]...`: what a file really asks for.
//!
//! In: a scene file (with `--set` overrides) or a study file.
//! Out, on stdout: for a scene, the files read (the scene and the scenes it `extends`), the
//! effective scene after `extends` and the overrides as TOML (units in the key names), and what
//! is derived from it: the axial positions of the named nodes, balancing planes and masses in mm
//! (relative positions resolved), the wall (uniform, or the map's statistics), the speed and the
//! record, each rollers support's contact law (as written, or fitted to its geometry: the
//! geometry, the fit's loads and how far the law lies from the Roark relation), warnings for
//! geometry that loads but is unlikely (a wall under 1 % of its diameter, a shell lighter than
//! the roll's ends), and, unless `--no-model`, the model: mass, mesh, reduced size, balancing
//! masses and the first undamped frequencies on the linearised supports at standstill (vertical,
//! horizontal), as `rotorsweep modes` computes them. For a study: its jobs, models and
//! references, the values of every swept key, then the first job's scene (the study's `[set]`
//! and `[budget]` with that job's swept values) as above. Errors as in every command (exit 1
//! names the file, line and key).
//!
//! The values come from the library ([`rotorsweep::study::overview`],
//! [`rotorsweep::dynamics::derived`], [`rotorsweep::dynamics::summary`],
//! [`rotorsweep::linear::overview::SupportedHz`]); this file prints each part as soon as it is
//! known, so what precedes a failing model build or linearisation is still shown.

use std::path::{Path, PathBuf};

use rotorsweep::dynamics::derived::{Contact, Derived, Positions, Speed, Wall};
use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::summary::ModelSummary;
use rotorsweep::error::InputError;
use rotorsweep::linear::overview::SupportedHz;
use rotorsweep::scene::source::Source;
use rotorsweep::scene::{plausibility, with_overrides, Machine, NipLaw, Scene};
use rotorsweep::study::Study;

use crate::error::CliError;
use crate::modes::list;

/// Arguments of `rotorsweep check`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene or study file (TOML).
    file: PathBuf,
    /// Override a scene value, `--set roll.shell.elements=60` (repeatable; scenes only: a
    /// study's overrides are its [set] and axes).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Read and validate only: no model, mass or frequencies (faster).
    #[arg(long)]
    no_model: bool,
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), CliError> {
    let text = rotorsweep::error::read_text(&a.file)
        .map_err(|e| InputError::new(&a.file, format!("cannot read: {e}")))?;
    if rotorsweep::error::toml_kind(&text) == Some("study") {
        if !a.set.is_empty() {
            return Err(InputError::new(
                &a.file,
                "--set changes a scene; a study's overrides are its [set] and [[axes]]: check its \
                 scene with --set, or edit the study",
            )
            .into());
        }
        return study(&a.file, !a.no_model);
    }
    let source = Source::from_text(&a.file, &text)?;
    scene(&source, &a.set, !a.no_model)
}

fn study(path: &Path, model: bool) -> Result<(), CliError> {
    let st = Study::load(path)?;
    let o = st.overview();
    println!(
        "study {}: {} jobs, {} distinct models, {} reference runs{}",
        path.display(),
        o.jobs,
        o.models,
        o.references.unwrap_or(0),
        if o.references.is_some() {
            ""
        } else {
            " (no [reference]: no errors computed)"
        }
    );
    if !o.swept.is_empty() {
        println!("swept keys (values in job order):");
    }
    for (k, values) in &o.swept {
        println!("  {k}: {}", values.join(", "));
    }
    println!(
        "\nthe first job's scene: the study's [set] and [budget] with its swept values (the \
         other jobs differ in the swept keys above):"
    );
    let source = Source::load(&st.scene_path)?;
    scene(&source, &o.first_job, model)
}

fn scene(source: &Source, set: &[String], model: bool) -> Result<(), CliError> {
    let sc = Scene::from_source(source, set)?;
    let (table, _) = with_overrides(source, set)?;
    println!("scene {}", source.path().display());
    for l in &source.layers[1..] {
        println!("  extends {}", l.path.display());
    }
    for s in set {
        println!("  --set {s}");
    }
    println!("\n# The effective scene: the files merged, overrides applied (units in key names).");
    print!("{}", toml::to_string(&table)?);
    match &sc.machine {
        Some(m) => machine(m, model),
        None => roll(source, set, &sc, &table, model),
    }
}

/// Every roll of a machine as a scene of its own, then the nips.
fn machine(m: &Machine, model: bool) -> Result<(), CliError> {
    for r in &m.rolls {
        println!(
            "\n# Roll {}: {} at ({}, {}) mm, arm force ({}, {}) N{}",
            r.name,
            r.scene.source.display(),
            1e3 * r.position[0],
            1e3 * r.position[1],
            r.arm.steady[0],
            r.arm.steady[1],
            if r.arm.varies() {
                ", varying in time"
            } else {
                ""
            }
        );
        let source = Source::load(&r.scene.source)?;
        let (table, _) = with_overrides(&source, &r.set)?;
        roll(&source, &r.set, &r.scene, &table, model)?;
    }
    for n in &m.nips {
        let (a, b) = n.rolls;
        println!(
            "\n# Nip {}: {} → {}, z {:.1} … {:.1} mm in {} segments of {:.2} mm, gap {:.4} mm, \
             outer radii {:.2} / {:.2} mm, line load {:.3} kN/m",
            n.name,
            m.rolls[a].name,
            m.rolls[b].name,
            1e3 * (n.z[0] - 0.5 * n.segment_length),
            1e3 * (n.z[n.z.len() - 1] + 0.5 * n.segment_length),
            n.z.len(),
            1e3 * n.segment_length,
            1e3 * n.gap,
            1e3 * n.radii.0,
            1e3 * n.radii.1,
            1e-3 * n.line_load
        );
        match &n.law {
            NipLaw::Linear { stiffness } => println!("  law: linear, {stiffness:e} N/m per m"),
            NipLaw::Hertz { fit } => println!(
                "  law: hertz (Roark fit per segment), k = {:.6e} N/m^e, e = {:.4}",
                fit.k, fit.exponent
            ),
            NipLaw::Cover {
                foundation,
                radius,
                thickness,
            } => println!(
                "  law: cover {:.2} mm, Winkler modulus {foundation:.4e} N/m³, R = {:.2} mm",
                1e3 * thickness,
                1e3 * radius
            ),
            NipLaw::Viscoelastic { cover } => println!(
                "  law: viscoelastic cover {:.2} mm (standard linear solid), Winkler moduli \
                 relaxed {:.4e}, unrelaxed {:.4e} N/m³, relaxation time {} s, R = {:.2} mm, \
                 {} points round the covered roll per segment",
                1e3 * cover.thickness,
                cover.relaxed,
                cover.unrelaxed,
                cover.relaxation_time,
                1e3 * cover.radius,
                cover.points
            ),
        }
        for (roll, surface) in [(a, &n.surfaces.0), (b, &n.surfaces.1)] {
            if !surface.is_empty() {
                let lines: Vec<String> = (surface.iter())
                    .map(|h| format!("order {} {:.3} µm", h.order, 1e6 * h.amplitude))
                    .collect();
                println!(
                    "  runout of {}'s surface at the nip: {}",
                    m.rolls[roll].name,
                    lines.join(", ")
                );
            }
        }
    }
    for w in &m.webs {
        println!(
            "\n# Web {} on {}: z {:.1} … {:.1} mm, tension {:.3} kN/m over {:.1}°: line load \
             ({:.1}, {:.1}) N/m{}",
            w.name,
            m.rolls[w.roll].name,
            1e3 * w.z.0,
            1e3 * w.z.1,
            1e-3 * w.tension,
            w.wrap.to_degrees(),
            w.load.steady[0],
            w.load.steady[1],
            if w.load.varies() {
                ", varying in time"
            } else {
                ""
            }
        );
    }
    Ok(())
}

/// One roll's derived values, warnings and (with `model`) its model.
fn roll(
    source: &Source,
    set: &[String],
    sc: &Scene,
    table: &toml::Value,
    model: bool,
) -> Result<(), CliError> {
    println!("\n# Derived");
    let d = Derived::of(sc, table);
    print_positions(&d.positions);
    print_wall(d.wall.as_ref());
    print_run(&d);
    print_contacts(&d.contacts);
    for w in plausibility::warnings(source, set, sc)? {
        println!("warning: {w}");
    }
    if model {
        let m = Model::build(sc, None)?;
        print_model(&m.summary());
        let hz = SupportedHz::of_scene(sc, &m)?;
        println!("first frequencies on the linearised supports at standstill [Hz]:");
        println!("  vertical:   {}", list(&hz.vertical, 4));
        println!("  horizontal: {}", list(&hz.horizontal, 4));
    }
    Ok(())
}

fn print_positions(p: &Positions) {
    let frame = if p.roll_frame {
        "z from the shell's tending end"
    } else {
        "z on the rotor's axis"
    };
    println!("axial positions [mm, {frame}]:");
    for n in &p.nodes {
        let what = if n.sensor { " (sensor)" } else { "" };
        println!("  node {}{what}: {:.1}", n.name, n.z_mm);
    }
    if let Some(b) = &p.balancing {
        let z: Vec<String> = b.z_mm.iter().map(|z| format!("{z:.1}")).collect();
        println!(
            "  balancing planes: {} at radius {:.1}",
            z.join(", "),
            b.radius_mm
        );
    }
    for m in &p.point_masses {
        println!(
            "  point mass {:.1} g at z {:.1}, radius {:.1}, {:.1}° (body frame)",
            m.mass_g, m.z_mm, m.radius_mm, m.angle_deg
        );
    }
}

fn print_wall(wall: Option<&Wall>) {
    match wall {
        Some(Wall::Map {
            file,
            mean_mm,
            std_mm,
            min_mm,
            max_mm,
        }) => {
            let from = file
                .as_ref()
                .map_or("synthetic_map".to_string(), |p| format!("map {p}"));
            println!(
                "wall ({from}): mean {mean_mm:.3} mm, std {std_mm:.3} mm, min {min_mm:.3} mm, \
                 max {max_mm:.3} mm"
            );
        }
        Some(Wall::Uniform(w)) => println!("wall: uniform {w} mm"),
        Some(Wall::Segments(tubes)) => {
            let tubes: Vec<String> = tubes
                .iter()
                .map(|(outer, inner)| format!("{outer:.1}/{inner:.1}"))
                .collect();
            println!("segments (outer/inner diameter mm): {}", tubes.join(", "));
        }
        None => {}
    }
}

fn print_run(d: &Derived) {
    let speed = match &d.speed {
        Speed::Constant(hz) => format!("constant {hz:.4} Hz ({:.2} rpm)", 60.0 * hz),
        Speed::Ramp {
            from_hz,
            to_hz,
            t0_s,
            t1_s,
        } => format!(
            "ramp {from_hz:.4} → {to_hz:.4} Hz ({:.2} → {:.2} rpm) over {t0_s} … {t1_s} s",
            60.0 * from_hz,
            60.0 * to_hz
        ),
        Speed::Steps(steps) => format!(
            "steps: {}",
            steps
                .iter()
                .map(|(hz, t)| format!("{hz:.4} Hz from {t} s"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Speed::Table {
            points,
            first_hz,
            first_s,
            last_hz,
            last_s,
        } => format!(
            "table of {points} points, {first_hz:.4} Hz at {first_s} s … {last_hz:.4} Hz at \
             {last_s} s (linear between)"
        ),
    };
    let r = &d.record;
    println!("speed: {speed}");
    println!(
        "record: {} … {} s at {} Hz: {} samples × {} channels; {} modal coordinates; solver {}",
        r.settle_s,
        r.t_end_s,
        r.sample_rate_hz,
        r.samples,
        r.channels,
        r.modal_coordinates,
        r.solver
    );
}

fn print_contacts(contacts: &[Contact]) {
    for c in contacts {
        let Some(f) = &c.fit else {
            println!(
                "contact at {}: F = k δ^e with k {:.1} N/mm^e, e {:.5} (as written)",
                c.node, c.k_n_per_mm_e, c.exponent
            );
            continue;
        };
        let g = &f.geometry;
        println!(
            "contact at {}: F = k δ^e with k {:.1} N/mm^e, e {:.5}, fitted to the Roark line \
             contact over {}–{} N ({} loads) of",
            c.node, c.k_n_per_mm_e, c.exponent, g.loads.0, g.loads.1, g.points
        );
        println!(
            "  Ø{:.2} mm (journal) on Ø{:.2} mm (roller), length {:.2} mm, E {}/{} GPa, ν {}/{}",
            1e3 * g.journal_diameter,
            1e3 * g.roller_diameter,
            1e3 * g.length,
            g.journal.0 * 1e-9,
            g.roller.0 * 1e-9,
            g.journal.1,
            g.roller.1,
        );
        let from = f
            .within_1pct_from
            .map_or("nowhere in the range".to_string(), |x| {
                format!("from {x:.0} N on")
            });
        println!(
            "  the law's penetration: at most {:.2} % off the relation's (at {:.0} N), within 1 % \
             {from}; {:.2} µm at {} N (relation {:.2} µm)",
            100.0 * f.max_deviation,
            f.max_deviation_load,
            1e6 * f.law_penetration(g.loads.1),
            g.loads.1,
            1e6 * g.penetration(g.loads.1)
        );
    }
}

fn print_model(m: &ModelSummary) {
    println!(
        "model: {:.2} kg, {} elements, {} nodes, {} DOFs, reduced to {} = {} coordinates ({:.2} s)",
        m.mass_kg,
        m.elements,
        m.nodes,
        m.dofs,
        m.modes_selected,
        m.modes.len(),
        m.build_time_s
    );
    for b in &m.balancing_masses {
        println!(
            "balancing mass: {:.2} g at z {:.1} mm, radius {:.1} mm, {:.1}° (body frame)",
            b.mass_g, b.z_mm, b.radius_mm, b.angle_deg
        );
    }
}
