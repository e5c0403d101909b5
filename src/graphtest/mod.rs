//! Graph tests written in RON (`passgraph test FILE.ron...`): cases that build a graph (a file,
//! or changes to one inline), render a scene for some frames and seeds, and check the plan's
//! shape and image statistics. `decl` is the schema, `expect` checks one expectation, `run`
//! reads files, runs cases and reports.

pub mod decl;
pub mod expect;
pub mod run;

pub use run::{Summary, run_files};
