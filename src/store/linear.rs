//! The HDF5 layout of the linear analyses: what `rotorsweep linear -o` writes under
//! `/linear/<scene>` and a study under `/linear/<id>`.
//!
//! In: the [`Results`] of a linear request (damped modes over speed, unbalance response, Floquet,
//! statics, critical-speed map, mode shapes; SI inside, Hz / µm / deg / mm as stored) and
//! Campbell data. Out: groups, datasets with their `units`, dimension scales and attributes
//! (layout in [`Results::write`] and [`write_campbell`]); docs/results.md describes it for users.

use ndarray::Array3;

use crate::linear::campbell::{lateral_modes, whirl_code, CampbellData, WHIRL_CODES};
use crate::linear::critical_map::CriticalMap;
use crate::linear::modes::DampedMode;
use crate::linear::request::{Results, PHASE_NOTE};
use crate::linear::response::SensorResponse;
use crate::linear::FRAME_NOTE;
use crate::store;

/// A value of the mode at (speed index, index in that speed's set).
type ModeValue<'a> = dyn Fn(usize, usize, &DampedMode) -> f64 + 'a;

impl Results {
    /// Writes the results into `g` (a study's `/linear/<id>` or a `linear -o` file's
    /// `/linear/<scene>`): attributes `frame`, `phase_convention`, `vertical_hz`, `horizontal_hz`
    /// (first bending at standstill), `json` (the [`Results::to_json`] object, times only when
    /// `with_times`); `campbell/…` ([`write_campbell`]); per plane
    /// `unbalance_response/<sensor>/{vertical,horizontal}/{amplitude_um,phase_deg}` and
    /// `…/{major_um,minor_um}` (and `unbalance_response_nodes/<node>/…` for named nodes) over
    /// `campbell/speed_hz`; `floquet/{speed_hz,growth_per_rev,steps_per_rev,converged,
    /// unstable_ranges_hz}`; `static/{sensors,sag_vertical_um,sag_horizontal_um}`;
    /// `critical_map/…`; `shapes/{node_z_mm,x_re,x_im,y_re,y_im}` [speeds × modes × nodes].
    pub fn write(&self, g: &hdf5::Group, with_times: bool) -> hdf5::Result<()> {
        store::attr_str(g, "frame", FRAME_NOTE)?;
        store::attr_str(g, "phase_convention", PHASE_NOTE)?;
        let first = |v: &[f64]| v.first().copied().unwrap_or(f64::NAN);
        store::attr_f64(g, "vertical_hz", first(&self.supported.0))?;
        store::attr_f64(g, "horizontal_hz", first(&self.supported.1))?;
        write_campbell(g, &self.campbell)?;
        if let Some(r) = &self.response {
            store::attr_str(g, "unbalance", &r.unbalance)?;
            for (i, plane) in r.planes.iter().enumerate() {
                let top = if i < r.sensors {
                    "unbalance_response"
                } else {
                    "unbalance_response_nodes"
                };
                let col = |f: &dyn Fn(&SensorResponse) -> f64| -> Vec<f64> {
                    r.values.iter().map(|s| f(&s[i])).collect()
                };
                let p = format!("{top}/{plane}");
                for (dir, pick) in [
                    ("vertical", (|s: &SensorResponse| s.vertical) as fn(&_) -> _),
                    ("horizontal", |s: &SensorResponse| s.horizontal),
                ] {
                    let amp = col(&|s| 1e6 * pick(s).norm());
                    let phase = col(&|s| pick(s).arg().to_degrees());
                    store::dataset(g, &format!("{p}/{dir}/amplitude_um"), &amp, "um")?;
                    store::dataset(g, &format!("{p}/{dir}/phase_deg"), &phase, "deg")?;
                }
                store::dataset(
                    g,
                    &format!("{p}/major_um"),
                    &col(&|s| 1e6 * s.major()),
                    "um",
                )?;
                store::dataset(
                    g,
                    &format!("{p}/minor_um"),
                    &col(&|s| 1e6 * s.minor()),
                    "um",
                )?;
            }
        }
        if let Some(f) = &self.floquet {
            store::dataset(g, "floquet/speed_hz", &f.speeds_hz, "Hz")?;
            let growth: Vec<f64> = f.growth.iter().map(|g| g.growth).collect();
            store::dataset(g, "floquet/growth_per_rev", &growth, "1")?;
            let steps: Vec<f64> = f.growth.iter().map(|g| g.steps as f64).collect();
            store::dataset(g, "floquet/steps_per_rev", &steps, "1")?;
            let conv: Vec<f64> = f
                .growth
                .iter()
                .map(|g| f64::from(u8::from(g.converged)))
                .collect();
            store::dataset(g, "floquet/converged", &conv, "1")?;
            store::scales::attach_axis(
                &store::subgroup(g, "floquet")?,
                "speed_hz",
                &["growth_per_rev", "steps_per_rev", "converged"],
                0,
            )?;
            let flat: Vec<f64> = f.ranges.iter().flatten().copied().collect();
            store::dataset_2d(
                g,
                "floquet/unstable_ranges_hz",
                (f.ranges.len(), 2),
                &flat,
                "Hz",
            )?;
            if let Some(c) = f.cutoff_hz {
                let fg = store::subgroup(g, "floquet")?;
                store::attr_f64(&fg, "cutoff_hz", c)?;
            }
        }
        if let Some(Ok(s)) = &self.statics {
            let names: Vec<String> = s.sensors.iter().map(|x| x.0.clone()).collect();
            store::string_dataset(&store::subgroup(g, "static")?, "sensors", &names)?;
            let v: Vec<f64> = s.sensors.iter().map(|x| 1e6 * x.1.y).collect();
            let h: Vec<f64> = s.sensors.iter().map(|x| 1e6 * x.1.x).collect();
            store::dataset(g, "static/sag_vertical_um", &v, "um")?;
            store::dataset(g, "static/sag_horizontal_um", &h, "um")?;
        }
        if let Some((map, nodes)) = &self.map {
            write_map(g, map, nodes)?;
        }
        if let Some(shapes) = &self.shapes {
            let sg = store::subgroup(g, "shapes")?;
            let z: Vec<f64> = self.node_z.iter().map(|z| 1e3 * z).collect();
            store::dataset(&sg, "node_z_mm", &z, "mm")?;
            let (ns, nb, nn) = (shapes.len(), shapes.first().map_or(0, Vec::len), z.len());
            for (p, name) in ["x_re", "x_im", "y_re", "y_im"].iter().enumerate() {
                let a = Array3::from_shape_fn((ns, nb, nn), |(s, k, n)| shapes[s][k][n][p]);
                dataset_3d(&sg, name, &a, "1")?;
            }
        }
        store::attr_str(g, "json", &self.to_json(with_times).to_string())
    }
}

