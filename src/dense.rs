//! Small dense kernels on column-major slices, through faer, whose SIMD width (SSE2, AVX2 +
//! FMA, AVX-512) is chosen at run time: the shipped binary uses the widest the machine has,
//! with no build flag. One thread (`Par::Seq`): the callers run inside a job's own thread.
//!
//! In: slices of f64 (matrices column-major). Out: the result in place. The same machine gives
//! the same bytes whatever the thread count.

/// out ← (out if `accumulate`) + alpha A x, for a column-major A of `out.len()` rows and
/// `x.len()` columns given as a slice.
pub fn matvec(out: &mut [f64], accumulate: bool, a: &[f64], x: &[f64], alpha: f64) {
    let (n, m) = (out.len(), x.len());
    let lhs = faer::MatRef::from_column_major_slice(a, n, m);
    let rhs = faer::MatRef::from_column_major_slice(x, m, 1);
    let dst = faer::MatMut::from_column_major_slice_mut(out, n, 1);
    let beta = if accumulate {
        faer::Accum::Add
    } else {
        faer::Accum::Replace
    };
    faer::linalg::matmul::matmul(dst, beta, lhs, rhs, alpha, faer::Par::Seq);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matvec_is_the_matrix_vector_product() {
        // A = [[1, 2, 3], [4, 5, 6]] column-major; A (1, 1, 2) = (9, 21).
        let a = [1.0, 4.0, 2.0, 5.0, 3.0, 6.0];
        let mut out = [100.0, 200.0];
        matvec(&mut out, false, &a, &[1.0, 1.0, 2.0], 1.0);
        assert_eq!(out, [9.0, 21.0]);
        matvec(&mut out, true, &a, &[1.0, 0.0, 0.0], -2.0);
        assert_eq!(out, [7.0, 13.0]);
    }
}
