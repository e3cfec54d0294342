//! The wall-thickness map itself: storage, interpolation and statistics.
//!
//! **In:** stations built by the CSV reader ([`csv`](super::csv)), the synthetic generator
//! ([`synthetic`](super::synthetic)) or one thickness ([`ThicknessMap::uniform`]).
//! **Out:** t(φ, z) in metres anywhere on the shell ([`ThicknessMap::thickness`]), the thinnest
//! wall at a z ([`ThicknessMap::min_thickness_at`]) and the map's statistics
//! ([`ThicknessMap::stats`]). SI: φ in radians (body frame, see [the wall doc](super)), z and t
//! in metres.
//!
//! # Storage and interpolation
//! A map is a list of z stations (ascending). Each station keeps its own points sorted by φ in
//! [0, 2π), at least three, **exactly as given**: measured points are not resampled, so nothing is
//! lost and stations may have different angles. Between the points of a station t is linear in φ
//! and periodic (the last point connects to the first through 2π); between stations t is linear
//! in z; below the first and above the last station it is clamped to that station.
//! [`ThicknessMap::stats`] weighs every stored point equally and uses the population standard
//! deviation (divide by N).

use std::f64::consts::{PI, TAU};

/// Wall thickness t(φ, z) of a shell: z stations, each with a periodic profile in φ.
#[derive(Debug, Clone, PartialEq)]
pub struct ThicknessMap {
    /// Shell length, m.
    pub(super) length_m: f64,
    /// Ascending in z; never empty.
    pub(super) stations: Vec<Station>,
}

/// One z station: points sorted by φ.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Station {
    /// Axial position, m.
    pub(super) z_m: f64,
    /// Strictly ascending, in [0, 2π), at least three.
    pub(super) phi_rad: Vec<f64>,
    /// Thickness at each angle, m.
    pub(super) t_m: Vec<f64>,
}

/// Statistics of a map over its stored points (population standard deviation), m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapStats {
    /// Mean, m.
    pub mean_m: f64,
    /// Population standard deviation, m.
    pub std_m: f64,
    /// Thinnest stored point, m.
    pub min_m: f64,
    /// Thickest stored point, m.
    pub max_m: f64,
}

impl ThicknessMap {
    /// A map of one thickness everywhere (m) on a shell of `length_m`: stations at both ends,
    /// four angles each. The caller ensures both numbers are positive.
    pub fn uniform(thickness_m: f64, length_m: f64) -> Self {
        let station = |z_m: f64| Station {
            z_m,
            phi_rad: vec![0.0, 0.5 * PI, PI, 1.5 * PI],
            t_m: vec![thickness_m; 4],
        };
        let stations = if length_m > 0.0 {
            vec![station(0.0), station(length_m)]
        } else {
            vec![station(0.0)]
        };
        Self { length_m, stations }
    }

    /// Wall thickness (m) at body-frame angle `phi_rad` (any value, periodic) and axial position
    /// `z_m`: linear between the points of a station (periodically), linear between stations,
    /// clamped to the first or last station outside them.
    pub fn thickness(&self, phi_rad: f64, z_m: f64) -> f64 {
        let s = &self.stations;
        let j = s.partition_point(|st| st.z_m <= z_m);
        if j == 0 {
            return s[0].at(phi_rad);
        }
        if j == s.len() {
            return s[j - 1].at(phi_rad);
        }
        let (lo, hi) = (&s[j - 1], &s[j]);
        let w = (z_m - lo.z_m) / (hi.z_m - lo.z_m);
        let t_lo = lo.at(phi_rad);
        t_lo + w * (hi.at(phi_rad) - t_lo)
    }

    /// The thinnest wall (m) at axial position `z_m` over every angle. Between the points of a
    /// station and between two stations t is linear, so the minimum lies at one of the angles of
    /// the (one or two) stations around `z_m`.
    pub fn min_thickness_at(&self, z_m: f64) -> f64 {
        let s = &self.stations;
        let j = s.partition_point(|st| st.z_m <= z_m);
        let around = &s[j.saturating_sub(1)..(j + 1).min(s.len())];
        around
            .iter()
            .flat_map(|st| st.phi_rad.iter())
            .map(|&phi| self.thickness(phi, z_m))
            .fold(f64::INFINITY, f64::min)
    }

