//! The maths the material models share (src/material): shading frames and cosine sampling,
//! Fresnel terms, the GGX and Beckmann microfacet distributions, erf, and the quadrature the
//! models' tables are computed with. Each file twins the WGSL of the same name in
//! `shaders/lib/`, in f32, line for line.

pub mod beckmann;
pub mod erf;
pub mod frame;
pub mod fresnel;
pub mod ggx;
pub mod microfacet;
pub mod quadrature;
