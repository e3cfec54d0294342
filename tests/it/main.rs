//! The integration tests, one binary (one link of the library and HDF5): one module per topic,
//! helpers in [`support`]. Run one topic with `cargo test --release --test it scene_errors::`.

mod support;

/// HDF5's own file locks off for this test process, before its first thread starts. The tests
/// share one process: while one runs a campaign in a thread (its results file open, HDF5
/// holding an flock on it), another spawns the binary, and the child inherits that descriptor
/// with its lock (HDF5 opens files without close-on-exec) and holds it until it exits, so the
/// campaign's read-back of its own file fails with EWOULDBLOCK. rotorsweep's own output locks
/// (`OUT.h5.lock`), which the safety tests check, are not HDF5's and stay on.
#[ctor::ctor(unsafe)]
fn no_hdf5_file_locks() {
    std::env::set_var("HDF5_USE_FILE_LOCKING", "FALSE");
}

mod analysis_study;
mod balancing;
mod barring;
mod barring_machine_time;
mod barring_time;
mod bdf_tolerance;
mod beam_closed_forms;
mod calibration;
mod campaign_messages;
mod campaign_safety;
mod cli_check;
mod contact_events;
mod contact_geometry;
mod contact_runs;
mod cvode;
mod dynamics_checks;
mod error_trust;
mod export;
mod fe_formats;
mod fe_import;
mod fe_nastran;
mod fe_rings;
mod fe_sparse;
mod fe_sparse_stress;
mod fe_study;
mod fe_supported_errors;
mod import;
mod input_checks;
mod integrator_order;
mod layering;
mod linear_cli;
mod linear_consistency;
mod linear_floquet;
mod linear_friswell;
mod linear_jeffcott;
mod linear_peaks;
mod linear_rigid;
mod linear_study;
mod linear_supports;
mod machine_loads;
mod machine_plan;
mod mutation;
mod nip_runout;
mod nips;
mod random_wall;
mod reduction;
mod report;
mod report_calibration;
mod report_html;
mod report_linear;
mod report_nips;
mod roll_surface_runout;
mod rotating_frame;
mod run_log;
mod runup;
mod sample_study;
mod scene_errors;
mod scene_files;
mod scene_keys;
mod shipped_scenes;
mod solid_spinning_ring;
mod stress_stiffening;
mod study;
mod study_errors;
mod study_kill;
mod visco;
