//! Helpers shared by the tests, by kind: physics references ([`physics`]), scene and study
//! fixtures ([`fixtures`], texts in tests/fixtures/), running the binary and reading results
//! ([`process`]) and scratch folders ([`scratch`]).
#![allow(dead_code)]

pub mod fixtures;
pub mod physics;
pub mod process;
pub mod scratch;

pub use fixtures::*;
pub use physics::*;
pub use process::*;
pub use scratch::*;
