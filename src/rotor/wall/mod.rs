//! Wall-thickness map t(φ, z) of a tube roll's shell.
//!
//! **In:** a measured map as CSV ([`ThicknessMap::from_csv`]), a synthetic recipe
//! ([`SyntheticSpec`] → [`ThicknessMap::synthetic`]) or one thickness ([`ThicknessMap::uniform`]),
//! plus the shell length.
//! **Out:** the wall thickness t(φ, z) in metres anywhere on the shell
//! ([`ThicknessMap::thickness`]), the thinnest wall at a z ([`ThicknessMap::min_thickness_at`]),
//! its statistics ([`ThicknessMap::stats`]) and the map written
//! back as CSV ([`ThicknessMap::write_csv`]). The section integrator turns t into
//! R_i(φ, z) = R_o − t(φ, z).
//!
//! # Conventions
//! - SI inside: φ in radians, z and t in metres.
//! - φ is the **body-frame** angle, positive about +z (x toward y): with y up and z from the
//!   tending end to the drive end, that is **clockwise seen from the tending end** (looking along
//!   +z) and counter-clockwise seen from the drive end; φ = 0 along +x of the body frame. z runs
//!   along the shell from its tending end (z = 0) to its drive end (z = L).
//! - CSV files use the **source's** convention (thesis Table 4.1, Appendix 1): header
//!   `angle_deg,z_mm,thickness_mm`; the angle in degrees grows **clockwise seen from the tending
//!   end** with 0 = +x — the same direction as φ — so the conversion at input is degrees to
//!   radians, wrapped into [0, 2π) (a CSV point at 90° sits at φ = π/2, on +y). `write_csv`
//!   converts back, so `from_csv(write_csv(m))` reproduces `m` (numbers are written with nine
//!   decimals of a millimetre or a degree).
//!
//! # Storage and interpolation
//! A map is a list of z stations (ascending). Each station keeps its own points sorted by φ in
//! [0, 2π), at least three, **exactly as given**: measured points are not resampled, so nothing is
//! lost and stations may have different angles. Between the points of a station t is linear in φ
//! and periodic (the last point connects to the first through 2π); between stations t is linear
//! in z; below the first and above the last station it is clamped to that station.
//! [`ThicknessMap::stats`] weighs every stored point equally and uses the population standard
//! deviation (divide by N).
//!
//! # CSV input
//! Blank lines and lines starting with `#` are ignored; spaces around values are tolerated. Points
//! with the same z_mm form a station. Problems are [`InputError`]s naming the file and the 1-based
//! line (and the column as the key): unreadable file, empty file, wrong header, wrong column
//! count, non-numeric or non-finite value, an angle beyond ±360°, thickness ≤ 0, z more than
//! 1 mm outside [0, L], duplicate point (same z, angles closer than 1e-9 rad, 0° and 360°
//! included), a station with fewer than three angles, a single station, and stations that do not
//! reach both ends of the shell within [`COVERAGE_SHARE`] (1 %) of its length (so a map written
//! for a shorter shell is refused). Points up to 1 mm outside the shell are kept where they are.
//!
//! # Synthetic maps
//! On a grid of `n_angles` uniform angles φ_i = 2πi/n and `n_stations` uniform stations
//! z_j = L·j/(n − 1):
//! 1. **Harmonics:** H = Σ weight·shape(z)·cos(k(φ − phase − twist·z/L)), shape 1, sin(πz/L) or
//!    z/L. Weights are relative: only their ratios matter. The thickest wall of harmonic k = 1 sits
//!    at φ = phase + twist·z/L.
//! 2. **Random field** (seeded SplitMix64 ([`SplitMix64`]) + Box–Muller, bit-reproducible): angular harmonics
//!    k = 0…6 (k = 0 is an axial change of the mean wall), coefficient standard deviation 1/2 for
//!    k = 0 and 1/k above; each cos/sin coefficient is a function of z with unit variance and
//!    Gaussian axial correlation exp(−Δz²/2ℓ²), ℓ = `correlation_length_m`, built from 16 random
//!    Fourier modes (wavenumbers drawn from N(0, 1/ℓ²), uniform phases). Orders the angle grid
//!    cannot resolve (2k ≥ n_angles) are left out; their random numbers are still drawn, so a finer
//!    grid keeps the same field.
//! 3. **Mix:** the random part is made uncorrelated with the harmonic part over the grid, then the
//!    two are scaled to variances `random_share` and 1 − `random_share` and added.
//! 4. **Target statistics:** a monotone map, sinh-stretch or asinh-squeeze applied separately to
//!    the negative and positive sides of the standardised field (smooth at zero), with its two
//!    parameters solved by damped Newton so that the extremes sit at (min − mean)/std and
//!    (max − mean)/std standard deviations; an affine map then sets mean and std. Mean and std are
//!    exact to rounding; min and max converge to about 1e-12 of the std. Because the map is
//!    monotone the pattern (where thick and thin lie) is kept; the variance share of step 3 refers
//!    to the field before it.

use std::f64::consts::{PI, TAU};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::error::InputError;
use crate::numerics::rng::SplitMix64;

/// Column names of the CSV header, in order.
const HEADER: [&str; 3] = ["angle_deg", "z_mm", "thickness_mm"];
/// How far outside [0, L] a measured station may lie before it is an error, mm.
const Z_TOLERANCE_MM: f64 = 1.0;
/// How far from each end of the shell a measured map's first and last stations may lie, as a
/// share of the shell length (1 %: 45 mm on the reference roll's 4500 mm shell, well under half of
/// its 112.5 mm shell elements). Beyond the stations the wall is the nearest station's, so a map
/// must reach the ends; a measured map may start a few centimetres in (probes cannot sit on the
/// head's weld), and the first bending mode has almost no strain energy in the last 1 % of the
/// shell (∝ sin²(πz/L): 3e-6 of it). A map written for a shorter shell ends far from the drive
/// end and is refused.
pub const COVERAGE_SHARE: f64 = 0.01;
/// Largest magnitude of a CSV angle, degrees: one turn either way.
const MAX_ANGLE_DEG: f64 = 360.0;
/// Angles of one station closer than this (rad) are the same point.
const SAME_ANGLE_RAD: f64 = 1e-9;
/// Highest angular order of the random field.
const RANDOM_MAX_ORDER: u32 = 6;
/// Random Fourier modes per axial coefficient of the random field.
const RANDOM_MODES: usize = 16;

/// Wall thickness t(φ, z) of a shell: z stations, each with a periodic profile in φ.
#[derive(Debug, Clone, PartialEq)]
pub struct ThicknessMap {
    length_m: f64,
    /// Ascending in z; never empty.
    stations: Vec<Station>,
}

/// One z station: points sorted by φ.
#[derive(Debug, Clone, PartialEq)]
struct Station {
    z_m: f64,
    /// Strictly ascending, in [0, 2π), at least three.
    phi_rad: Vec<f64>,
    /// Thickness at each angle, m.
    t_m: Vec<f64>,
}

