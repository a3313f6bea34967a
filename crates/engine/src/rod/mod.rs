//! Discrete Elastic Rods (Bergou et al. 2008): stretching, bending and twisting.
pub mod stretch;

pub use stretch::Stretch;
