//! Import of FE bodies from other codes: the matrices of a full or reduced model with its node
//! and DOF tables, read, checked and turned into the rotor's body-frame matrices.
//!
//! In: Matrix Market coordinate files ([`matrix_market`], also written for export) with a node
//! and a DOF table ([`tables`]), Abaqus `*MATRIX OUTPUT, FORMAT=COORDINATE` files
//! ([`abaqus`]), Nastran DMIG bulk-data cards ([`dmig`], the cards by [`bulk`]) or Nastran
//! OUTPUT4 ASCII files with a DOF table ([`op4`]), in SI or mm-t-s units. Out: an [`ImportedBody`](body::ImportedBody) in SI and
//! the rotor's DOF order, with its inertia invariants ([`invariants`]); or an
//! [`InputError`](crate::error::InputError) naming the file and the line or entry.
//! Every reader gives a matrix's [`Entries`](entries::Entries); a body is read dense
//! ([`body`]) or, in any format, sparse ([`sparse_body`]) for the sparse reduction
//! ([`crate::rotor::sparse_reduction`]).
//! Method: dense matrices (the reduction's dense eigen-solvers bound a body to
//! [`MAX_FE_NODES`](crate::scene::MAX_FE_NODES) nodes), checked for symmetry, size, nodes,
//! positive-definite mass and units ([`body`]).

pub mod abaqus;
pub mod body;
pub mod bulk;
pub mod dmig;
pub mod entries;
pub mod files;
pub mod invariants;
pub mod matrix_market;
pub mod op4;
pub mod rings;
pub mod solid;
pub mod sparse_body;
pub mod tables;
