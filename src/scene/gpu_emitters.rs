//! The emitters that are not triangles joining the GPU light list: each analytic light and the
//! environment one entry of `scene.lights` after the area lights, with its selection weight
//! (src/scene/emitters.rs describes them).

use super::emitters::{Emitters, luminance, record};
use super::environment::Environment;
use super::gpu::SceneGpu;
use super::lights::{LIGHT_ENVIRONMENT_CONSTANT, LIGHT_ENVIRONMENT_MAP};
use super::texture::Texture;
use glam::Vec3;

impl SceneGpu {
    /// Appends the analytic lights, then the environment, to the light list; the environment
    /// image joins the textures and its tables the weights.
    pub fn add_emitters(&mut self, emitters: &Emitters) {
        for light in &emitters.lights {
            let (record, weight) = light.gpu(&mut self.textures);
            self.lights.push(record);
            self.light_power.push(weight);
        }
        match &emitters.environment {
            None => {}
            Some(Environment::Constant { radiance }) => {
                self.environment_light = Some(self.lights.len() as u32);
                let r = *radiance;
                self.lights.push(record(
                    LIGHT_ENVIRONMENT_CONSTANT,
                    Vec3::ZERO,
                    r,
                    Vec3::ZERO,
                    0,
                    0,
                ));
                // A uniform environment's irradiance on any surface: pi L.
                self.light_power.push(std::f32::consts::PI * luminance(r));
            }
            Some(Environment::Map(map)) => {
                self.environment_light = Some(self.lights.len() as u32);
                // World to local: the rows of the rotation's transpose.
                let local = map.to_world.transpose();
                let texture = self.textures.len() as u32;
                let (w, h) = (map.image.width as usize, map.image.height as usize);
                // Mitsuba's layout: one more column, a copy of the first (the image wraps).
                let mut texels = Vec::with_capacity((w + 1) * h);
                for row in map.image.texels.chunks(w) {
                    for t in row.iter().chain(std::iter::once(&row[0])) {
                        let c = Vec3::from(*t) * map.scale;
                        texels.push([c.x, c.y, c.z, 0.0]);
                    }
                }
                self.textures
                    .push(Texture::from_texels(w as u32 + 1, h as u32, texels));
                self.lights.push(record(
                    LIGHT_ENVIRONMENT_MAP,
                    local.row(0),
                    local.row(1),
                    local.row(2),
                    texture,
                    0, // the table's offset, set below
                ));
                self.light_power
                    .push(std::f32::consts::PI * map.distribution.mean_luminance);
                self.environment_table = map.distribution.gpu_table();
            }
        }
        if !self.environment_table.is_empty() {
            // The table starts at the next texel boundary after the weights.
            let offset = self.light_power.len().div_ceil(4) * 4;
            let env = self.environment_light.expect("a table belongs to a map") as usize;
            self.lights[env].first = offset as u32;
        }
        self.light_count = self.lights.len() as u32;
        self.light_kinds = self.lights.iter().fold(0, |k, l| k | 1 << l.kind());
    }

    /// The `scene.light_power` buffer: each light's selection weight, then (from the next
    /// multiple of 4) the environment map's sampling tables; one zero texel when empty.
    pub fn light_power_bytes(&self) -> Vec<u8> {
        let mut values = self.light_power.clone();
        if !self.environment_table.is_empty() {
            values.resize(values.len().div_ceil(4) * 4, 0.0);
            values.extend_from_slice(&self.environment_table);
        }
        values.resize(values.len().max(1).div_ceil(4) * 4, 0.0);
        bytemuck::cast_slice(&values).to_vec()
    }
}
