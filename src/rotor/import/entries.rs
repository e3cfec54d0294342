//! A square matrix as its entries: what every matrix reader (Matrix Market, Abaqus, DMIG, OP4)
//! gives, for the dense path ([`super::body`]) and the sparse one ([`super::sparse_body`]) alike.
//!
//! In: the readers' entries (row, column, value), 0-based, each position at most once, both
//! triangles of a symmetric matrix (a reader mirrors what its file stores once), in the file's
//! units. Out: [`Entries`], and the dense matrix of them ([`Entries::dense`]) for a body the
//! dense path takes; or, for a dimension above the dense path's
//! [`super::matrix_market::MAX_DIM`], an [`InputError`] naming the file and the way on (the
//! sparse path: `fe.rings`). Method: plain data.

use std::path::Path;

use nalgebra::DMatrix;

use crate::error::InputError;

/// A square matrix as read (module doc).
#[derive(Debug, Clone, Default)]
pub struct Entries {
    /// Dimension.
    pub n: usize,
    /// (row, column, value), 0-based, each position once.
    pub entries: Vec<(usize, usize, f64)>,
}

impl Entries {
    /// The dense matrix, for the dense path; `path` names the file when it is too large.
    pub fn dense(&self, path: &Path) -> Result<DMatrix<f64>, InputError> {
        let max = super::matrix_market::MAX_DIM;
        if self.n > max {
            return Err(InputError::new(
                path,
                format!(
                    "the matrix has {} DOFs, above the {max} a body read dense takes: give the \
                     body rings (`[fe.rings]`), which read and reduce it sparse, or reduce it with \
                     `rotorsweep reduce`",
                    self.n
                ),
            ));
        }
        let mut a = DMatrix::zeros(self.n, self.n);
        for &(i, j, x) in &self.entries {
            a[(i, j)] = x;
        }
        Ok(a)
    }
}
