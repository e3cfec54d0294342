//! `rotorsweep barring MACHINE`: the barring stability map of a machine's viscoelastic nip
//! over speed × nip load ([`rotorsweep::linear::barring_machine`]).
//!
//! In: a machine file, `--speeds START:STOP:COUNT` [Hz] of the first roll (default 1:20:39;
//! with a trailing `rpm` in rev/min), `--loads-kn-per-m A,B,…` (default the nip's own line
//! load), `--nip NAME` (default the first viscoelastic nip), `--set KEY=VALUE`, `--json`,
//! `-o MAP.h5` (`--overwrite`). Out: a table per load (speed, covered roll's revolution
//! frequency, stable or not, growth rate [1/s], frequency [Hz], waves per revolution, polygon
//! order, the nip's share of the root, closed segments at the rolling equilibrium) and
//! the onset speed with its polygon order; with `--json` the [`BarringMap`] as one object
//! (`nip`, `covered_roll`, `cover_speed_per_speed`, `speeds_hz`, `loads_kn_per_m`, `loads`: per
//! load `line_load_kn_per_m`, `nip_force_n`, `closed_segments`, `max_penetration_um`, `modes`
//! {`freq_hz`, `damping_ratio`, `nip_share`}, `points` {`speed_hz`, `cover_speed_hz`, `stable`,
//! `growth_per_s`, `growth_per_rev`, `frequency_hz`, `waves_per_rev`, `polygon_order`,
//! `nip_share`, `closed_segments`, `max_penetration_um`, `contact_stiffness_n_per_m`,
//! `overlap`}, `onset` {`speed_hz`, `last_stable_hz`,
//! `cover_speed_hz`, `polygon_order`, `waves_per_rev`, `growth_per_s`} or null); `-o` the HDF5
//! layout of [`rotorsweep::results::barring_file::write_h5`].

use std::path::PathBuf;

use rotorsweep::dynamics::model::Model;
use rotorsweep::linear::barring_machine::{barring_map, BarringMap, MapRequest};
use rotorsweep::results::barring_file::write_h5;
use rotorsweep::store;
use rotorsweep::text::number_text;

use crate::error::CliError;
use crate::speeds;

/// Arguments of `rotorsweep barring`.
#[derive(clap::Args)]
pub struct Args {
    /// Machine file (TOML) with a viscoelastic nip.
    machine: PathBuf,
    /// The first roll's speeds START:STOP:COUNT [Hz] (default 1:20:39), or in rev/min with a
    /// trailing `rpm`.
    #[arg(long, alias = "speeds-hz")]
    speeds: Option<String>,
    /// Nip line loads [kN/m], comma-separated (default: the nip's own).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    loads_kn_per_m: Option<Vec<f64>>,
    /// The nip (default: the first with a viscoelastic cover).
    #[arg(long)]
    nip: Option<String>,
    /// Override a machine value, `--set nips[0].cover_relaxation_time_s=0.1` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Print the map as JSON.
    #[arg(long)]
    json: bool,
    /// Write the map into this HDF5 file.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Replace an existing output.
    #[arg(long)]
    overwrite: bool,
}

fn print(map: &BarringMap) {
    println!(
        "barring: nip {}, cover on roll {} (turning at {:.4} x the first roll's speed)",
        map.nip, map.covered_roll, map.cover_speed_per_speed
    );
    for l in &map.loads {
        println!(
            "\nline load {} kN/m: nip force {:.0} N, at standstill {} closed segments, largest penetration {:.1} um",
            l.line_load_kn_per_m, l.nip_force_n, l.closed_segments, l.max_penetration_um
        );
        for (i, m) in l.modes.iter().enumerate() {
            println!(
                "  roll mode {i} (nip open): {:.3} Hz, damping ratio {:.4}, nip share {:.3}",
                m.freq_hz, m.damping_ratio, m.nip_share
            );
        }
        println!("  speed Hz   cover Hz  stable  growth 1/s   freq Hz  waves/rev  order  nip share  closed");
        for p in &l.points {
            println!(
                "  {:8.3}  {:8.3}  {:6}  {:10.4}  {:8.3}  {:9.3}  {:5}  {:9.3}  {:6}",
                p.speed_hz,
                p.cover_speed_hz,
                if p.stable { "yes" } else { "no" },
                p.growth_per_s,
                p.frequency_hz,
                p.waves_per_rev,
                p.polygon_order,
                p.nip_share,
                p.closed_segments
            );
        }
        match &l.onset {
            Some(o) => println!(
                "  onset: {} Hz (cover {:.3} Hz; last stable {}), polygon order {} ({:.3} waves/rev), growth {:.4} 1/s",
                o.speed_hz,
                o.cover_speed_hz,
                o.last_stable_hz.map_or("none".into(), |s| format!("{s} Hz")),
                o.polygon_order,
                o.waves_per_rev,
                o.growth_per_s
            ),
            None => println!("  stable over the speeds given"),
        }
    }
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), CliError> {
    let speeds_hz =
        speeds::sweep(a.speeds.as_deref().unwrap_or("1:20:39")).map_err(CliError::input)?;
    if let Some(q) = (a.loads_kn_per_m.iter().flatten()).find(|q| !(q.is_finite() && **q >= 0.0)) {
        return Err(CliError::input(format!(
            "--loads-kn-per-m {}: a line load must be a finite number, zero or positive [kN/m]",
            number_text(*q)
        )));
    }
    let (scene, model) = Model::load(&a.machine, &a.set, None)?;
    let machine = scene.machine.as_ref().ok_or_else(|| {
        CliError::input(format!(
            "{}: barring needs a machine file ([[rolls]] and [[nips]] with a viscoelastic cover)",
            a.machine.display()
        ))
    })?;
    let _lock = (a.output.as_deref())
        .map(|p| store::output::claim(p, a.overwrite))
        .transpose()?;
    let req = MapRequest {
        nip: a.nip.clone(),
        speeds_hz,
        loads_kn_per_m: a.loads_kn_per_m.clone(),
    };
    let map = barring_map(machine, &model, &req)
        .map_err(|e| CliError::input(format!("{}: {e}", a.machine.display())))?;
    if let Some(path) = &a.output {
        let command = std::env::args().collect::<Vec<_>>().join(" ");
        let text = std::fs::read_to_string(&a.machine).unwrap_or_default();
        write_h5(&map, path, &command, &text).map_err(|e| CliError::Io(e.into()))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&map)?);
    } else {
        print(&map);
    }
    Ok(())
}
