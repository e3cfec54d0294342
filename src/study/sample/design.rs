//! The unit points of a sampled study: n points in the open unit cube (0, 1)^d, one coordinate
//! per sampled parameter, which the parameters' quantile functions turn into samples.
//!
//! In: the method, the number of points n, the dimension d and the seed. Out: the points, row
//! by row, and for `saltelli` the matrix and row each job belongs to ([`Row`]).
//!
//! Methods:
//! - `monte-carlo`: independent uniforms from the project's seeded SplitMix64 stream
//!   ([`crate::numerics::rng`]), row by row.
//! - `latin-hypercube`: per coordinate a random permutation π of the n strata (Fisher–Yates on
//!   the same stream) and a uniform offset in each, u = (π(i) + U)/n (McKay, Beckman & Conover
//!   1979): every marginal has exactly one point in each of the n equal strata.
//! - `sobol`: the Owen-scrambled Sobol' sequence of the `sobol_burley` crate (Burley 2020,
//!   Joe–Kuo direction numbers, at most 256 coordinates and 2¹⁶ points); the seed picks the
//!   scramble. Its points carry 24 bits; each is moved to the middle of its 2⁻²⁴ cell so that
//!   none is 0 (normal quantiles stay within ±5.3σ).
//! - `saltelli`: the radial design for Sobol' indices (Saltelli et al. 2010, *Comput. Phys.
//!   Commun.* 181, 259): scrambled Sobol' points of dimension 2d, the first d coordinates the
//!   rows of A, the last d those of B, and for each parameter i the matrix AB_i (A with column i
//!   from B). Jobs are the n rows of A, then of B, then of AB_1 … AB_d: n (d + 2) in all.
//! - `morris`: n one-at-a-time trajectories for elementary effects (Morris 1991,
//!   *Technometrics* 33, 161; the sensitivity table reads μ* of Campolongo, Cariboni & Saltelli
//!   2007). On a grid of p (even) levels ℓ ∈ {0, 1/(p − 1), …, 1} each trajectory starts at a
//!   base point whose coordinates are drawn from {0, …, 1 − Δ}, Δ = p/(2(p − 1)), and moves every
//!   coordinate once by ±Δ in a random order with a random sign (Morris's B* = (J x* + (Δ/2)
//!   ((2B − J) D* + J)) P*), drawn from the seeded SplitMix64 stream: d + 1 points, n (d + 1)
//!   jobs, trajectory by trajectory. A level ℓ is the probability u = (ℓ (p − 1) + δ)/p, a point
//!   of the ℓ-th of p equal-probability strata, with δ ∈ (0, 1) an offset drawn per trajectory
//!   and coordinate: every quantile is finite, a step still moves u by exactly Δ (p − 1)/p, and
//!   two trajectories never share a point (a study refuses two identical jobs).
//!
//! Every method is deterministic in (n, d, seed): the same points on every machine, thread count
//! and shard.

use crate::numerics::rng::SplitMix64;

/// How a sampled study draws its points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Independent uniforms.
    MonteCarlo,
    /// Latin hypercube.
    LatinHypercube,
    /// Scrambled Sobol'.
    Sobol,
    /// Saltelli's A, B, AB_i design on scrambled Sobol' points.
    Saltelli,
    /// Morris trajectories on a grid of this many (even) levels.
    Morris(usize),
}

/// The method names a study may give, in [`Method`] order.
pub const METHODS: [&str; 5] = [
    "monte-carlo",
    "latin-hypercube",
    "sobol",
    "saltelli",
    "morris",
];

/// The levels of a Morris design unless `[sample] levels` says otherwise.
pub const DEFAULT_LEVELS: usize = 4;

/// Most coordinates the Sobol' points have (`sobol_burley::NUM_DIMENSIONS`).
pub const MAX_SOBOL_DIMENSIONS: usize = sobol_burley::NUM_DIMENSIONS as usize;

impl Method {
    /// The method of a name in [`METHODS`].
    pub fn parse(name: &str) -> Option<Method> {
        match name {
            "monte-carlo" => Some(Method::MonteCarlo),
            "latin-hypercube" => Some(Method::LatinHypercube),
            "sobol" => Some(Method::Sobol),
            "saltelli" => Some(Method::Saltelli),
            "morris" => Some(Method::Morris(DEFAULT_LEVELS)),
            _ => None,
        }
    }

    /// Jobs of a design of n base points in d coordinates.
    pub fn jobs(self, n: usize, d: usize) -> usize {
        match self {
            Method::Saltelli => n * (d + 2),
            Method::Morris(_) => n * (d + 1),
            _ => n,
        }
    }

