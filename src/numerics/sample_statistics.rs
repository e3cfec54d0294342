//! Statistics of a sample with bootstrap confidence intervals.
//!
//! In: the values of one output over a study's jobs (any unit; non-finite values are left out),
//! the probabilities of the quantiles wanted, and the bootstrap's resample count and seed.
//! Out: a [`Summary`]: the count, mean, standard deviation (n − 1 in the denominator), min,
//! max and the quantiles, each of mean, standard deviation and quantiles with a 95 %
//! percentile-bootstrap interval (Efron & Tibshirani, *An Introduction to the Bootstrap*, 1993,
//! §13.3): the statistic over `resamples` resamples of n values drawn with replacement (the
//! project's seeded SplitMix64), the interval between its 2.5 % and 97.5 % quantiles. The
//! intervals shrink as 1/√n and say how far N samples pin each statistic down.
//!
//! Quantiles interpolate linearly between order statistics (Hyndman & Fan 1996 type 7, numpy's
//! and R's default): q(p) = x₍ₖ₎ + h (x₍ₖ₊₁₎ − x₍ₖ₎), h = (n − 1) p − k, k = ⌊(n − 1) p⌋.

use crate::numerics::rng::SplitMix64;

/// A statistic and its 95 % bootstrap interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The statistic of the sample.
    pub value: f64,
    /// The 2.5 % quantile of its bootstrap distribution.
    pub low: f64,
    /// The 97.5 % quantile of its bootstrap distribution.
    pub high: f64,
}

/// The statistics of one sample (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Finite values used.
    pub n: usize,
    /// Mean.
    pub mean: Estimate,
    /// Standard deviation (n − 1).
    pub std: Estimate,
    /// The quantiles, in the order asked.
    pub quantiles: Vec<Estimate>,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// The type-7 quantile of sorted values at probability `p` (module doc); NaN when empty.
pub fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * p;
    let k = h.floor() as usize;
    let next = sorted[(k + 1).min(sorted.len() - 1)];
    sorted[k] + (h - k as f64) * (next - sorted[k])
}

/// Mean and standard deviation (n − 1; NaN below 2 values).
pub fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, if x.len() >= 2 { var.sqrt() } else { f64::NAN })
}

/// The statistics of `values` (module doc), or `None` without finite values.
pub fn summarise(
    values: &[f64],
    probabilities: &[f64],
    resamples: usize,
    seed: u64,
) -> Option<Summary> {
    let mut x: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if x.is_empty() {
        return None;
    }
    x.sort_by(f64::total_cmp);
    let stats = |sorted: &[f64]| {
        let (m, s) = mean_std(sorted);
        let mut out = vec![m, s];
        out.extend(probabilities.iter().map(|p| quantile_sorted(sorted, *p)));
        out
    };
    let point = stats(&x);
    let mut rng = SplitMix64::new(seed);
    let n = x.len();
    let mut boot: Vec<Vec<f64>> = vec![Vec::with_capacity(resamples); point.len()];
    let mut r = vec![0.0; n];
    for _ in 0..resamples {
        for v in r.iter_mut() {
            *v = x[(rng.next_u64() % n as u64) as usize];
        }
        r.sort_by(f64::total_cmp);
        for (b, s) in boot.iter_mut().zip(stats(&r)) {
            b.push(s);
        }
    }
    let estimates: Vec<Estimate> = point
        .iter()
        .zip(boot.iter_mut())
        .map(|(value, b)| interval(*value, b))
        .collect();
    Some(Summary {
        n,
        mean: estimates[0],
        std: estimates[1],
        quantiles: estimates[2..].to_vec(),
        min: x[0],
        max: x[n - 1],
    })
}

/// A statistic and the 95 % percentile interval of its bootstrap values (the non-finite left
/// out).
pub fn interval(value: f64, boot: &mut Vec<f64>) -> Estimate {
    boot.retain(|v| v.is_finite());
    boot.sort_by(f64::total_cmp);
    Estimate {
        value,
        low: quantile_sorted(boot, 0.025),
        high: quantile_sorted(boot, 0.975),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_numpy_s_default() {
        // numpy.quantile([1, 2, 3, 4], [0.25, 0.5, 0.9]) = [1.75, 2.5, 3.7] (linear method).
        let x = [1.0, 2.0, 3.0, 4.0];
        for (p, q) in [(0.25, 1.75), (0.5, 2.5), (0.9, 3.7)] {
            assert!((quantile_sorted(&x, p) - q).abs() < 1e-12);
        }
    }

    #[test]
    fn the_mean_s_interval_covers_the_normal_theory_one() {
        // For n standard normal values the mean's 95 % interval is ±1.96/√n (normal theory);
        // the bootstrap's width agrees within 15 %.
        let mut rng = SplitMix64::new(4);
        let n = 2000;
        let x: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let s = summarise(&x, &[0.5], 1000, 1).unwrap();
        let width = s.mean.high - s.mean.low;
        let theory = 2.0 * 1.96 / (n as f64).sqrt();
        assert!(
            (width / theory - 1.0).abs() < 0.15,
            "{width} against {theory}"
        );
        assert!(s.mean.low < s.mean.value && s.mean.value < s.mean.high);
    }
}
