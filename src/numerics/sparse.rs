//! Sparse symmetric matrices: storage, sub-blocks, products with tall dense blocks, and the
//! sparse Cholesky factor.
//!
//! In: entries (row, column, value) of a square matrix, 0-based, each position once (both
//! triangles, as a symmetric matrix is used). Out: a [`Sparse`] matrix in compressed columns,
//! its entries, the matrix grown and with entries added ([`Sparse::with_added`]), its
//! sub-blocks on index lists, its products A X with dense n × k blocks (faer `Mat`), and a
//! [`Cholesky`] factor A = L Lᵀ that solves A X = B in place. Units as given.
//! Method: compressed sparse columns built by sorting the entries; the factor is faer's sparse
//! Cholesky (`sp_cholesky`: AMD fill-reducing ordering, simplicial or supernodal by the
//! pattern), chosen because faer is already the engine's dense kernel and its sparse LLᵀ needs
//! no C library. Cost: a product is O(nnz · k); the factor's cost and memory are those of its
//! fill (a banded beam chain stays O(n), a 3-D lattice grows as n^{4/3}–n²). No dense n × n
//! matrix is formed.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

/// A square sparse matrix in compressed columns (module doc).
#[derive(Debug, Clone)]
pub struct Sparse {
    n: usize,
    col_ptr: Vec<usize>,
    row: Vec<usize>,
    val: Vec<f64>,
}

impl Sparse {
    /// The n × n matrix of `entries` (row, column, value), 0-based; a position given twice is
    /// summed (the readers refuse that before).
    pub fn from_entries(n: usize, mut entries: Vec<(usize, usize, f64)>) -> Self {
        entries.sort_unstable_by_key(|&(i, j, _)| (j, i));
        let mut col_ptr = vec![0; n + 1];
        let mut row = Vec::with_capacity(entries.len());
        let mut val: Vec<f64> = Vec::with_capacity(entries.len());
        let mut last = None;
        for (i, j, x) in entries {
            if last == Some((i, j)) {
                *val.last_mut().expect("an entry before") += x;
                continue;
            }
            last = Some((i, j));
            row.push(i);
            val.push(x);
            col_ptr[j + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        Self {
            n,
            col_ptr,
            row,
            val,
        }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Stored entries.
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// The entries of column `j`: (row, value).
    pub fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row[r.clone()]
            .iter()
            .copied()
            .zip(self.val[r].iter().copied())
    }

    /// Entry (i, j), zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        match self.row[r.clone()].binary_search(&i) {
            Ok(k) => self.val[r.start + k],
            Err(_) => 0.0,
        }
    }

