//! The wall-thickness map as CSV: reading a measured map and writing a map back.
//!
//! **In:** a CSV file and the shell length L ([`ThicknessMap::from_csv`]). **Out:** the
//! [`ThicknessMap`] of its points (φ in radians, z and t in metres), or an [`InputError`] naming
//! the file and the line; a map written as CSV ([`ThicknessMap::write_csv`]). Records are split by
//! the `csv` crate (quoted fields allowed); [`data_rows`] gives each record with its 1-based line.
//!
//! # Convention
//! CSV files use the **source's** convention (thesis Table 4.1, Appendix 1): header
//! `angle_deg,z_mm,thickness_mm`; the angle in degrees grows **clockwise seen from the tending
//! end** with 0 = +x — the same direction as φ — so the conversion at input is degrees to
//! radians, wrapped into [0, 2π) (a CSV point at 90° sits at φ = π/2, on +y). `write_csv`
//! converts back, so `from_csv(write_csv(m))` reproduces `m` (numbers are written with nine
//! decimals of a millimetre or a degree).
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

use std::f64::consts::TAU;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use ::csv::{ReaderBuilder, StringRecord, Writer};

use super::map::{wrap_angle, Station, ThicknessMap};
use crate::error::InputError;

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

impl ThicknessMap {
    /// Reads a measured map (source convention, module doc) for a shell of `length_m`.
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

    /// Writes the map as CSV in the source convention (header `angle_deg,z_mm,thickness_mm`,
    /// clockwise degrees, mm), stations in ascending z, angles ascending within a station.
    pub fn write_csv(&self, path: &Path) -> io::Result<()> {
        let mut out = BufWriter::new(File::create(path)?);
        self.write_rows(&mut out)?;
        out.flush()
    }

    /// The header and one row per stored point.
    pub(super) fn write_rows(&self, out: &mut impl Write) -> io::Result<()> {
        let mut writer = Writer::from_writer(out);
        writer.write_record(HEADER)?;
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
                writer.write_record([decimal(angle_deg), z_mm.clone(), decimal(t_mm)])?;
            }
        }
        writer.flush()
    }
}

/// The data records of a CSV text (`path` names it in errors), each with its 1-based line: split
/// by the `csv` crate (commas, quoted fields allowed), every record kept as it is except blank
/// lines (also of spaces only) and lines whose first non-blank character is `#`. Fields are not
/// trimmed. The line is where the record ends (its only line but for quoted line breaks), from
/// the reader's position after it (`csv` counts line feeds; a record read through its `\n` is
/// one line above the position, one ended at a `\r` or at the end of the text is on it).
pub(crate) fn data_rows<'a>(
    path: &'a Path,
    text: &'a str,
) -> impl Iterator<Item = Result<(usize, StringRecord), InputError>> + 'a {
    let mut records = ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes())
        .into_records();
    std::iter::from_fn(move || loop {
        let record = match records.next()? {
            Ok(record) => record,
            Err(e) => {
                let line = e.position().map_or(0, |p| p.line() as usize);
                return Some(Err(InputError::new(path, e.to_string()).at_line(line)));
            }
        };
        let end = records.reader().position();
        let through_newline = text.as_bytes()[..end.byte() as usize].ends_with(b"\n");
        let line = (end.line() - u64::from(through_newline)) as usize;
        let first = record.get(0).unwrap_or("").trim();
        if (record.len() == 1 && first.is_empty()) || first.starts_with('#') {
            continue;
        }
        return Some(Ok((line, record)));
    })
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
    let mut rows = data_rows(path, text);
    let expected = HEADER.join(",");
    let Some(header) = rows.next() else {
        return Err(InputError::new(
            path,
            format!("the file is empty: expected the header `{expected}`"),
        )
        .at_line(text.lines().count() + 1));
    };
    let (header_line, header) = header?;
    if !header.iter().map(str::trim).eq(HEADER) {
        let header = text.lines().nth(header_line - 1).map_or("", str::trim);
        return Err(InputError::new(
            path,
            format!("expected the header `{expected}`, found `{header}`"),
        )
        .at_line(header_line));
    }
    let length_mm = length_m * 1e3;
    let mut points = Vec::new();
    for row in rows {
        let (line, row) = row?;
        let fields: Vec<&str> = row.iter().map(str::trim).collect();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::wall::test_support::*;
    use std::f64::consts::PI;

    #[test]
    fn csv_round_trip_reproduces_map() {
        let original = ThicknessMap::synthetic(&table_spec(7, 12, 5), REFERENCE_LENGTH_M);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("round-trip.csv");
        original.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let read = ThicknessMap::from_csv(&path, REFERENCE_LENGTH_M).unwrap();

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
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("angles-out.csv");
        map.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "angle_deg,z_mm,thickness_mm\n0,0,18\n90,0,20\n180,0,18\n270,0,16\n\
             0,4500,18\n90,4500,20\n180,4500,18\n270,4500,16\n"
        );
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
    fn shipped_reference_map_has_table_4_1_statistics() {
        let map = ThicknessMap::from_csv(&shipped_map_path(), REFERENCE_LENGTH_M).unwrap();
        assert_eq!(map.length_m(), REFERENCE_LENGTH_M);
        assert_eq!(map.stations.len(), 31);
        assert!(map.stations.iter().all(|s| s.phi_rad.len() == 36));
        // The stored numbers are rounded to 1e-9 mm, far inside the tolerances.
        assert_hits_targets(map.stats(), &reference_roll_spec());
    }

    #[test]
    fn writer_reproduces_the_shipped_map_byte_for_byte() {
        // The shipped map is its comment lines, then `write_rows` of the reference recipe.
        let shipped = std::fs::read_to_string(shipped_map_path()).unwrap();
        let rows = &shipped[shipped.find("angle_deg,").unwrap()..];
        let mut written = Vec::new();
        ThicknessMap::synthetic(&reference_roll_spec(), REFERENCE_LENGTH_M)
            .write_rows(&mut written)
            .unwrap();
        assert!(written.as_slice() == rows.as_bytes());
    }

    #[test]
    fn data_rows_name_the_line_of_each_record() {
        // Comments (also indented), blank lines (also of spaces), LF and CRLF line ends, a quoted
        // field with a comma, and a last record without a line end.
        let text = "# c\n\n  a , b \n\n1,2\n   \n  # indented\n#x\r\n3,\"4,5\"\r\n\r\n6";
        let rows: Vec<(usize, Vec<String>)> = data_rows(Path::new("t.csv"), text)
            .map(|r| {
                let (line, record) = r.unwrap();
                (line, record.iter().map(|f| f.trim().to_string()).collect())
            })
            .collect();
        let expected: Vec<(usize, Vec<&str>)> = vec![
            (3, vec!["a", "b"]),
            (5, vec!["1", "2"]),
            (9, vec!["3", "4,5"]),
            (11, vec!["6"]),
        ];
        assert_eq!(rows.len(), expected.len(), "{rows:?}");
        for ((line, fields), (e_line, e_fields)) in rows.iter().zip(&expected) {
            assert_eq!(
                (line, fields),
                (e_line, &e_fields.iter().map(|f| f.to_string()).collect())
            );
        }
    }
}
