//! How big a scene's model and record are, and the limits that keep a run within the machine.
//!
//! In: a scene's mesh (elements per segment, named points, disks) and its record (run window,
//! sample rate, channels). Out: the counts (FE nodes, modal coordinates, channels, samples per
//! channel) and, over [`MAX_FE_NODES`], [`MAX_SAMPLES_PER_CHANNEL`] or [`MAX_RECORD_VALUES`], an
//! [`InputError`] at the key that asks for the most. Method: upper bounds counted from the
//! scene as written, before anything is built.

use super::check::Check;
use super::types::{Scene, SupportModel};
use crate::error::InputError;
use crate::rotor::reduction::ModeSelection;

/// Most samples one output channel of a run may hold, (t_end − settle) × sample_rate + 1: 80 MB
/// per channel (10 000 s at 1 kHz, 100 s at 100 kHz). The analysis needs far fewer (the source's
/// spectra use 8192 samples); a record this long is almost surely a typo in t_end_s or
/// sample_rate_hz, and an unbounded one exhausts the memory.
pub const MAX_SAMPLES_PER_CHANNEL: f64 = 1e7;

/// Most values (samples × channels, time included, 8 bytes each) one run may record: 2 GB, so
/// that a long record with every output on (the modal coordinates too) still fits in memory.
pub const MAX_RECORD_VALUES: f64 = 2.5e8;

/// A run's record stays within [`MAX_SAMPLES_PER_CHANNEL`] and [`MAX_RECORD_VALUES`]. The error
/// names `simulation.t_end_s` when the window alone is too long at the default 1 kHz, else
/// `simulation.sample_rate_hz`.
pub(super) fn record_size(c: &Check, scene: &Scene) -> Result<(), InputError> {
    let sim = &scene.simulation;
    let samples = scene.samples();
    let channels = scene.channels() + 1;
    let values = samples * channels as f64;
    let basis = format!(
        "(t_end_s − settle_s) × sample_rate_hz = ({} − {}) s × {} Hz gives {samples:.4e} samples \
         per channel",
        sim.t_end, sim.settle, sim.sample_rate
    );
    let reason = if samples > MAX_SAMPLES_PER_CHANNEL {
        format!(
            "{basis}, more than the limit of {MAX_SAMPLES_PER_CHANNEL:e} (80 MB per channel; the \
             analysis needs thousands, not millions)"
        )
    } else if values > MAX_RECORD_VALUES {
        format!(
            "{basis}, × {channels} channels (time, runout, outputs.*) = {values:.4e} values, more \
             than the limit of {MAX_RECORD_VALUES:e} (2 GB) one run may record"
        )
    } else {
        return Ok(());
    };
    let key = if (sim.t_end - sim.settle) * 1e3 > MAX_SAMPLES_PER_CHANNEL {
        "simulation.t_end_s"
    } else {
        "simulation.sample_rate_hz"
    };
    Err(c.err(key, reason))
}

impl Scene {
    /// Modal coordinates of the scene's reduced model: the five rigid modes and the elastic
    /// modes its selection keeps (`reduction.modes`; a pruned run keeps fewer).
    pub fn modal_coordinates(&self) -> usize {
        match &self.modes {
            ModeSelection::Counts { normal, statics } => 5 + normal + statics.saturating_sub(6),
            ModeSelection::List(l) => {
                let elastic: std::collections::BTreeSet<usize> =
                    l.iter().copied().filter(|&i| i >= 5).collect();
                5 + elastic.len()
            }
        }
    }

    /// Output channels a run records (the time axis not counted): two runout directions per
    /// sensor, and as `[outputs]` asks two journal and two stand directions per support, a
    /// contact force per roller, the modal coordinates.
    pub fn channels(&self) -> usize {
        let o = &self.outputs;
        let mut n = 0;
        if o.runout {
            n += 2 * self.sensors.len();
        }
        for s in &self.supports {
            if o.journal_orbits {
                n += 2;
            }
            if o.stand_motion && s.has_mass() {
                n += 2;
            }
            if let (true, SupportModel::Rollers(r)) = (o.contact_forces, &s.model) {
                n += r.rollers.len();
            }
        }
        if o.modal {
            n += self.modal_coordinates();
        }
        if o.speed {
            n += 2;
        }
        n
    }

    /// Most FE nodes the scene's mesh can have (6 DOFs each), as [`MAX_FE_NODES`] counts them.
    pub fn max_nodes(&self) -> usize {
        let r = &self.rotor;
        node_bound(
            r.segments.iter().map(|s| s.elements),
            r.named_points.len() + r.disks.len(),
        )
    }

    /// Samples per channel of a run: one every 1 / sample_rate from settle_s to t_end_s.
    pub fn samples(&self) -> f64 {
        let sim = &self.simulation;
        ((sim.t_end - sim.settle) * sim.sample_rate).floor() + 1.0
    }
}

/// Most FE nodes a model may have (6 DOFs each). The reduction solves dense eigenproblems of the
/// interior DOFs and holds the assembled matrices densely: memory grows with DOFs² and time with
/// DOFs³. Measured with `rotorsweep modes` on a 2-core machine (docs/benchmarks.md, 2026-12-01) (busy with other
/// builds): the reference roll at the limit (`roll.shell.elements = 482`, 493 nodes, 2958 DOFs)
/// built in 13.8 s with a peak of 0.74 GB, the Jeffcott rotor at it (2 × 243 elements, 487
/// nodes) in 18.0 s and 0.72 GB; at 600 shell elements it took 28.6 s and 1.1 GB, at 800 74 s
/// and 1.9 GB, and 2000 would need about 60 times the time of the limit and 16 times its memory.
pub const MAX_FE_NODES: usize = 500;

/// The mesh stays within [`MAX_FE_NODES`]: one node more than the elements as written (`written`:
/// the elements key of each segment and the elements it adds) plus one per named point or disk
/// (`extra`), which may each add a node. Too many: an error at the key that adds the most.
pub(super) fn mesh_size(
    c: &Check,
    written: &[(String, usize)],
    extra: usize,
) -> Result<(), InputError> {
    let nodes = node_bound(written.iter().map(|(_, e)| *e), extra);
    if nodes <= MAX_FE_NODES {
        return Ok(());
    }
    let worst = written
        .iter()
        .max_by_key(|(_, e)| *e)
        .map_or("elements", |(k, _)| k.as_str());
    Err(c.err(
        worst,
        format!(
            "the mesh would have up to {nodes} nodes ({} DOFs), more than the limit of \
             {MAX_FE_NODES} nodes ({} DOFs): the reduction solves dense eigenproblems of that \
             size (memory grows with DOFs², time with DOFs³; at the limit a model takes about \
             15-20 s and 0.75 GB to build)",
            6 * nodes,
            6 * MAX_FE_NODES
        ),
    ))
}

/// Most nodes a mesh of segments of `elements` can have: one more than the elements, plus one
/// per named point or disk (`extra`) that may fall between nodes.
fn node_bound(elements: impl Iterator<Item = usize>, extra: usize) -> usize {
    elements.fold(1 + extra, usize::saturating_add)
}
