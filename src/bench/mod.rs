//! Measuring renders: error metrics against references.

pub mod metrics;
