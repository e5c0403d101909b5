//! Progressive rendering: sessions over a compiled graph and a scene, and image output.

pub mod channels;
pub mod image;
pub mod session;
