//! The median of a sample, as the noise floor of a record and the report's comparison read it.
//!
//! In: values (any unit), non-finite ones ignored. Out: their median (the mean of the two
//! middle values for an even count), NaN when no finite value is left. Method: sort, O(n log n).

/// The median of the finite values of `v` (module doc).
pub fn median(v: impl IntoIterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = v.into_iter().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn odd_even_empty_and_non_finite() {
        assert_eq!(median([3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median([f64::NAN, f64::INFINITY]).is_nan());
        assert_eq!(median([f64::NAN, 5.0, 1.0, f64::NEG_INFINITY, 3.0]), 3.0);
    }
}
