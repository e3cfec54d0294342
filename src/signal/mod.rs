//! Signal processing of sampled records, knowing nothing of rotors or files: spectra, line
//! amplitudes, resonance peaks over a sweep ([`spectrum`]), angle-domain order tracking
//! ([`orders`]) and influence-coefficient balancing ([`influence`]).
//!
//! In: uniformly sampled signals (any unit; runout in µm) with their sample rate [Hz] or sample
//! times [s], amplitude curves over speed [Hz], complex 1× responses. Out: spectra, complex line
//! amplitudes, peaks, order blocks, correction masses. Pure functions, no I/O.

pub mod influence;
pub mod orders;
pub mod spectrum;

pub use spectrum::{
    curve_peaks, hanning, lines, mean_and_spectrum, peaks, resolution, spectrum, trial_response,
    weighted_fit, weighted_lines, Peak, Resolution, Spectrum, TrialResponse, COARSE_STEP,
};
