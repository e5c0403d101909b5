//! Progressive rendering: sessions over a compiled graph and a scene, image output (from the
//! accumulation or an output texture), and the accumulate pass's arithmetic on the CPU.

pub mod accumulate;
pub mod camera_path;
pub mod channels;
pub mod checkpoint;
pub mod fingerprint;
pub mod image;
pub mod merge;
pub mod output_texture;
pub mod partial;
pub mod planes;
pub mod provided;
pub mod sample_range;
pub mod session;
pub mod session_builder;
pub mod tile_order;
pub mod tiles;
pub mod tiling;