    /// The coordinates of the underlying points (2d for Saltelli).
    pub fn dimensions(self, d: usize) -> usize {
        match self {
            Method::Saltelli => 2 * d,
            _ => d,
        }
    }
}

/// Which matrix of a Saltelli design a job's row is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Matrix {
    /// A plain sample (not Saltelli).
    Plain,
    A,
    B,
    /// AB_i: A with column i (0-based) from B.
    AB(usize),
    /// Step s of a Morris trajectory (0: its start).
    Step(usize),
}

/// One job of a design: its matrix, its row and its unit point.
#[derive(Debug, Clone)]
pub struct Row {
    pub matrix: Matrix,
    pub row: usize,
    pub point: Vec<f64>,
}

impl Row {
    /// The job's label: `sample 12`, or `A 12`, `B 12`, `AB_1 12` (parameters from 1).
    pub fn label(&self) -> String {
        match self.matrix {
            Matrix::Plain => format!("sample {}", self.row),
            Matrix::A => format!("A {}", self.row),
            Matrix::B => format!("B {}", self.row),
            Matrix::AB(i) => format!("AB_{} {}", i + 1, self.row),
            Matrix::Step(s) => format!("T_{s} {}", self.row),
        }
    }

    /// The inverse of [`Row::label`].
    pub fn parse_label(label: &str) -> Option<(Matrix, usize)> {
        let (m, r) = label.split_once(' ')?;
        let row = r.parse().ok()?;
        let matrix = match m {
            "sample" => Matrix::Plain,
            "A" => Matrix::A,
            "B" => Matrix::B,
            _ if m.starts_with("T_") => Matrix::Step(m.strip_prefix("T_")?.parse().ok()?),
            _ => Matrix::AB(
                m.strip_prefix("AB_")?
                    .parse::<usize>()
                    .ok()?
                    .checked_sub(1)?,
            ),
        };
        Some((matrix, row))
    }
}

/// The n points of `method` in `dims` coordinates (module doc), each in (0, 1).
pub fn unit_points(method: Method, n: usize, dims: usize, seed: u64) -> Vec<Vec<f64>> {
    // Half of the last bit of each generator, so that no point is 0.
    const HALF_53: f64 = 1.0 / (1u64 << 54) as f64;
    const HALF_24: f64 = 1.0 / (1u64 << 25) as f64;
    match method {
        Method::MonteCarlo => {
            let mut rng = SplitMix64::new(seed);
            (0..n)
                .map(|_| (0..dims).map(|_| rng.uniform() + HALF_53).collect())
                .collect()
        }
        Method::LatinHypercube => {
            let mut rng = SplitMix64::new(seed);
            let mut points = vec![vec![0.0; dims]; n];
            for k in 0..dims {
                let mut perm: Vec<usize> = (0..n).collect();
                for i in (1..n).rev() {
                    let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                    perm.swap(i, j);
                }
                for (i, p) in points.iter_mut().enumerate() {
                    p[k] = (perm[i] as f64 + rng.uniform() + HALF_53) / n as f64;
                }
            }
            points
        }
        Method::Morris(levels) => morris_points(n, dims, levels, seed),
        Method::Sobol | Method::Saltelli => {
            // The crate's seed is 32 bits: both halves of the study's seed fold into it.
            let s = (seed ^ (seed >> 32)) as u32;
            (0..n)
                .map(|i| {
                    (0..dims)
                        .map(|k| f64::from(sobol_burley::sample(i as u32, k as u32, s)) + HALF_24)
                        .collect()
                })
                .collect()
        }
    }
}

/// The jobs of a design: its points as rows (module doc), for d parameters.
pub fn rows(method: Method, n: usize, d: usize, seed: u64) -> Vec<Row> {
    let points = unit_points(method, n, method.dimensions(d), seed);
    if let Method::Morris(_) = method {
        return points
            .into_iter()
            .enumerate()
            .map(|(k, point)| Row {
                matrix: Matrix::Step(k % (d + 1)),
                row: k / (d + 1),
                point,
            })
            .collect();
    }
    if method != Method::Saltelli {
        return points
            .into_iter()
            .enumerate()
            .map(|(row, point)| Row {
                matrix: Matrix::Plain,
                row,
                point,
            })
            .collect();
    }
    let a = |p: &[f64]| p[..d].to_vec();
    let b = |p: &[f64]| p[d..].to_vec();
    let mut out = Vec::with_capacity(n * (d + 2));
    for (matrix, take) in [
        (Matrix::A, &a as &dyn Fn(&[f64]) -> Vec<f64>),
        (Matrix::B, &b),
    ] {
        out.extend(points.iter().enumerate().map(|(row, p)| Row {
            matrix,
            row,
            point: take(p),
        }));
    }
    for i in 0..d {
        out.extend(points.iter().enumerate().map(|(row, p)| {
            let mut point = a(p);
            point[i] = p[d + i];
            Row {
                matrix: Matrix::AB(i),
                row,
                point,
            }
        }));
    }
    out
}