/// Statistics of a map over its stored points (population standard deviation), m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapStats {
    pub mean_m: f64,
    pub std_m: f64,
    pub min_m: f64,
    pub max_m: f64,
}

/// Recipe of a synthetic map: harmonics plus a seeded smooth random field, mapped onto target
/// statistics over the grid the map is stored on.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticSpec {
    /// Seed of the random field; the same seed gives a bit-identical map.
    pub seed: u64,
    /// Target mean thickness over the grid, m.
    pub mean_m: f64,
    /// Target population standard deviation over the grid, m.
    pub std_m: f64,
    /// Target minimum over the grid, m.
    pub min_m: f64,
    /// Target maximum over the grid, m.
    pub max_m: f64,
    /// Angular harmonics whose amplitude and phase vary along z.
    pub harmonics: Vec<HarmonicSpec>,
    /// Share of the variance coming from the random field, 0..=1.
    pub random_share: f64,
    /// Axial correlation length of the random field, m.
    pub correlation_length_m: f64,
    /// Uniformly spaced angles per station (≥ 3).
    pub n_angles: usize,
    /// Uniformly spaced stations from z = 0 to z = L (≥ 2).
    pub n_stations: usize,
}

/// One angular harmonic: weight·shape(z)·cos(order·(φ − phase − twist·z/L)).
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicSpec {
    /// Angular order k (1: eccentric bore, 2: oval bore; 0: an axial profile of the mean).
    pub order: u32,
    /// Relative amplitude (only ratios between harmonics matter).
    pub weight: f64,
    /// Body-frame angle of the first maximum at z = 0, rad (positive about +z).
    pub phase_rad: f64,
    /// Extra phase reached at z = L (linear in z), rad.
    pub phase_twist_rad: f64,
    /// How the amplitude varies along z.
    pub axial_shape: AxialShape,
}

/// Amplitude factor of a harmonic along the shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxialShape {
    /// 1 everywhere.
    Constant,
    /// sin(πz/L): zero at both ends, largest mid-shell.
    HalfSine,
    /// z/L: zero at the tending end, largest at the drive end.
    Linear,
}

impl AxialShape {
    /// The factor at s = z/L.
    fn factor(self, s: f64) -> f64 {
        match self {
            AxialShape::Constant => 1.0,
            AxialShape::HalfSine => (PI * s).sin(),
            AxialShape::Linear => s,
        }
    }
}

impl HarmonicSpec {
    /// The harmonic's value at angle φ and s = z/L.
    fn value(&self, phi: f64, s: f64) -> f64 {
        let k = f64::from(self.order);
        self.weight
            * self.axial_shape.factor(s)
            * (k * (phi - self.phase_rad - self.phase_twist_rad * s)).cos()
    }
}

