//! Emitters not attached to shapes: `point`, `spot`, `directional` (passgraph's analytic
//! lights), `constant` and `envmap` (its environment). Area emitters are read with their shape
//! (build.rs) as the emission of its triangles' material.

use super::builder::Builder;
use super::parse::Plugin;
use crate::scene::emitters::AnalyticLight;
use crate::scene::environment::{Environment, EnvironmentMap};
use crate::scene::environment_image::load_environment_image;
use crate::scene::error::SceneError;
use glam::{DMat4, DVec3, Mat3, Vec3};

fn v3(v: DVec3) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

fn colour(plugin: &Plugin, name: &str) -> Result<Vec3, SceneError> {
    let c = plugin.constant_color(name, [1.0; 3])?;
    if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(plugin.error(format!("{name} {c:?} must be finite and not negative")));
    }
    Ok(Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
}

fn to_world(plugin: &Plugin) -> Result<Option<DMat4>, SceneError> {
    Ok(plugin.transform("to_world")?.map(|(m, _)| m))
}

/// Adds a scene-level emitter to the builder.
pub fn emitter(builder: &mut Builder, plugin: &Plugin) -> Result<(), SceneError> {
    match plugin.kind.as_str() {
        "point" => {
            let position = match (plugin.point("position")?, to_world(plugin)?) {
                (Some(_), Some(_)) => {
                    return Err(plugin.error("give position or to_world, not both"));
                }
                (Some(p), None) => p,
                (None, Some(m)) => m.transform_point3(DVec3::ZERO),
                (None, None) => DVec3::ZERO,
            };
            let intensity = colour(plugin, "intensity")?;
            plugin.finish()?;
            builder.lights.push(AnalyticLight::Point {
                position: v3(position),
                intensity,
            });
        }
        "spot" => {
            let m = to_world(plugin)?.unwrap_or(DMat4::IDENTITY);
            let intensity = colour(plugin, "intensity")?;
            let cutoff = plugin.float_or("cutoff_angle", 20.0)?;
            let beam = plugin.float_or("beam_width", 0.75 * cutoff)?;
            if !(cutoff > 0.0 && cutoff <= 90.0 && beam > 0.0 && beam <= cutoff) {
                return Err(plugin.error(format!(
                    "cutoff_angle {cutoff} must be in (0, 90] and beam_width {beam} in (0, cutoff_angle]"
                )));
            }
            // Mitsuba's spot texture: the image over the cone, in to_world's frame.
            let texture = match plugin.named_child("texture") {
                None => None,
                Some(child) => {
                    let used = super::textures::texture(builder, &child.plugin)?;
                    if used.to_uv != glam::DMat3::IDENTITY {
                        return Err(child
                            .plugin
                            .error("a spot texture's to_uv is not supported"));
                    }
                    Some(builder.texture_image(used.index).clone())
                }
            };
            plugin.finish()?;
            let position = m.transform_point3(DVec3::ZERO);
            let axis = m.transform_vector3(DVec3::Z);
            if axis.length() == 0.0 {
                return Err(plugin.error("to_world maps the spot's axis to zero"));
            }
            // The frame's y axis as up: spot_frame rebuilds to_world's x = y x z from it.
            let up = m.transform_vector3(DVec3::Y);
            if up.cross(axis).length() == 0.0 {
                return Err(plugin.error("to_world maps the spot's y axis onto its z axis"));
            }
            builder.lights.push(AnalyticLight::Spot {
                position: v3(position),
                target: v3(position + axis.normalize()),
                up: v3(up.normalize()),
                intensity,
                cutoff_angle: cutoff as f32,
                beam_width: beam as f32,
                texture,
            });
        }
        "directional" => {
            let direction = match (plugin.vector("direction")?, to_world(plugin)?) {
                (Some(_), Some(_)) => {
                    return Err(plugin.error("give direction or to_world, not both"));
                }
                (Some(d), None) => d,
                (None, Some(m)) => m.transform_vector3(DVec3::Z),
                (None, None) => DVec3::Z,
            };
            let irradiance = colour(plugin, "irradiance")?;
            plugin.finish()?;
            let direction = direction
                .try_normalize()
                .ok_or_else(|| plugin.error("direction must be a nonzero vector"))?;
            builder.lights.push(AnalyticLight::Directional {
                direction: v3(direction),
                irradiance,
            });
        }
        "constant" => {
            let radiance = colour(plugin, "radiance")?;
            plugin.finish()?;
            builder.environment = Some(match builder.environment.take() {
                None => Environment::Constant { radiance },
                // Two uniform skies are one with the sum of their radiances.
                Some(Environment::Constant { radiance: r }) => Environment::Constant {
                    radiance: r + radiance,
                },
                Some(Environment::Map(_)) => {
                    return Err(plugin.error("a constant emitter besides an envmap is not supported (passgraph has one environment)"));
                }
            });
        }
        "envmap" => {
            let (name, at) = plugin
                .string("filename")?
                .ok_or_else(|| plugin.error("an envmap needs a 'filename'"))?;
            let scale = plugin.float_or("scale", 1.0)?;
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(plugin.error(format!("scale {scale} must be finite and not negative")));
            }
            let m = to_world(plugin)?.unwrap_or(DMat4::IDENTITY);
            let r = glam::DMat3::from_mat4(m);
            if !(r * r.transpose()).abs_diff_eq(glam::DMat3::IDENTITY, 1e-6)
                || r.determinant() < 0.0
            {
                return Err(plugin.error("an envmap's to_world must be a rotation"));
            }
            plugin.finish()?;
            if builder.environment.is_some() {
                return Err(plugin.error(
                    "a second environment emitter is not supported (passgraph has one environment)",
                ));
            }
            let path = builder.resolve(&name, &at).ok_or_else(|| {
                plugin.error_at(&at, format!("filename '{name}': file not found"))
            })?;
            let image = load_environment_image(&path).map_err(|m| plugin.error_at(&at, m))?;
            let to_world = Mat3::from_cols(v3(r.x_axis), v3(r.y_axis), v3(r.z_axis));
            builder.environment = Some(Environment::Map(EnvironmentMap::new(
                path,
                image,
                scale as f32,
                to_world,
            )));
        }
        "area" => {
            return Err(plugin.error("an area emitter must be nested in a shape"));
        }
        other => {
            return Err(plugin.error(format!(
                "emitter type '{other}' is not supported (supported: area, point, spot, directional, constant, envmap)"
            )));
        }
    }
    Ok(())
}