/// Writes Campbell data under `g` in the layout shared by `rotorsweep linear -o` and a study's
/// `/linear/<id>`: `campbell/speed_hz` [Hz]; per speed × lateral branch (the lowest `nb`
/// lateral modes every speed has, ascending; `campbell/mode` = 0…nb−1; both axes dimension
/// scales, `store::scales`) `campbell/whirl_hz` [Hz], `log_dec`,
/// `damping_ratio`, `whirl_index`, `whirl` (codes in its `codes` attribute) and `branch` (the
/// matched branch, −1 none); `critical_speeds_hz` [Hz] with `critical_log_dec` and
/// `critical_whirl`; the attribute `stability_threshold_hz` when a speed is unstable.
pub fn write_campbell(g: &hdf5::Group, c: &CampbellData) -> hdf5::Result<()> {
    let ns = c.speeds_hz.len();
    store::dataset(g, "campbell/speed_hz", &c.speeds_hz, "Hz")?;
    let (lateral, nb) = lateral_modes(c);
    let flat = |f: &ModeValue<'_>| -> Vec<f64> {
        lateral
            .iter()
            .enumerate()
            .flat_map(|(s, l)| l[..nb].iter().map(move |(j, m)| f(s, *j, m)))
            .collect()
    };
    let per_mode: [(&str, &ModeValue<'_>, &str); 5] = [
        ("whirl_hz", &|_, _, m| m.freq_hz, "Hz"),
        ("log_dec", &|_, _, m| m.log_dec, "1"),
        ("damping_ratio", &|_, _, m| m.damping_ratio, "1"),
        ("whirl_index", &|_, _, m| m.whirl_index, "1"),
        ("whirl", &|_, _, m| whirl_code(m.whirl), "1"),
    ];
    for (name, f, units) in per_mode {
        store::dataset_2d(g, &format!("campbell/{name}"), (ns, nb), &flat(f), units)?;
    }
    let whirl = g.dataset("campbell/whirl")?;
    store::attr_str(&whirl, "codes", WHIRL_CODES)?;
    let branch_of = |s: usize, j: usize| {
        c.branches
            .iter()
            .position(|b| b.mode[s] == Some(j))
            .map_or(-1.0, |b| b as f64)
    };
    store::dataset_2d(
        g,
        "campbell/branch",
        (ns, nb),
        &flat(&|s, j, _| branch_of(s, j)),
        "1",
    )?;
    // The axes: speed × the k-th lowest lateral mode (`mode` first, so that a `mode` as long
    // as the speeds is an axis, not a value over speed).
    let modes: Vec<f64> = (0..nb).map(|k| k as f64).collect();
    store::dataset(g, "campbell/mode", &modes, "1")?;
    let cg = g.group("campbell")?;
    store::scales::attach_axis(&cg, "mode", &[""], 1)?;
    store::scales::attach_axis(&cg, "speed_hz", &[""], 0)?;
    let crit: Vec<f64> = c.critical.iter().map(|x| x.speed_hz).collect();
    store::dataset(g, "critical_speeds_hz", &crit, "Hz")?;
    let crit_log_dec: Vec<f64> = c.critical.iter().map(|x| x.log_dec).collect();
    store::dataset(g, "critical_log_dec", &crit_log_dec, "1")?;
    let crit_whirl: Vec<String> = c.critical.iter().map(|x| x.whirl.to_string()).collect();
    store::string_dataset(g, "critical_whirl", &crit_whirl)?;
    if let Some(t) = c.threshold_hz {
        store::attr_f64(g, "stability_threshold_hz", t)?;
    }
    Ok(())
}

/// The critical-speed map, NaN-padded to the most critical speeds of any stiffness.
fn write_map(g: &hdf5::Group, map: &CriticalMap, nodes: &[String]) -> hdf5::Result<()> {
    let width = map.critical_hz.iter().map(Vec::len).max().unwrap_or(0);
    let padded: Vec<f64> = map
        .critical_hz
        .iter()
        .flat_map(|row| (0..width).map(|i| row.get(i).copied().unwrap_or(f64::NAN)))
        .collect();
    store::dataset(g, "critical_map/stiffness_n_per_m", &map.stiffness, "N/m")?;
    store::dataset_2d(
        g,
        "critical_map/critical_speeds_hz",
        (map.stiffness.len(), width),
        &padded,
        "Hz",
    )?;
    let kx: Vec<f64> = map.actual.iter().map(|k| k.0).collect();
    let ky: Vec<f64> = map.actual.iter().map(|k| k.1).collect();
    store::dataset(g, "critical_map/actual_kx_n_per_m", &kx, "N/m")?;
    store::dataset(g, "critical_map/actual_ky_n_per_m", &ky, "N/m")?;
    store::string_dataset(&g.group("critical_map")?, "support_nodes", nodes)
}

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