    /// Replaces every stored entry x at (i, j) by f(i, j, x).
    pub fn map(&mut self, f: impl Fn(usize, usize, f64) -> f64) {
        for j in 0..self.n {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                self.val[k] = f(self.row[k], j, self.val[k]);
            }
        }
    }

    /// Every stored entry (row, column, value), column by column, rows ascending.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |j| self.column(j).map(move |(i, x)| (i, j, x)))
    }

    /// self + a · other (same dimension), e.g. K − σM for a shifted factor.
    pub fn plus_scaled(&self, other: &Sparse, a: f64) -> Sparse {
        assert_eq!(self.n, other.n, "sum of mismatched sizes");
        let entries = self
            .entries()
            .chain(other.entries().map(|(i, j, x)| (i, j, a * x)))
            .collect();
        Sparse::from_entries(self.n, entries)
    }

    /// This matrix grown to `n` ≥ its dimension (the new rows and columns empty) plus
    /// `extra` (row, column, value) entries, a position given again summed after the stored
    /// value in the order given; only `extra` is sorted, so adding a few entries to a large
    /// matrix costs O(nnz + e log e) (e.g. support springs on a body's stiffness).
    pub fn with_added(&self, n: usize, mut extra: Vec<(usize, usize, f64)>) -> Sparse {
        assert!(n >= self.n, "a matrix grown to a smaller dimension");
        extra.sort_by_key(|&(i, j, _)| (j, i));
        let mut col_ptr = vec![0; n + 1];
        let mut row = Vec::with_capacity(self.nnz() + extra.len());
        let mut val: Vec<f64> = Vec::with_capacity(self.nnz() + extra.len());
        let mut next = extra.into_iter().peekable();
        for j in 0..n {
            let stored = if j < self.n {
                self.col_ptr[j]..self.col_ptr[j + 1]
            } else {
                0..0
            };
            let mut k = stored.start;
            loop {
                let own = (k < stored.end).then(|| self.row[k]);
                let add = next.peek().filter(|e| e.1 == j).map(|e| e.0);
                let i = match (own, add) {
                    (None, None) => break,
                    (Some(i), None) => i,
                    (None, Some(i)) => i,
                    (Some(a), Some(b)) => a.min(b),
                };
                let mut x = 0.0;
                if own == Some(i) {
                    x = self.val[k];
                    k += 1;
                }
                while let Some(&(_, _, y)) = next.peek().filter(|e| e.1 == j && e.0 == i) {
                    x += y;
                    next.next();
                }
                row.push(i);
                val.push(x);
            }
            col_ptr[j + 1] = row.len();
        }
        assert!(
            next.peek().is_none(),
            "an added entry outside the dimension"
        );
        Self {
            n,
            col_ptr,
            row,
            val,
        }
    }

    /// The 1-norm: the largest column sum of |entries|.
    pub fn norm1(&self) -> f64 {
        (0..self.n).fold(0.0, |m: f64, j| {
            m.max(self.column(j).map(|(_, x)| x.abs()).sum())
        })
    }

    /// The largest |entry|.
    pub fn amax(&self) -> f64 {
        self.val.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
    }

    /// The block on `rows` × `cols` (index lists into this matrix), as a rectangular matrix in
    /// the same storage: row k of the block is `rows[k]`.
    pub fn block(&self, rows: &[usize], cols: &[usize]) -> Block {
        let mut at = vec![usize::MAX; self.n];
        for (k, &r) in rows.iter().enumerate() {
            at[r] = k;
        }
        let mut col_ptr = Vec::with_capacity(cols.len() + 1);
        col_ptr.push(0);
        let mut row = Vec::new();
        let mut val = Vec::new();
        for &c in cols {
            for (i, x) in self.column(c) {
                if at[i] != usize::MAX {
                    row.push(at[i]);
                    val.push(x);
                }
            }
            col_ptr.push(row.len());
        }
        Block {
            nrows: rows.len(),
            inner: Self {
                n: cols.len(),
                col_ptr,
                row,
                val,
            },
        }
    }

    /// A X for a dense n × k block X.
    pub fn mul(&self, x: &Mat<f64>) -> Mat<f64> {
        product(self, self.n, x)
    }

    /// A x for a vector x.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        assert_eq!(x.len(), self.n, "product of mismatched sizes");
        let mut y = vec![0.0; self.n];
        for (j, &xj) in x.iter().enumerate() {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row[k]] += self.val[k] * xj;
            }
        }
        y
    }

    /// The Cholesky factor of this symmetric matrix (its lower triangle is read), or `None`
    /// when it is not positive definite.
    pub fn cholesky(&self) -> Option<Cholesky> {
        let t: Vec<Triplet<usize, usize, f64>> = (0..self.n)
            .flat_map(|j| {
                self.column(j)
                    .filter(move |&(i, _)| i >= j)
                    .map(move |(i, x)| Triplet::new(i, j, x))
            })
            .collect();
        let a = SparseColMat::try_new_from_triplets(self.n, self.n, &t).ok()?;
        let llt = a.sp_cholesky(Side::Lower).ok()?;
        Some(Cholesky { llt })
    }
}

/// A rectangular block of a [`Sparse`] matrix (compressed columns).
#[derive(Debug, Clone)]
pub struct Block {
    nrows: usize,
    inner: Sparse,
}

impl Block {
    /// B X for a dense block X with as many rows as B has columns.
    pub fn mul(&self, x: &Mat<f64>) -> Mat<f64> {
        product(&self.inner, self.nrows, x)
    }

    /// A square block as a [`Sparse`] matrix.
    pub fn into_square(self) -> Sparse {
        assert_eq!(self.nrows, self.inner.n, "the block is not square");
        self.inner
    }

    /// The block as a dense matrix (for blocks with few columns).
    pub fn to_dense(&self) -> Mat<f64> {
        let s = &self.inner;
        let mut y = Mat::zeros(self.nrows, s.n);
        for j in 0..s.n {
            for (i, x) in s.column(j) {
                y[(i, j)] = x;
            }
        }
        y
    }
}

