//! Measuring renders: error metrics against references, speed-against-error runs, reports.

pub mod metrics;
pub mod plot;
pub mod report;
pub mod rounds;
pub mod run;
pub mod series;
pub mod variant;