impl SyntheticSpec {
    /// Checks that a map of this recipe exists on a shell of `length_m`; the reason says which
    /// field is wrong. [`ThicknessMap::synthetic`] requires this to pass.
    pub fn validate(&self, length_m: f64) -> Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(length_m) {
            return Err(format!(
                "the shell length must be positive, got {length_m} m"
            ));
        }
        if self.n_angles < 3 {
            return Err(format!(
                "n_angles must be at least 3, got {}",
                self.n_angles
            ));
        }
        if self.n_stations < 2 {
            return Err(format!(
                "n_stations must be at least 2, got {}",
                self.n_stations
            ));
        }
        for (name, v) in [
            ("mean_m", self.mean_m),
            ("std_m", self.std_m),
            ("min_m", self.min_m),
            ("max_m", self.max_m),
        ] {
            if !positive(v) {
                return Err(format!("{name} must be a positive number, got {v}"));
            }
        }
        if !(self.min_m < self.mean_m && self.mean_m < self.max_m) {
            return Err(format!(
                "the targets need min_m < mean_m < max_m, got {} / {} / {}",
                self.min_m, self.mean_m, self.max_m
            ));
        }
        let below = (self.mean_m - self.min_m) / self.std_m;
        let above = (self.max_m - self.mean_m) / self.std_m;
        if below * above <= 1.0 {
            return Err(format!(
                "std_m = {} is too large for the range: with this mean, min and max the standard \
                 deviation must be below sqrt((max - mean)(mean - min)) = {}",
                self.std_m,
                ((self.max_m - self.mean_m) * (self.mean_m - self.min_m)).sqrt()
            ));
        }
        let n_points = self.n_angles.saturating_mul(self.n_stations);
        let reach = (n_points as f64 - 1.0).sqrt();
        if below >= reach || above >= reach {
            return Err(format!(
                "min_m and max_m must lie within sqrt(N - 1) = {reach:.3} standard deviations of \
                 mean_m on a grid of N = {n_points} points; use a finer grid"
            ));
        }
        if !(0.0..=1.0).contains(&self.random_share) {
            return Err(format!(
                "random_share must lie in [0, 1], got {}",
                self.random_share
            ));
        }
        if !positive(self.correlation_length_m) {
            return Err(format!(
                "correlation_length_m must be positive, got {}",
                self.correlation_length_m
            ));
        }
        for (i, h) in self.harmonics.iter().enumerate() {
            if !(h.weight.is_finite() && h.phase_rad.is_finite() && h.phase_twist_rad.is_finite()) {
                return Err(format!(
                    "harmonic {}: weight, phase_rad and phase_twist_rad must be finite",
                    i + 1
                ));
            }
            if 2 * u64::from(h.order) >= self.n_angles as u64 {
                return Err(format!(
                    "harmonic {}: order {} needs more than {} angles on the grid, got n_angles = {}",
                    i + 1,
                    h.order,
                    2 * u64::from(h.order),
                    self.n_angles
                ));
            }
        }
        if self.random_share < 1.0 {
            let grid = Grid::new(self.n_angles, self.n_stations, length_m);
            if variance(&harmonic_field(&self.harmonics, &grid)) == 0.0 {
                return Err(
                    "random_share < 1 needs a harmonic that varies over the map (a nonzero \
                     weight and an order ≥ 1 or an axial shape other than Constant)"
                        .to_string(),
                );
            }
        }
        Ok(())
    }
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

    /// Reads a measured map (source convention, see the module doc) for a shell of `length_m`.
    pub fn from_csv(path: &Path, length_m: f64) -> Result<Self, InputError> {
        if !(length_m.is_finite() && length_m > 0.0) {
            return Err(InputError::new(
                path,
                format!(
                    "the shell length must be positive to read a thickness map, got {length_m} m"
                ),
            ));
        }
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot be read: {e}")))?;
        let points = parse_points(path, &text, length_m)?;
        let stations = group_stations(path, points, length_m)?;
        Ok(Self { length_m, stations })
    }

    /// A synthetic map from `spec` on a shell of `length_m` (see the module doc for the method).
    ///
    /// # Panics
    /// If `spec.validate(length_m)` fails; callers reading user input validate first.
    pub fn synthetic(spec: &SyntheticSpec, length_m: f64) -> Self {
        if let Err(reason) = spec.validate(length_m) {
            panic!("invalid synthetic thickness map: {reason}");
        }
        let grid = Grid::new(spec.n_angles, spec.n_stations, length_m);
        let field = mixed_field(spec, &grid);
        let values = fit_statistics(&field, spec);
        let stations = grid
            .z_m
            .iter()
            .zip(values.chunks_exact(spec.n_angles))
            .map(|(&z_m, row)| Station {
                z_m,
                phi_rad: grid.phi_rad.clone(),
                t_m: row.to_vec(),
            })
            .collect();
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

    /// Writes the map as CSV in the source convention (header `angle_deg,z_mm,thickness_mm`,
    /// clockwise degrees, mm), stations in ascending z, angles ascending within a station.
    pub fn write_csv(&self, path: &Path) -> io::Result<()> {
        let mut out = BufWriter::new(File::create(path)?);
        self.write_rows(&mut out)?;
        out.flush()
    }

    /// Shell length the map belongs to, m.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// The header and one row per stored point.
    fn write_rows(&self, out: &mut impl Write) -> io::Result<()> {
        writeln!(out, "{}", HEADER.join(","))?;
        for station in &self.stations {
            let z_mm = decimal(station.z_m * 1e3);
            let mut rows: Vec<(f64, f64)> = station
                .phi_rad
                .iter()
                .zip(&station.t_m)
                .map(|(&phi, &t)| (source_angle_deg(phi), t * 1e3))
                .collect();
            rows.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (angle_deg, t_mm) in rows {
                writeln!(out, "{},{z_mm},{}", decimal(angle_deg), decimal(t_mm))?;
            }
        }
        Ok(())
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
fn wrap_angle(phi: f64) -> f64 {
    let w = phi.rem_euclid(TAU);
    if w >= TAU {
        0.0
    } else {
        w
    }
}

/// Body-frame φ (rad) of a source angle (degrees; both clockwise seen from the tending end).
fn body_angle_rad(angle_deg: f64) -> f64 {
    wrap_angle(angle_deg.rem_euclid(360.0).to_radians())
}

/// Source angle (degrees in [0, 360)) of a body-frame φ in [0, 2π).
fn source_angle_deg(phi_rad: f64) -> f64 {
    phi_rad.to_degrees()
}

/// A number with nine decimals, trailing zeros dropped (`150`, `18.723456789`).
fn decimal(x: f64) -> String {
    let s = format!("{x:.9}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// One measured point as read, with where it came from.
struct Point {
    line: usize,
    angle_deg: f64,
    z_mm: f64,
    phi_rad: f64,
    t_mm: f64,
}

/// Parses header and rows, checking every value on its own.
fn parse_points(path: &Path, text: &str, length_m: f64) -> Result<Vec<Point>, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let expected = HEADER.join(",");
    let Some((header_line, header)) = rows.next() else {
        return Err(InputError::new(
            path,
            format!("the file is empty: expected the header `{expected}`"),
        )
        .at_line(text.lines().count() + 1));
    };
    if !header.split(',').map(str::trim).eq(HEADER) {
        return Err(InputError::new(
            path,
            format!("expected the header `{expected}`, found `{header}`"),
        )
        .at_line(header_line));
    }
    let length_mm = length_m * 1e3;
    let mut points = Vec::new();
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != HEADER.len() {
            return Err(InputError::new(
                path,
                format!(
                    "expected 3 comma-separated values ({}), found {}",
                    HEADER.join(", "),
                    fields.len()
                ),
            )
            .at_line(line));
        }
        let mut values = [0.0; 3];
        for ((value, field), key) in values.iter_mut().zip(&fields).zip(HEADER) {
            let err = |reason: String| InputError::new(path, reason).at_line(line).with_key(key);
            *value = field
                .parse::<f64>()
                .map_err(|_| err(format!("`{field}` is not a number")))?;
            if !value.is_finite() {
                return Err(err(format!("`{field}` is not a finite number")));
            }
        }
        let [angle_deg, z_mm, t_mm] = values;
        if angle_deg.abs() > MAX_ANGLE_DEG {
            return Err(InputError::new(
                path,
                format!(
                    "the angle must lie in [-{MAX_ANGLE_DEG}, {MAX_ANGLE_DEG}] degrees (one turn), \
                     found {angle_deg}"
                ),
            )
            .at_line(line)
            .with_key("angle_deg"));
        }
        if t_mm <= 0.0 {
            return Err(InputError::new(
                path,
                format!("the thickness must be positive, found {t_mm} mm"),
            )
            .at_line(line)
            .with_key("thickness_mm"));
        }
        if !(-Z_TOLERANCE_MM..=length_mm + Z_TOLERANCE_MM).contains(&z_mm) {
            return Err(InputError::new(
                path,
                format!(
                    "z = {z_mm} mm lies outside the shell [0, {length_mm}] mm by more than \
                     {Z_TOLERANCE_MM} mm"
                ),
            )
            .at_line(line)
            .with_key("z_mm"));
        }
        points.push(Point {
            line,
            angle_deg,
            // `+ 0.0` turns −0 into +0 so that both land in one station.
            z_mm: z_mm + 0.0,
            phi_rad: body_angle_rad(angle_deg),
            t_mm,
        });
    }
    if points.is_empty() {
        return Err(InputError::new(path, "no data rows after the header").at_line(header_line));
    }
    Ok(points)
}

/// Groups points into stations of equal z, rejecting duplicate points and sparse stations.
fn group_stations(
    path: &Path,
    mut points: Vec<Point>,
    length_m: f64,
) -> Result<Vec<Station>, InputError> {
    points.sort_by(|a, b| {
        a.z_mm
            .total_cmp(&b.z_mm)
            .then(a.phi_rad.total_cmp(&b.phi_rad))
            .then(a.line.cmp(&b.line))
    });
    let groups: Vec<&[Point]> = points.chunk_by(|a, b| a.z_mm == b.z_mm).collect();
    for group in &groups {
        let last = &group[group.len() - 1];
        let wrap = (group.len() > 1).then(|| (last, &group[0], group[0].phi_rad + TAU));
        let pairs = group
            .windows(2)
            .map(|w| (&w[0], &w[1], w[1].phi_rad))
            .chain(wrap);
        for (a, b, b_phi) in pairs {
            if b_phi - a.phi_rad < SAME_ANGLE_RAD {
                let (first, second) = if a.line < b.line { (a, b) } else { (b, a) };
                return Err(InputError::new(
                    path,
                    format!(
                        "duplicate point: angle {}° at z = {} mm is already given on line {}",
                        second.angle_deg, second.z_mm, first.line
                    ),
                )
                .at_line(second.line)
                .with_key("angle_deg"));
            }
        }
    }
    for group in &groups {
        if group.len() < 3 {
            let first_line = group.iter().map(|p| p.line).min().unwrap_or(0);
            return Err(InputError::new(
                path,
                format!(
                    "the station at z = {} mm has {} distinct angle(s); a periodic profile needs \
                     at least 3",
                    group[0].z_mm,
                    group.len()
                ),
            )
            .at_line(first_line)
            .with_key("z_mm"));
        }
    }
    check_coverage(path, &groups, length_m)?;
    Ok(groups
        .into_iter()
        .map(|group| Station {
            z_m: group[0].z_mm * 1e-3,
            phi_rad: group.iter().map(|p| p.phi_rad).collect(),
            t_m: group.iter().map(|p| p.t_mm * 1e-3).collect(),
        })
        .collect())
}

/// The stations (ascending z) must reach both ends of the shell within [`COVERAGE_SHARE`] of its
/// length; a single station is no map of a shell.
fn check_coverage(path: &Path, groups: &[&[Point]], length_m: f64) -> Result<(), InputError> {
    let (Some(first), Some(last)) = (groups.first(), groups.last()) else {
        return Ok(());
    };
    let line = |g: &[Point]| g.iter().map(|p| p.line).min().unwrap_or(0);
    let length_mm = length_m * 1e3;
    let tol_mm = COVERAGE_SHARE * length_mm;
    let err = |g: &[Point], reason: String| {
        Err(InputError::new(path, reason)
            .at_line(line(g))
            .with_key("z_mm"))
    };
    if groups.len() < 2 {
        return err(
            first,
            format!(
                "the map has a single z station (z = {} mm); it must have stations at both ends \
                 of the {length_mm} mm shell (roll.shell.length_mm)",
                first[0].z_mm
            ),
        );
    }
    let (z0, z1) = (first[0].z_mm, last[0].z_mm);
    let covers = format!(
        "the map's stations cover z = {z0} ... {z1} mm of the shell's 0 ... {length_mm} mm \
         (roll.shell.length_mm)"
    );
    let share = 100.0 * COVERAGE_SHARE;
    if z0 > tol_mm {
        return err(
            first,
            format!(
                "{covers}: the first station must lie within {tol_mm} mm ({share} % of the \
                 length) of the tending end z = 0"
            ),
        );
    }
    if z1 < length_mm - tol_mm {
        return err(
            last,
            format!(
                "{covers}: the last station must lie within {tol_mm} mm ({share} % of the \
                 length) of the drive end z = {length_mm} mm (a map of a shorter shell?)"
            ),
        );
    }
    Ok(())
}

/// The storage grid of a synthetic map; fields on it are station-major (`j * n_angles + i`).
struct Grid {
    phi_rad: Vec<f64>,
    /// s = z/L of each station, 0 and 1 exactly at the ends.
    s: Vec<f64>,
    z_m: Vec<f64>,
}

impl Grid {
    fn new(n_angles: usize, n_stations: usize, length_m: f64) -> Self {
        let phi_rad = (0..n_angles)
            .map(|i| TAU * i as f64 / n_angles as f64)
            .collect();
        let s: Vec<f64> = (0..n_stations)
            .map(|j| j as f64 / (n_stations - 1) as f64)
            .collect();
        let z_m = s.iter().map(|s| s * length_m).collect();
        Self { phi_rad, s, z_m }
    }
}

/// The harmonic part on the grid.
fn harmonic_field(harmonics: &[HarmonicSpec], grid: &Grid) -> Vec<f64> {
    grid.s
        .iter()
        .flat_map(|&s| {
            grid.phi_rad
                .iter()
                .map(move |&phi| harmonics.iter().map(|h| h.value(phi, s)).sum())
        })
        .collect()
}

/// A stationary unit-variance function of z with correlation exp(−Δz²/2ℓ²): random Fourier
/// modes √(2/M)·Σ cos(κ_m z + ψ_m), κ_m ~ N(0, 1/ℓ²), ψ_m ~ U(0, 2π).
struct AxialProcess {
    modes: Vec<(f64, f64)>,
}

impl AxialProcess {
    fn draw(rng: &mut SplitMix64, correlation_length_m: f64) -> Self {
        let modes = (0..RANDOM_MODES)
            .map(|_| {
                let kappa = rng.normal() / correlation_length_m;
                (kappa, TAU * rng.uniform())
            })
            .collect();
        Self { modes }
    }

    fn at(&self, z_m: f64) -> f64 {
        let sum: f64 = self.modes.iter().map(|&(k, p)| (k * z_m + p).cos()).sum();
        sum * (2.0 / self.modes.len() as f64).sqrt()
    }
}

/// The random part on the grid (module doc, step 2).
fn random_field(seed: u64, correlation_length_m: f64, grid: &Grid) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    let n_angles = grid.phi_rad.len() as u64;
    // Every order's numbers are drawn, resolved or not, so the field does not depend on the grid.
    let terms: Vec<(u32, f64, AxialProcess, AxialProcess)> = (0..=RANDOM_MAX_ORDER)
        .map(|k| {
            let amplitude = if k == 0 { 0.5 } else { 1.0 / f64::from(k) };
            let cos = AxialProcess::draw(&mut rng, correlation_length_m);
            let sin = AxialProcess::draw(&mut rng, correlation_length_m);
            (k, amplitude, cos, sin)
        })
        .filter(|&(k, ..)| 2 * u64::from(k) < n_angles)
        .collect();
    let mut field = Vec::with_capacity(grid.z_m.len() * grid.phi_rad.len());
    for &z in &grid.z_m {
        let coefficients: Vec<(f64, f64, f64)> = terms
            .iter()
            .map(|(k, amp, cos, sin)| (f64::from(*k), amp * cos.at(z), amp * sin.at(z)))
            .collect();
        for &phi in &grid.phi_rad {
            let value = coefficients
                .iter()
                .map(|&(k, c, s)| c * (k * phi).cos() + s * (k * phi).sin())
                .sum();
            field.push(value);
        }
    }
    field
}

/// Harmonic and random parts mixed by `random_share` (module doc, step 3), standardised to mean
/// 0 and standard deviation 1.
fn mixed_field(spec: &SyntheticSpec, grid: &Grid) -> Vec<f64> {
    let harmonic = centred(harmonic_field(&spec.harmonics, grid));
    let mut random = centred(random_field(spec.seed, spec.correlation_length_m, grid));
    let var_h = variance(&harmonic);
    if var_h > 0.0 {
        let covariance = harmonic
            .iter()
            .zip(&random)
            .map(|(h, r)| h * r)
            .sum::<f64>()
            / harmonic.len() as f64;
        let beta = covariance / var_h;
        for (r, h) in random.iter_mut().zip(&harmonic) {
            *r -= beta * h;
        }
    }
    let var_r = variance(&random);
    let scale = |share: f64, var: f64| if var > 0.0 { (share / var).sqrt() } else { 0.0 };
    let w_h = scale(1.0 - spec.random_share, var_h);
    let w_r = scale(spec.random_share, var_r);
    let mixed: Vec<f64> = harmonic
        .iter()
        .zip(&random)
        .map(|(h, r)| w_h * h + w_r * r)
        .collect();
    let (mean, std) = mean_std(&mixed);
    mixed.iter().map(|v| (v - mean) / std).collect()
}

/// Odd monotone map, smooth in `c`: sinh-stretch for c > 0, asinh-squeeze for c < 0
/// (both ≈ x + c·x³/6 for small c).
fn tail_map(x: f64, c: f64) -> f64 {
    if c > 0.0 {
        let r = c.sqrt();
        (r * x).sinh() / r
    } else if c < 0.0 {
        let r = (-c).sqrt();
        (r * x).asinh() / r
    } else {
        x
    }
}

/// The standardised field `x` mapped onto the spec's statistics (module doc, step 4).
fn fit_statistics(x: &[f64], spec: &SyntheticSpec) -> Vec<f64> {
    let below = (spec.mean_m - spec.min_m) / spec.std_m;
    let above = (spec.max_m - spec.mean_m) / spec.std_m;
    let [c_neg, c_pos] = solve_tails(x, below, above);
    let y: Vec<f64> = x
        .iter()
        .map(|&v| tail_map(v, if v < 0.0 { c_neg } else { c_pos }))
        .collect();
    let (mean, std) = mean_std(&y);
    y.iter()
        .map(|v| spec.mean_m + spec.std_m * (v - mean) / std)
        .collect()
}

/// Tail parameters (negative side, positive side) that put the standardised minimum at −`below`
/// and the maximum at +`above`, by damped Newton with a forward-difference Jacobian. Returns the
/// best parameters found if the targets cannot be reached.
fn solve_tails(x: &[f64], below: f64, above: f64) -> [f64; 2] {
    const TOLERANCE: f64 = 1e-13;
    const MAX_ITERATIONS: usize = 100;
    const STEP: f64 = 1e-7;
    let (mut i_min, mut i_max) = (0, 0);
    for (i, &v) in x.iter().enumerate() {
        if v < x[i_min] {
            i_min = i;
        }
        if v > x[i_max] {
            i_max = i;
        }
    }
    // Keep sinh's argument below 50: no overflow, and stretch enough for any reachable target.
    let limit = (50.0 / x[i_min].abs().max(x[i_max].abs())).powi(2);
    let residual = |c: [f64; 2]| -> [f64; 2] {
        let y: Vec<f64> = x
            .iter()
            .map(|&v| tail_map(v, if v < 0.0 { c[0] } else { c[1] }))
            .collect();
        let (mean, std) = mean_std(&y);
        [
            (y[i_min] - mean) / std + below,
            (y[i_max] - mean) / std - above,
        ]
    };
    let norm = |r: [f64; 2]| r[0].hypot(r[1]);
    let mut c = [0.0; 2];
    let mut r = residual(c);
    for _ in 0..MAX_ITERATIONS {
        if norm(r) < TOLERANCE {
            break;
        }
        let mut jac = [[0.0; 2]; 2];
        for k in 0..2 {
            let mut shifted = c;
            shifted[k] += STEP;
            let r_shifted = residual(shifted);
            jac[0][k] = (r_shifted[0] - r[0]) / STEP;
            jac[1][k] = (r_shifted[1] - r[1]) / STEP;
        }
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        if !det.is_normal() {
            break;
        }
        let step = [
            (jac[0][1] * r[1] - jac[1][1] * r[0]) / det,
            (jac[1][0] * r[0] - jac[0][0] * r[1]) / det,
        ];
        let mut damping = 1.0;
        let mut improved = false;
        while damping > 1e-6 {
            let trial = [
                (c[0] + damping * step[0]).clamp(-limit, limit),
                (c[1] + damping * step[1]).clamp(-limit, limit),
            ];
            let r_trial = residual(trial);
            if norm(r_trial) < norm(r) {
                c = trial;
                r = r_trial;
                improved = true;
                break;
            }
            damping *= 0.5;
        }
        if !improved {
            break;
        }
    }
    c
}

/// Mean and population standard deviation (two passes).
fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Population variance.
fn variance(values: &[f64]) -> f64 {
    mean_std(values).1.powi(2)
}

/// The values minus their mean.
fn centred(mut values: Vec<f64>) -> Vec<f64> {
    let (mean, _) = mean_std(&values);
    for v in &mut values {
        *v -= mean;
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// Thesis Table 4.1 (`docs/thesis-data.md` §2): wall thickness of the measured roll, m.
    const TABLE_4_1_MEAN_M: f64 = 18.72e-3;
    const TABLE_4_1_STD_M: f64 = 0.30e-3;
    const TABLE_4_1_MIN_M: f64 = 17.86e-3;
    const TABLE_4_1_MAX_M: f64 = 19.59e-3;
    /// Reference roll shell length between heads (`docs/physics.md` §10), m.
    const REFERENCE_LENGTH_M: f64 = 4.5;
    /// The brief's tolerance on min and max of a synthetic map: 0.02 mm.
    const MIN_MAX_TOLERANCE_M: f64 = 0.02e-3;
    /// The brief's tolerance on mean and std of a synthetic map: 1e-9 relative.
    const MOMENT_TOLERANCE: f64 = 1e-9;
    /// CSV numbers carry nine decimals of a mm: round-trip error ≤ 0.5e-9 mm = 5e-13 m.
    const CSV_ROUNDING_M: f64 = 5e-13;

    fn shipped_map_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/maps/reference-roll-thickness.csv")
    }

    /// The recipe of the shipped map (physics.md §10: Table 4.1 statistics, an eccentric bore
    /// (k = 1) and an oval bore (k = 2) both varying along z, some random field).
    fn reference_roll_spec() -> SyntheticSpec {
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
    fn table_spec(seed: u64, n_angles: usize, n_stations: usize) -> SyntheticSpec {
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

    fn assert_hits_targets(stats: MapStats, spec: &SyntheticSpec) {
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

    /// Writes `text` to a fresh file, reads it as a map of a 4.5 m shell, removes the file.
    fn load(name: &str, text: &str) -> (PathBuf, Result<ThicknessMap, InputError>) {
        let dir = std::env::temp_dir().join(format!("rotorsweep-thickness-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let result = ThicknessMap::from_csv(&path, REFERENCE_LENGTH_M);
        std::fs::remove_file(&path).unwrap();
        (path, result)
    }

    fn load_ok(name: &str, text: &str) -> ThicknessMap {
        let (_, result) = load(name, text);
        result.unwrap()
    }

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
    fn csv_round_trip_reproduces_map() {
        let original = ThicknessMap::synthetic(&table_spec(7, 12, 5), REFERENCE_LENGTH_M);
        let dir = std::env::temp_dir().join(format!("rotorsweep-thickness-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("round-trip.csv");
        original.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let read = ThicknessMap::from_csv(&path, REFERENCE_LENGTH_M).unwrap();
        std::fs::remove_file(&path).unwrap();

        assert!(text.starts_with("angle_deg,z_mm,thickness_mm\n"));
        // 12 angles × 5 stations, one row each, plus the header.
        assert_eq!(text.lines().count(), 61);
        assert_eq!(read.length_m(), original.length_m());
        assert_eq!(read.stations.len(), original.stations.len());
        for (a, b) in original.stations.iter().zip(&read.stations) {
            // z: 4500 mm / 4 = 1125 mm steps, written to 1e-9 mm.
            assert!((a.z_m - b.z_m).abs() < CSV_ROUNDING_M);
            assert_eq!(a.phi_rad.len(), b.phi_rad.len());
            for ((pa, ta), (pb, tb)) in a
                .phi_rad
                .iter()
                .zip(&a.t_m)
                .zip(b.phi_rad.iter().zip(&b.t_m))
            {
                // 1e-9° written precision ≈ 1.7e-11 rad.
                assert!((pa - pb).abs() < 1e-10, "{pa} vs {pb}");
                assert!((ta - tb).abs() < CSV_ROUNDING_M, "{ta} vs {tb}");
            }
        }
        let (sa, sb) = (original.stats(), read.stats());
        assert!((sa.mean_m - sb.mean_m).abs() < CSV_ROUNDING_M);
        assert!((sa.std_m - sb.std_m).abs() < CSV_ROUNDING_M);
    }

    #[test]
    fn source_angle_is_the_body_angle() {
        // Source convention (thesis-data.md §2): angle grows clockwise seen from the tending end,
        // which with y up and z toward the drive end is the positive sense about +z: a thick
        // spot at angle_deg = 90 lies at body-frame φ = π/2 (on +y).
        let map = load_ok(
            "angles.csv",
            "angle_deg,z_mm,thickness_mm\n0,0,18\n90,0,20\n180,0,18\n270,0,16\n\
             0,4500,18\n90,4500,20\n180,4500,18\n270,4500,16\n",
        );
        assert!((map.thickness(0.5 * PI, 0.0) - 0.020).abs() < 1e-15);
        assert!((map.thickness(1.5 * PI, 0.0) - 0.016).abs() < 1e-15);
        assert!((map.thickness(0.0, 0.0) - 0.018).abs() < 1e-15);
        assert!((map.thickness(PI, 0.0) - 0.018).abs() < 1e-15);
        // Writing converts back: the 20 mm point is written at 90°.
        let dir = std::env::temp_dir().join(format!("rotorsweep-thickness-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("angles-out.csv");
        map.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(
            text,
            "angle_deg,z_mm,thickness_mm\n0,0,18\n90,0,20\n180,0,18\n270,0,16\n\
             0,4500,18\n90,4500,20\n180,4500,18\n270,4500,16\n"
        );
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

    #[test]
    fn points_up_to_1_mm_outside_the_shell_are_accepted() {
        // The brief: z outside [0, L] by more than 1 mm is an error, so 0.9 mm beyond is not.
        let map = load_ok(
            "edges.csv",
            "angle_deg,z_mm,thickness_mm\n0,-0.9,18\n120,-0.9,18\n240,-0.9,18\n\
             0,4500.9,19\n120,4500.9,19\n240,4500.9,19\n",
        );
        assert!((map.thickness(0.0, 2.25) - 0.0185).abs() < 1e-6);
    }

    #[test]
    fn csv_errors_name_file_and_line() {
        const HEAD: &str = "angle_deg,z_mm,thickness_mm\n";
        let station = |z: &str| format!("0,{z},18\n120,{z},18\n240,{z},18\n");
        // (file name, text, expected line, expected key, words in the reason)
        let cases: Vec<(&str, String, usize, Option<&str>, &str)> = vec![
            ("empty.csv", String::new(), 1, None, "empty"),
            (
                "comments-only.csv",
                "# nothing\n\n".into(),
                3,
                None,
                "empty",
            ),
            (
                "header-only.csv",
                format!("# c\n{HEAD}"),
                2,
                None,
                "no data rows",
            ),
            (
                "wrong-header.csv",
                "# c\nangle,z,t\n0,0,18\n".into(),
                2,
                None,
                "expected the header",
            ),
            (
                "swapped-header.csv",
                "z_mm,angle_deg,thickness_mm\n".into(),
                1,
                None,
                "expected the header",
            ),
            (
                "columns.csv",
                format!("{HEAD}0,0,18\n120,0\n"),
                3,
                None,
                "found 2",
            ),
            (
                "columns4.csv",
                format!("{HEAD}0,0,18,\n"),
                2,
                None,
                "found 4",
            ),
            (
                "not-a-number.csv",
                format!("{HEAD}0,0,18\nx,0,18\n"),
                3,
                Some("angle_deg"),
                "not a number",
            ),
            (
                "z-nan-text.csv",
                format!("{HEAD}0,abc,18\n"),
                2,
                Some("z_mm"),
                "not a number",
            ),
            (
                "nan.csv",
                format!("{HEAD}\n0,0,NaN\n"),
                3,
                Some("thickness_mm"),
                "not a finite",
            ),
            (
                "inf.csv",
                format!("{HEAD}0,inf,18\n"),
                2,
                Some("z_mm"),
                "not a finite",
            ),
            (
                "zero.csv",
                format!("{HEAD}0,0,18\n120,0,0\n"),
                3,
                Some("thickness_mm"),
                "positive",
            ),
            (
                "negative.csv",
                format!("{HEAD}0,0,-1\n"),
                2,
                Some("thickness_mm"),
                "positive",
            ),
            (
                "z-high.csv",
                format!("{HEAD}0,4501.5,18\n"),
                2,
                Some("z_mm"),
                "outside the shell",
            ),
            (
                "z-low.csv",
                format!("{HEAD}{}0,-2,18\n", station("0")),
                5,
                Some("z_mm"),
                "outside",
            ),
            (
                "sparse.csv",
                format!("{HEAD}{}# gap\n0,150,18\n180,150,18\n", station("0")),
                6,
                Some("z_mm"),
                "2 distinct angle",
            ),
            (
                "duplicate.csv",
                format!("{HEAD}{}{}120,150,19\n", station("0"), station("150")),
                8,
                Some("angle_deg"),
                "already given on line 6",
            ),
            (
                "huge-angle.csv",
                format!("{HEAD}{}1e308,4500,18\n", station("0")),
                5,
                Some("angle_deg"),
                "[-360, 360]",
            ),
            // One station (at z = 0): no map of a shell; reported at its first row.
            (
                "one-station.csv",
                format!("{HEAD}# only z = 0\n{}", station("0")),
                3,
                Some("z_mm"),
                "single z station",
            ),
            // Stations up to 1200 mm of the 4500 mm shell (issue 9): at the last station's row.
            (
                "short.csv",
                format!("{HEAD}{}{}", station("0"), station("1200")),
                5,
                Some("z_mm"),
                "cover z = 0 ... 1200 mm",
            ),
            // 1 % of 4500 mm is 45 mm: a first station at 46 mm is too far from the tending end.
            (
                "late-start.csv",
                format!("{HEAD}{}{}", station("46"), station("4500")),
                2,
                Some("z_mm"),
                "within 45 mm",
            ),
            (
                "duplicate-360.csv",
                format!("{HEAD}{}360,0,19\n", station("0")),
                5,
                Some("angle_deg"),
                "already given on line 2",
            ),
        ];
        for (name, text, line, key, words) in cases {
            let (path, result) = load(name, &text);
            let err = result.expect_err(name);
            assert_eq!(err.file, path, "{name}");
            assert_eq!(err.line, Some(line), "{name}: {err}");
            assert_eq!(err.key.as_deref(), key, "{name}: {err}");
            assert!(err.reason.contains(words), "{name}: {err}");
            assert!(err
                .to_string()
                .starts_with(&format!("{}:{line}:", path.display())));
        }
    }

    #[test]
    fn a_map_must_cover_its_shell() {
        let station = |z: &str| format!("0,{z},18\n120,{z},18\n240,{z},18\n");
        // Stations 45 mm (1 % of 4500 mm) in from both ends still cover the shell.
        let text = format!(
            "angle_deg,z_mm,thickness_mm\n{}{}",
            station("45"),
            station("4455")
        );
        load_ok("inset.csv", &text);
        // The shipped 4500 mm map on a 6000 mm shell: refused at its last station (z = 4500 mm,
        // the last 36 rows of the file).
        let shipped = shipped_map_path();
        let err = ThicknessMap::from_csv(&shipped, 6.0).unwrap_err();
        let text = std::fs::read_to_string(&shipped).unwrap();
        let first_4500 = text
            .lines()
            .position(|l| l.split(',').nth(1) == Some("4500"))
            .unwrap()
            + 1;
        assert_eq!(err.line, Some(first_4500), "{err}");
        assert_eq!(err.key.as_deref(), Some("z_mm"), "{err}");
        assert!(err.reason.contains("a map of a shorter shell"), "{err}");
    }

    #[test]
    fn missing_file_and_bad_length_are_errors() {
        let path = Path::new("/nonexistent/rotorsweep/thickness.csv");
        let err = ThicknessMap::from_csv(path, REFERENCE_LENGTH_M).unwrap_err();
        assert_eq!(err.file, path);
        assert_eq!(err.line, None);
        assert!(err.reason.starts_with("cannot be read: "), "{err}");
        assert!(err.reason.contains("No such file"), "{err}");
        let err = ThicknessMap::from_csv(&shipped_map_path(), -1.0).unwrap_err();
        assert!(err.reason.contains("length"), "{err}");
    }

    #[test]
    fn synthetic_hits_table_4_1_statistics() {
        // The brief's recipe on the shipped grid (36 angles × 31 stations over 4.5 m).
        let spec = table_spec(1, 36, 31);
        let stats = ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M).stats();
        assert_hits_targets(stats, &spec);
        // The fit converges far inside the 0.02 mm requirement: 1e-9 mm.
        assert!((stats.min_m - TABLE_4_1_MIN_M).abs() < 1e-12, "{stats:?}");
        assert!((stats.max_m - TABLE_4_1_MAX_M).abs() < 1e-12, "{stats:?}");
    }

    #[test]
    fn synthetic_hits_targets_across_seeds_shares_grids_and_skews() {
        for seed in 1..=6 {
            for share in [0.0, 0.3, 0.7, 1.0] {
                for (n_angles, n_stations) in [(8, 6), (36, 31), (72, 61)] {
                    let spec = SyntheticSpec {
                        random_share: share,
                        ..table_spec(seed, n_angles, n_stations)
                    };
                    let stats = ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M).stats();
                    assert_hits_targets(stats, &spec);
                }
            }
        }
        // Skewed targets: extremes 1.5 and 4 standard deviations from the mean (invented).
        for (min_m, max_m) in [(0.01755, 0.01992), (0.01752, 0.01965)] {
            let spec = SyntheticSpec {
                min_m,
                max_m,
                ..table_spec(3, 36, 31)
            };
            assert_hits_targets(
                ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M).stats(),
                &spec,
            );
        }
    }

    #[test]
    fn synthetic_same_seed_identical_different_seed_differs() {
        let bits = |m: &ThicknessMap| -> Vec<u64> {
            m.stations
                .iter()
                .flat_map(|s| s.t_m.iter().map(|t| t.to_bits()))
                .collect()
        };
        let a = ThicknessMap::synthetic(&reference_roll_spec(), REFERENCE_LENGTH_M);
        let b = ThicknessMap::synthetic(&reference_roll_spec(), REFERENCE_LENGTH_M);
        assert_eq!(bits(&a), bits(&b));
        let other = SyntheticSpec {
            seed: 20002,
            ..reference_roll_spec()
        };
        let c = ThicknessMap::synthetic(&other, REFERENCE_LENGTH_M);
        let largest_change = a
            .stations
            .iter()
            .zip(&c.stations)
            .flat_map(|(sa, sc)| sa.t_m.iter().zip(&sc.t_m).map(|(x, y)| (x - y).abs()))
            .fold(0.0, f64::max);
        // A different random field moves some point by more than 0.01 mm (std 0.30 mm, share 0.3).
        assert!(largest_change > 1e-5, "{largest_change}");
    }

    #[test]
    fn seeded_maps_are_bit_identical_to_their_recorded_fingerprints() {
        use sha2::{Digest, Sha256};
        // SHA-256 of every station's z, angles and thicknesses (f64 little-endian bits), recorded
        // from the generator before the RNG moved to `numerics::rng`: the seeded maps must not
        // change by a bit.
        let cases = [
            (
                reference_roll_spec(),
                "39c0ecf5a386b6909b48ad97615eafe3a395bdf6190eff6c80e20a2ef4b06f45",
            ),
            (
                table_spec(7, 12, 5),
                "db3dfda88153879dd45ec009a02fdf6bc33f2b6d97195c2b1c711f5062c0ce1b",
            ),
            (
                SyntheticSpec {
                    random_share: 1.0,
                    ..table_spec(3, 72, 61)
                },
                "f5d173433b9d96144846288422e6a863651339135593e233b56ca5acab2c9fa5",
            ),
        ];
        for (spec, expected) in cases {
            let map = ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M);
            let mut hash = Sha256::new();
            for s in &map.stations {
                hash.update(s.z_m.to_le_bytes());
                for (phi, t) in s.phi_rad.iter().zip(&s.t_m) {
                    hash.update(phi.to_le_bytes());
                    hash.update(t.to_le_bytes());
                }
            }
            let hex: String = hash.finalize().iter().map(|b| format!("{b:02x}")).collect();
            assert_eq!(hex, expected, "seed {}", spec.seed);
        }
    }

    #[test]
    fn harmonic_phase_and_twist_place_the_thick_wall() {
        // One eccentric-bore harmonic, no random field: the thickest wall of each station sits at
        // φ = phase + twist·z/L (module doc), here 1.0 rad at z = 0 and 1.0 + π/2 rad at z = L.
        let spec = SyntheticSpec {
            harmonics: vec![HarmonicSpec {
                order: 1,
                weight: 1.0,
                phase_rad: 1.0,
                phase_twist_rad: 0.5 * PI,
                axial_shape: AxialShape::Constant,
            }],
            random_share: 0.0,
            ..table_spec(1, 360, 3)
        };
        let map = ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M);
        for (station, expected) in map
            .stations
            .iter()
            .zip([1.0, 1.0 + 0.25 * PI, 1.0 + 0.5 * PI])
        {
            let (i_max, _) = station
                .t_m
                .iter()
                .enumerate()
                .fold(
                    (0, f64::MIN),
                    |best, (i, &t)| if t > best.1 { (i, t) } else { best },
                );
            // The grid has 1° steps.
            assert!((station.phi_rad[i_max] - expected).abs() <= 0.5_f64.to_radians() + 1e-12);
        }
    }

    #[test]
    fn invalid_specs_are_rejected() {
        let good = reference_roll_spec();
        assert_eq!(good.validate(REFERENCE_LENGTH_M), Ok(()));
        assert!(good.validate(0.0).is_err());
        let bad = [
            SyntheticSpec {
                n_angles: 2,
                ..good.clone()
            },
            SyntheticSpec {
                n_stations: 1,
                ..good.clone()
            },
            SyntheticSpec {
                std_m: 0.0,
                ..good.clone()
            },
            SyntheticSpec {
                min_m: 0.019,
                ..good.clone()
            },
            // std 1 mm with extremes under 1 mm away: impossible (Bhatia–Davis).
            SyntheticSpec {
                std_m: 1e-3,
                ..good.clone()
            },
            // 9 points reach at most √8 ≈ 2.83 std from the mean; the table needs 2.87 and 2.9.
            SyntheticSpec {
                n_angles: 3,
                n_stations: 3,
                harmonics: vec![],
                random_share: 1.0,
                ..good.clone()
            },
            SyntheticSpec {
                random_share: 1.5,
                ..good.clone()
            },
            SyntheticSpec {
                correlation_length_m: 0.0,
                ..good.clone()
            },
            SyntheticSpec {
                n_angles: 4,
                ..good.clone()
            },
            SyntheticSpec {
                harmonics: vec![],
                ..good.clone()
            },
        ];
        for spec in bad {
            assert!(spec.validate(REFERENCE_LENGTH_M).is_err(), "{spec:?}");
        }
    }

    #[test]
    fn shipped_reference_map_has_table_4_1_statistics() {
        let map = ThicknessMap::from_csv(&shipped_map_path(), REFERENCE_LENGTH_M).unwrap();
        assert_eq!(map.length_m(), REFERENCE_LENGTH_M);
        assert_eq!(map.stations.len(), 31);
        assert!(map.stations.iter().all(|s| s.phi_rad.len() == 36));
        // The stored numbers are rounded to 1e-9 mm, far inside the tolerances.
        assert_hits_targets(map.stats(), &reference_roll_spec());
    }

    #[test]
    fn shipped_reference_map_matches_generator() {
        let shipped = ThicknessMap::from_csv(&shipped_map_path(), REFERENCE_LENGTH_M).unwrap();
        let generated = ThicknessMap::synthetic(&reference_roll_spec(), REFERENCE_LENGTH_M);
        for station in &generated.stations {
            for (&phi, &t) in station.phi_rad.iter().zip(&station.t_m) {
                let d = (shipped.thickness(phi, station.z_m) - t).abs();
                assert!(
                    d < 1e-12,
                    "regenerate the map: {d} m off at φ = {phi}, z = {}",
                    station.z_m
                );
            }
        }
    }

    /// Regenerates `studies/maps/reference-roll-thickness.csv`:
    /// `cargo test --release write_reference_map -- --ignored`.
    #[test]
    #[ignore]
    fn write_reference_map() {
        let spec = reference_roll_spec();
        let map = ThicknessMap::synthetic(&spec, REFERENCE_LENGTH_M);
        let stats = map.stats();
        let shape = |s: AxialShape| match s {
            AxialShape::Constant => "constant along z",
            AxialShape::HalfSine => "amplitude sin(pi z/L)",
            AxialShape::Linear => "amplitude z/L",
        };
        let mut text = vec![
            "# Wall-thickness map of the reference roll's shell (rotorsweep, physics.md §10)."
                .to_string(),
            "# SYNTHETIC, not measured: rotorsweep::rotor::wall::ThicknessMap::synthetic, regenerate \
             with `cargo test --release write_reference_map -- --ignored`."
                .to_string(),
            format!(
                "# seed {}; shell length {} mm; grid {} angles x {} stations; target statistics \
                 of thesis Table 4.1: mean {} mm, std {} mm (population, over this grid), \
                 min {} mm, max {} mm.",
                spec.seed,
                REFERENCE_LENGTH_M * 1e3,
                spec.n_angles,
                spec.n_stations,
                spec.mean_m * 1e3,
                spec.std_m * 1e3,
                spec.min_m * 1e3,
                spec.max_m * 1e3
            ),
            format!(
                "# achieved: mean {:.6} mm, std {:.6} mm, min {:.6} mm, max {:.6} mm.",
                stats.mean_m * 1e3,
                stats.std_m * 1e3,
                stats.min_m * 1e3,
                stats.max_m * 1e3
            ),
        ];
        for h in &spec.harmonics {
            let what = match h.order {
                1 => "eccentric bore",
                2 => "oval bore",
                _ => "harmonic",
            };
            let sign = if h.phase_twist_rad < 0.0 { '-' } else { '+' };
            text.push(format!(
                "# k = {} ({what}): relative weight {}, {}, thickest wall at body-frame \
                 (positive about +z, clockwise seen from the tending end) angle {} {sign} {} * z/L rad (plus multiples of 2 pi / k).",
                h.order,
                h.weight,
                shape(h.axial_shape),
                h.phase_rad,
                h.phase_twist_rad.abs()
            ));
        }
        text.push(format!(
            "# random field: {} of the variance, axial correlation length {} m.",
            spec.random_share, spec.correlation_length_m
        ));
        text.push(
            "# Conventions (the source's): angle_deg grows CLOCKWISE seen from the tending end, \
             0 = +x of the roll's body frame; z_mm from the tending end (0) to the drive end; \
             thickness_mm is the wall thickness (variation on the inner surface)."
                .to_string(),
        );
        let path = shipped_map_path();
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let mut out = BufWriter::new(File::create(&path).unwrap());
        for line in text {
            writeln!(out, "{line}").unwrap();
        }
        map.write_rows(&mut out).unwrap();
        out.flush().unwrap();
    }
}