/// The n (d + 1) points of n Morris trajectories on `levels` levels (module doc), trajectory
/// by trajectory.
fn morris_points(n: usize, d: usize, levels: usize, seed: u64) -> Vec<Vec<f64>> {
    // Half of the last bit of a uniform, so that no offset is 0.
    const HALF_53: f64 = 1.0 / (1u64 << 54) as f64;
    let p = levels as f64;
    let jump = levels / 2;
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::with_capacity(n * (d + 1));
    for _ in 0..n {
        // Base levels 0 … p/2 − 1, so that a step of Δ = (p/2)/(p − 1) (p/2 levels) stays on the
        // grid; a negative step starts p/2 levels up.
        let mut level: Vec<usize> = (0..d)
            .map(|_| (rng.next_u64() % jump as u64) as usize)
            .collect();
        let up: Vec<bool> = (0..d).map(|_| rng.next_u64().is_multiple_of(2)).collect();
        for (l, u) in level.iter_mut().zip(&up) {
            if !u {
                *l += jump;
            }
        }
        let mut order: Vec<usize> = (0..d).collect();
        for i in (1..d).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            order.swap(i, j);
        }
        let offset: Vec<f64> = (0..d).map(|_| rng.uniform() + HALF_53).collect();
        let to_u = |level: &[usize]| -> Vec<f64> {
            level
                .iter()
                .zip(&offset)
                .map(|(&l, o)| (l as f64 + o) / p)
                .collect()
        };
        out.push(to_u(&level));
        for &i in &order {
            level[i] = if up[i] {
                level[i] + jump
            } else {
                level[i] - jump
            };
            out.push(to_u(&level));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin_hypercube_has_one_point_per_stratum() {
        // McKay, Beckman & Conover (1979): each marginal has exactly one point per stratum.
        let n = 50;
        let p = unit_points(Method::LatinHypercube, n, 3, 9);
        for k in 0..3 {
            let mut strata: Vec<usize> = p.iter().map(|x| (x[k] * n as f64) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..n).collect::<Vec<_>>());
        }
    }

    #[test]
    fn saltelli_rows_mix_a_and_b() {
        let (n, d) = (8, 3);
        let r = rows(Method::Saltelli, n, d, 1);
        assert_eq!(r.len(), n * (d + 2));
        let (a, b, ab1) = (&r[5], &r[n + 5], &r[3 * n + 5]);
        assert_eq!(ab1.matrix, Matrix::AB(1));
        assert_eq!(ab1.point[1], b.point[1]);
        assert_eq!(ab1.point[0], a.point[0]);
        assert_eq!(ab1.point[2], a.point[2]);
        for row in &r {
            assert_eq!(Row::parse_label(&row.label()), Some((row.matrix, row.row)));
        }
    }

    #[test]
    fn morris_trajectories_move_one_coordinate_a_step_at_a_time() {
        // Morris (1991): each step changes exactly one coordinate, each coordinate once per
        // trajectory, by Δ = p/(2(p − 1)) levels, here (p/2)/p in probability.
        let (n, d, p) = (20, 3, 6);
        let r = rows(Method::Morris(p), n, d, 5);
        assert_eq!(r.len(), n * (d + 1));
        for t in r.chunks(d + 1) {
            let mut moved = vec![0; d];
            for (s, pair) in t.windows(2).enumerate() {
                assert_eq!(pair[1].matrix, Matrix::Step(s + 1));
                let changed: Vec<usize> = (0..d)
                    .filter(|&i| pair[0].point[i] != pair[1].point[i])
                    .collect();
                assert_eq!(changed.len(), 1);
                let i = changed[0];
                moved[i] += 1;
                let step = (pair[1].point[i] - pair[0].point[i]).abs();
                assert!((step - 0.5).abs() < 1e-12, "{step}");
            }
            assert_eq!(moved, vec![1; d]);
            assert!(t
                .iter()
                .flat_map(|x| &x.point)
                .all(|u| *u > 0.0 && *u < 1.0));
        }
        for row in &r {
            assert_eq!(Row::parse_label(&row.label()), Some((row.matrix, row.row)));
        }
    }

    #[test]
    fn points_lie_inside_the_open_cube() {
        for m in [Method::MonteCarlo, Method::LatinHypercube, Method::Sobol] {
            let p = unit_points(m, 1024, 4, 3);
            assert!(p.iter().flatten().all(|u| *u > 0.0 && *u < 1.0), "{m:?}");
        }
    }
}
