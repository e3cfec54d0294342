//! Fixtures shared by the wall's unit tests: the thesis Table 4.1 targets, the reference roll's
//! recipe, the shipped map, and reading a CSV text written to a scratch folder.

use std::path::{Path, PathBuf};

use super::{AxialShape, HarmonicSpec, MapStats, SyntheticSpec, ThicknessMap};
use crate::error::InputError;

/// Thesis Table 4.1 (`docs/thesis-data.md` §2): wall thickness of the measured roll, m.
pub(super) const TABLE_4_1_MEAN_M: f64 = 18.72e-3;
pub(super) const TABLE_4_1_STD_M: f64 = 0.30e-3;
pub(super) const TABLE_4_1_MIN_M: f64 = 17.86e-3;
pub(super) const TABLE_4_1_MAX_M: f64 = 19.59e-3;
/// Reference roll shell length between heads (`docs/physics.md` §10), m.
pub(super) const REFERENCE_LENGTH_M: f64 = 4.5;
/// The brief's tolerance on min and max of a synthetic map: 0.02 mm.
pub(super) const MIN_MAX_TOLERANCE_M: f64 = 0.02e-3;
/// The brief's tolerance on mean and std of a synthetic map: 1e-9 relative.
pub(super) const MOMENT_TOLERANCE: f64 = 1e-9;
/// CSV numbers carry nine decimals of a mm: round-trip error ≤ 0.5e-9 mm = 5e-13 m.
pub(super) const CSV_ROUNDING_M: f64 = 5e-13;

pub(super) fn shipped_map_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/maps/reference-roll-thickness.csv")
}

/// The recipe of the shipped map (physics.md §10: Table 4.1 statistics, an eccentric bore
/// (k = 1) and an oval bore (k = 2) both varying along z, some random field).
pub(super) fn reference_roll_spec() -> SyntheticSpec {
    SyntheticSpec {
        seed: 20001,
        mean_m: TABLE_4_1_MEAN_M,
        std_m: TABLE_4_1_STD_M,
        min_m: TABLE_4_1_MIN_M,
        max_m: TABLE_4_1_MAX_M,
        harmonics: vec![
            HarmonicSpec {
                order: 1,
                weight: 1.0,
                phase_rad: 0.6,
                phase_twist_rad: 0.8,
                axial_shape: AxialShape::HalfSine,
            },
            HarmonicSpec {
                order: 2,
                weight: 0.8,
                phase_rad: 1.9,
                phase_twist_rad: -0.5,
                axial_shape: AxialShape::Linear,
            },
        ],
        random_share: 0.3,
        correlation_length_m: 0.6,
        n_angles: 36,
        n_stations: 31,
    }
}

/// The brief's example recipe: k = 1 weight 1 HalfSine, k = 2 weight 0.8 Linear, random
/// share 0.3, Table 4.1 targets, on a grid of `n_angles` × `n_stations`.
pub(super) fn table_spec(seed: u64, n_angles: usize, n_stations: usize) -> SyntheticSpec {
    SyntheticSpec {
        seed,
        harmonics: vec![
            HarmonicSpec {
                order: 1,
                weight: 1.0,
                phase_rad: 0.0,
                phase_twist_rad: 0.0,
                axial_shape: AxialShape::HalfSine,
            },
            HarmonicSpec {
                order: 2,
                weight: 0.8,
                phase_rad: 0.0,
                phase_twist_rad: 0.0,
                axial_shape: AxialShape::Linear,
            },
        ],
        correlation_length_m: 1.0,
        n_angles,
        n_stations,
        ..reference_roll_spec()
    }
}

pub(super) fn assert_hits_targets(stats: MapStats, spec: &SyntheticSpec) {
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(
        rel(stats.mean_m, spec.mean_m) < MOMENT_TOLERANCE,
        "{stats:?}"
    );
    assert!(rel(stats.std_m, spec.std_m) < MOMENT_TOLERANCE, "{stats:?}");
    assert!(
        (stats.min_m - spec.min_m).abs() < MIN_MAX_TOLERANCE_M,
        "{stats:?}"
    );
    assert!(
        (stats.max_m - spec.max_m).abs() < MIN_MAX_TOLERANCE_M,
        "{stats:?}"
    );
}

/// Writes `text` to a file in a scratch folder, reads it as a map of a 4.5 m shell, removes
/// the folder.
pub(super) fn load(name: &str, text: &str) -> (PathBuf, Result<ThicknessMap, InputError>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let result = ThicknessMap::from_csv(&path, REFERENCE_LENGTH_M);
    (path, result)
}

pub(super) fn load_ok(name: &str, text: &str) -> ThicknessMap {
    let (_, result) = load(name, text);
    result.unwrap()
}