    /// Mean, population standard deviation, minimum and maximum over the stored points, m.
    pub fn stats(&self) -> MapStats {
        let values: Vec<f64> = self
            .stations
            .iter()
            .flat_map(|s| s.t_m.iter().copied())
            .collect();
        let (mean_m, std_m) = mean_std(&values);
        MapStats {
            mean_m,
            std_m,
            min_m: values.iter().copied().fold(f64::INFINITY, f64::min),
            max_m: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// Shell length the map belongs to, m.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }
}

impl Station {
    /// Periodic linear interpolation in φ.
    fn at(&self, phi_rad: f64) -> f64 {
        let phi = wrap_angle(phi_rad);
        let n = self.phi_rad.len();
        let i = self.phi_rad.partition_point(|&p| p <= phi);
        let (lo, hi, p_lo, p_hi) = if i == 0 {
            (n - 1, 0, self.phi_rad[n - 1] - TAU, self.phi_rad[0])
        } else if i == n {
            (n - 1, 0, self.phi_rad[n - 1], self.phi_rad[0] + TAU)
        } else {
            (i - 1, i, self.phi_rad[i - 1], self.phi_rad[i])
        };
        let w = (phi - p_lo) / (p_hi - p_lo);
        self.t_m[lo] + w * (self.t_m[hi] - self.t_m[lo])
    }
}

/// An angle wrapped into [0, 2π).
pub(super) fn wrap_angle(phi: f64) -> f64 {
    let w = phi.rem_euclid(TAU);
    if w >= TAU {
        0.0
    } else {
        w
    }
}

/// Mean and population standard deviation (two passes).
pub(super) fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::wall::test_support::*;

    #[test]
    fn uniform_map_is_uniform() {
        // The trial-mass runs' map: the Table 4.1 mean everywhere (physics.md §10).
        let map = ThicknessMap::uniform(TABLE_4_1_MEAN_M, REFERENCE_LENGTH_M);
        for (phi, z) in [
            (0.0, 0.0),
            (1.0, 2.0),
            (-7.0, 4.5),
            (100.0, -1.0),
            (3.0, 9.0),
        ] {
            assert_eq!(map.thickness(phi, z), TABLE_4_1_MEAN_M);
        }
        let stats = map.stats();
        assert_eq!(stats.mean_m, TABLE_4_1_MEAN_M);
        assert_eq!(stats.std_m, 0.0);
        assert_eq!(
            (stats.min_m, stats.max_m),
            (TABLE_4_1_MEAN_M, TABLE_4_1_MEAN_M)
        );
        assert_eq!(map.length_m(), REFERENCE_LENGTH_M);
    }

    #[test]
    fn interpolates_between_stations_and_wraps_in_angle() {
        // Two stations (z = 0 and 4500 mm, the ends of the shell) with angles given out of
        // order, and a body-frame profile 10, 12, 14, 16 mm at φ = 0°, 90°, 180°, 270° (the same
        // source angles) at z = 0 and 20 mm flat at z = 4500 mm.
        let map = load_ok(
            "stations.csv",
            "# test map\n\n  angle_deg , z_mm , thickness_mm \n\
             180,0,14\n0,0,10\n3000.0e-3 , 4500 , 20\n90,0,12\n270,0,16\n\
             0,4500,20\n120,4500,20\n",
        );
        let mm = |phi_deg: f64, z_mm: f64| map.thickness(phi_deg.to_radians(), z_mm * 1e-3) * 1e3;
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        // Nodes.
        assert!(close(mm(90.0, 0.0), 12.0));
        assert!(close(mm(270.0, 0.0), 16.0));
        // Linear in φ: halfway between 90° (12) and 180° (14).
        assert!(close(mm(135.0, 0.0), 13.0));
        // Periodic wrap: halfway between 270° (16) and 360° = 0° (10); also from below 0.
        assert!(close(mm(315.0, 0.0), 13.0));
        assert!(close(mm(-45.0, 0.0), 13.0));
        assert!(close(mm(315.0 + 720.0, 0.0), 13.0));
        // Station at z = 4500 mm: given at 0°, 3°, 120°, all 20 mm.
        assert!(close(mm(200.0, 4500.0), 20.0));
        // Linear in z: a quarter of the way from 0 (13) to 4500 mm (20) at φ = 135°.
        assert!(close(mm(135.0, 1125.0), 13.0 + 0.25 * 7.0));
        // Clamped outside the stations.
        assert!(close(mm(135.0, -1000.0), 13.0));
        assert!(close(mm(135.0, 1e6), 20.0));
    }

    #[test]
    fn thinnest_wall_at_a_station_and_between_stations() {
        // z = 0: 10, 12, 14, 16 mm at 0°, 90°, 180°, 270°; z = 4500 mm: 20 mm except 8 mm at 45°.
        let map = load_ok(
            "thin.csv",
            "angle_deg,z_mm,thickness_mm\n0,0,10\n90,0,12\n180,0,14\n270,0,16\n\
             0,4500,20\n45,4500,8\n180,4500,20\n",
        );
        let mm = |z_mm: f64| map.min_thickness_at(z_mm * 1e-3) * 1e3;
        assert!((mm(0.0) - 10.0).abs() < 1e-12);
        assert!((mm(4500.0) - 8.0).abs() < 1e-12);
        // Halfway: at 0° (10 + 20) / 2 = 15, at 45° (11 + 8) / 2 = 9.5, the thinnest.
        assert!((mm(2250.0) - 9.5).abs() < 1e-12);
    }
}
