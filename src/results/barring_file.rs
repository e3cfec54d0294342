//! A barring map of a machine as a results file: what `rotorsweep barring MACHINE -o MAP.h5`
//! writes.
//!
//! In: the [`BarringMap`] (`linear::barring_machine`), the output path (claimed by the caller),
//! the command line and the machine file's text. Out: `MAP.h5` with the root attributes every
//! results file has (`store::create_file`) and one group `barring/<nip>` (layout in
//! [`write_h5`]'s doc), written under its working name and renamed when complete.

use std::path::Path;

use crate::linear::barring_machine::{BarringMap, MapPoint, Onset};
use crate::store;

/// Writes the map into a new HDF5 file at `path` (its working name `path`.tmp, renamed at the
/// end): group `barring/<nip>` with the axes `loads_kn_per_m` [kN/m] and `speeds_hz` [Hz] as
/// dimension scales, the [loads × speeds] datasets `growth_per_s` [1/s], `growth_per_rev` [-],
/// `frequency_hz` [Hz], `waves_per_rev` [-], `polygon_order` [-], `stable` [1 stable, 0 not],
/// `contact_stiffness_n_per_m` [N/m] and `overlap` [-] (the nip's quasi-static rolling
/// stiffness and mean overlap at each point's rolling equilibrium), and per load
/// `onset_speed_hz` [Hz] and `onset_polygon_order` [-] (NaN: stable over the grid); the JSON of
/// the map as the group's `json` attribute.
pub fn write_h5(
    map: &BarringMap,
    path: &Path,
    command: &str,
    scene_text: &str,
) -> Result<(), String> {
    let io = |e: hdf5::Error| format!("{}: {e}", path.display());
    let (f, jobs) = store::create_file(path, command, scene_text).map_err(io)?;
    let g = store::subgroup(&f, &format!("barring/{}", map.nip)).map_err(io)?;
    store::attr_str(&g, "covered_roll", &map.covered_roll).map_err(io)?;
    store::attr_f64(&g, "cover_speed_per_speed", map.cover_speed_per_speed).map_err(io)?;
    let json = serde_json::to_string(map).map_err(|e| e.to_string())?;
    store::attr_str(&g, "json", &json).map_err(io)?;
    store::dataset(&g, "speeds_hz", &map.speeds_hz, "Hz").map_err(io)?;
    store::dataset(&g, "loads_kn_per_m", &map.loads_kn_per_m, "kN/m").map_err(io)?;
    let shape = (map.loads.len(), map.speeds_hz.len());
    let grid = |f: &dyn Fn(&MapPoint) -> f64| -> Vec<f64> {
        map.loads
            .iter()
            .flat_map(|l| l.points.iter().map(f))
            .collect()
    };
    let fields: [(&str, &str, Vec<f64>); 8] = [
        ("growth_per_s", "1/s", grid(&|p| p.growth_per_s)),
        ("growth_per_rev", "1", grid(&|p| p.growth_per_rev)),
        ("frequency_hz", "Hz", grid(&|p| p.frequency_hz)),
        ("waves_per_rev", "1", grid(&|p| p.waves_per_rev)),
        ("polygon_order", "1", grid(&|p| p.polygon_order as f64)),
        ("stable", "1", grid(&|p| f64::from(u8::from(p.stable)))),
        (
            "contact_stiffness_n_per_m",
            "N/m",
            grid(&|p| p.contact_stiffness_n_per_m),
        ),
        ("overlap", "1", grid(&|p| p.overlap)),
    ];
    for (name, units, data) in &fields {
        store::dataset_2d(&g, name, shape, data, units).map_err(io)?;
    }
    let onset = |f: &dyn Fn(&Onset) -> f64| -> Vec<f64> {
        map.loads
            .iter()
            .map(|l| l.onset.as_ref().map_or(f64::NAN, f))
            .collect()
    };
    store::dataset(&g, "onset_speed_hz", &onset(&|o| o.speed_hz), "Hz").map_err(io)?;
    store::dataset(
        &g,
        "onset_polygon_order",
        &onset(&|o| o.polygon_order as f64),
        "1",
    )
    .map_err(io)?;
    let names: Vec<&str> = fields.iter().map(|f| f.0).collect();
    let mut with_onset = names.clone();
    with_onset.extend(["onset_speed_hz", "onset_polygon_order"]);
    store::scales::attach_axis(&g, "loads_kn_per_m", &with_onset, 0).map_err(io)?;
    store::scales::attach_axis(&g, "speeds_hz", &names, 1).map_err(io)?;
    store::finish_file(path, f, jobs).map_err(|e| format!("{}: {e}", path.display()))
}