/// S X for compressed columns S with `nrows` rows and a dense X.
fn product(s: &Sparse, nrows: usize, x: &Mat<f64>) -> Mat<f64> {
    assert_eq!(x.nrows(), s.n, "product of mismatched sizes");
    let mut y = Mat::zeros(nrows, x.ncols());
    for c in 0..x.ncols() {
        for j in 0..s.n {
            let xj = x[(j, c)];
            if xj == 0.0 {
                continue;
            }
            for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                y[(s.row[k], c)] += s.val[k] * xj;
            }
        }
    }
    y
}

/// The sparse Cholesky factor of a symmetric positive-definite [`Sparse`] matrix.
pub struct Cholesky {
    llt: faer::sparse::linalg::solvers::Llt<usize, f64>,
}

impl Cholesky {
    /// Overwrites B with A⁻¹ B.
    pub fn solve_in_place(&self, b: &mut Mat<f64>) {
        self.llt.solve_in_place(b.as_mut());
    }

    /// A⁻¹ b for a vector b.
    pub fn solve_vec(&self, b: &[f64]) -> Vec<f64> {
        let mut x = Mat::from_fn(b.len(), 1, |i, _| b[i]);
        self.solve_in_place(&mut x);
        (0..b.len()).map(|i| x[(i, 0)]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1-D Laplacian tridiag(−1, 2, −1) of size n.
    fn laplacian(n: usize) -> Sparse {
        let mut e = Vec::new();
        for i in 0..n {
            e.push((i, i, 2.0));
            if i + 1 < n {
                e.push((i + 1, i, -1.0));
                e.push((i, i + 1, -1.0));
            }
        }
        Sparse::from_entries(n, e)
    }

    #[test]
    fn solve_of_the_laplacian_matches_its_closed_form_inverse() {
        // (tridiag(−1, 2, −1))⁻¹_ij = min(i, j) (n + 1 − max(i, j)) / (n + 1), 1-based
        // (the Green's function of the discrete second difference).
        let n = 50;
        let a = laplacian(n);
        let f = a.cholesky().expect("positive definite");
        let mut b = Mat::zeros(n, 1);
        b[(9, 0)] = 1.0;
        f.solve_in_place(&mut b);
        for i in 0..n {
            let (p, q) = ((i + 1).min(10) as f64, (i + 1).max(10) as f64);
            let exact = p * (n as f64 + 1.0 - q) / (n as f64 + 1.0);
            assert!((b[(i, 0)] - exact).abs() < 1e-12 * exact.abs().max(1.0));
        }
        let y = a.mul(&b);
        assert!((y[(9, 0)] - 1.0).abs() < 1e-12 && y[(3, 0)].abs() < 1e-12);
    }

    #[test]
    fn an_indefinite_matrix_has_no_factor() {
        let a = Sparse::from_entries(2, vec![(0, 0, 1.0), (1, 1, -1.0)]);
        assert!(a.cholesky().is_none());
    }

    #[test]
    fn added_entries_are_summed_into_a_grown_matrix() {
        // laplacian(3) grown to 4, plus 1 at (1, 1) twice, (3, 0) and (0, 3), (3, 3): by hand.
        let a = laplacian(3).with_added(
            4,
            vec![
                (3, 3, 5.0),
                (1, 1, 1.0),
                (3, 0, 0.5),
                (0, 3, 0.5),
                (1, 1, 1.0),
            ],
        );
        let want = [
            [2.0, -1.0, 0.0, 0.5],
            [-1.0, 4.0, -1.0, 0.0],
            [0.0, -1.0, 2.0, 0.0],
            [0.5, 0.0, 0.0, 5.0],
        ];
        for (i, r) in want.iter().enumerate() {
            for (j, &x) in r.iter().enumerate() {
                assert_eq!(a.get(i, j), x, "({i}, {j})");
            }
        }
        assert_eq!(a.nnz(), 10);
        let same: Vec<_> = laplacian(5).with_added(5, Vec::new()).entries().collect();
        assert_eq!(same, laplacian(5).entries().collect::<Vec<_>>());
    }

    #[test]
    fn a_block_keeps_the_rows_and_columns_asked() {
        let a = laplacian(5);
        let b = a.block(&[1, 2], &[0, 2]).to_dense();
        assert_eq!(
            (b[(0, 0)], b[(0, 1)], b[(1, 0)], b[(1, 1)]),
            (-1.0, -1.0, 0.0, 2.0)
        );
    }
}
