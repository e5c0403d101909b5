//! The plugin tree as passgraph's [`Scene`]: every shape's triangles (in world space) with one
//! material per distinct BSDF and emission, the lights and environment, the camera and film,
//! and the integrator's depth.

use super::bsdf::{Back, Bsdf, bsdf};
use super::builder::Builder;
use super::emitters::emitter;
use super::parse::{ParsedScene, Plugin};
use super::sensor::{Sensor, sensor};
use super::serialized::load_serialized;
use super::shapes::{self, Geometry, Triangle};
use crate::material::Material;
use crate::scene::camera::MAX_COORDINATE;
use crate::scene::description::{MAX_MAX_DEPTH, Scene, SceneOptions};
use crate::scene::emitters::Emitters;
use crate::scene::error::SceneError;
use crate::scene::mesh::{Mesh, MeshTriangle};
use crate::scene::obj::load_obj_geometry;
use crate::scene::ply::load_ply_with_attributes;
use glam::{DMat3, DMat4, DVec2, DVec3, Vec2, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Shape groups by plugin (their shapes in group space, with their BSDFs).
type Groups = HashMap<*const Plugin, Vec<(Geometry, Bsdf, String)>>;

/// The loaded scene and what its sensor says about the render.
pub struct Built {
    pub scene: Scene,
    pub film_size: [u32; 2],
    pub sample_count: u32,
}

impl Builder {
    /// The index of a material with its back face, shared with an identical one; a new front
    /// comes before its new back.
    fn material(&mut self, m: Material, back: &Back, name: String) -> u32 {
        let back = match back {
            Back::Same => None,
            Back::Black => Some((
                Material::diffuse([0.0; 3]),
                "black (the back of one-sided BSDFs)".to_string(),
            )),
            Back::Other(b) => Some((*b, format!("{name}, back face"))),
        };
        let back_index = back.as_ref().map(|(b, _)| self.find_material(b, None));
        if let Some(i) = match back_index {
            None => self.find_material(&m, None),
            Some(Some(b)) => self.find_material(&m, Some(b)),
            Some(None) => None,
        } {
            return i;
        }
        let index = self.push_material(m, name);
        if let Some((b, back_name)) = back {
            let b = back_index
                .flatten()
                .unwrap_or_else(|| self.push_material(b, back_name));
            self.back_materials.insert(index, b);
        }
        index
    }

    fn find_material(&self, m: &Material, back: Option<u32>) -> Option<u32> {
        (0..self.materials.len() as u32).find(|&i| {
            bytemuck::bytes_of(&self.materials[i as usize]) == bytemuck::bytes_of(m)
                && self.back_materials.get(&i).copied() == back
        })
    }

    fn push_material(&mut self, m: Material, name: String) -> u32 {
        self.materials.push(m);
        self.material_names.push(name);
        (self.materials.len() - 1) as u32
    }

    /// Adds world-space triangles with a material and its `to_uv`.
    fn add(
        &mut self,
        plugin: &Plugin,
        geometry: &Geometry,
        material: u32,
        to_uv: Option<DMat3>,
    ) -> Result<(), SceneError> {
        let f = |v: DVec3| Vec3::new(v.x as f32, v.y as f32, v.z as f32);
        for t in &geometry.triangles {
            let vertices = t.p.map(f);
            if vertices
                .iter()
                .any(|v| !v.is_finite() || v.abs().max_element() > MAX_COORDINATE)
            {
                return Err(plugin.error(format!(
                    "a vertex at {:?} is not finite or lies beyond ±{MAX_COORDINATE:e}",
                    t.p
                )));
            }
            let uvs = t.uv.map(|uv| {
                uv.map(|uv| {
                    let uv = match to_uv {
                        Some(m) => (m * uv.extend(1.0)).truncate(),
                        None => uv,
                    };
                    let p = Triangle::passgraph_uv(uv);
                    Vec2::new(p.x as f32, p.y as f32)
                })
            });
            let normals = t.n.and_then(|n| {
                let n = n.map(f);
                n.iter()
                    .all(|n| n.length_squared().is_normal())
                    .then(|| n.map(Vec3::normalize))
            });
            self.triangles.push(MeshTriangle {
                vertices,
                material,
                normals,
                uvs,
            });
        }
        Ok(())
    }
}

/// A mesh loaded by passgraph's OBJ/PLY loaders as geometry; `flip_v`: the file's v is
/// Mitsuba's 1 - v (its OBJ loader's flip_tex_coords).
fn mesh_geometry(mesh: &Mesh, flip_v: bool) -> Geometry {
    let d = |v: Vec3| DVec3::new(v.x.into(), v.y.into(), v.z.into());
    Geometry {
        triangles: mesh
            .triangles
            .iter()
            .map(|t| Triangle {
                p: t.vertices.map(d),
                n: t.normals.map(|n| n.map(d)),
                uv: t.uvs.map(|uv| {
                    uv.map(|uv| {
                        let uv = DVec2::new(uv.x.into(), uv.y.into());
                        if flip_v {
                            DVec2::new(uv.x, 1.0 - uv.y)
                        } else {
                            uv
                        }
                    })
                }),
            })
            .collect(),
    }
}

/// A shape's own geometry in world space (before its `to_world` for `instance`s' groups: the
/// caller passes the group's), and whether it is a mesh (its normals as the file has them).
fn geometry(
    builder: &Builder,
    plugin: &Plugin,
    warnings: &mut Vec<String>,
) -> Result<Geometry, SceneError> {
    let kind = plugin.kind.as_str();
    let to_world = plugin
        .transform("to_world")?
        .map_or(DMat4::IDENTITY, |(m, _)| m);
    let flip = plugin.boolean_or("flip_normals", false)?;
    let file = |builder: &Builder| -> Result<PathBuf, SceneError> {
        let (name, at) = plugin
            .string("filename")?
            .ok_or_else(|| plugin.error("needs a 'filename'"))?;
        builder
            .resolve(&name, &at)
            .ok_or_else(|| plugin.error_at(&at, format!("filename '{name}': file not found")))
    };
    let mut geometry = match kind {
        "obj" | "ply" | "serialized" => {
            let path = file(builder)?;
            let face_normals = plugin.boolean_or("face_normals", false)?;
            let (g, file_face_normals) = match kind {
                "obj" => {
                    // Mitsuba ignores an OBJ's materials (the shape's BSDF is the scene's).
                    let flip_v = plugin.boolean_or("flip_tex_coords", true)?;
                    (mesh_geometry(&load_obj_geometry(&path)?, flip_v), false)
                }
                "ply" => (
                    mesh_geometry(&load_ply_with_attributes(&path)?, false),
                    false,
                ),
                _ => {
                    let index = plugin.integer("shape_index")?.unwrap_or(0);
                    let index = usize::try_from(index).map_err(|_| {
                        plugin.error(format!("shape_index {index} must not be negative"))
                    })?;
                    load_serialized(&path, index).map_err(|m| plugin.error(m))?
                }
            };
            if g.triangles.is_empty() {
                return Err(plugin.error(format!("{} has no triangles", path.display())));
            }
            let g = g.transformed(&to_world, false);
            if face_normals || file_face_normals {
                g.without_normals()
            } else if g.triangles.iter().any(|t| t.n.is_none()) {
                // Mitsuba computes vertex normals for a mesh without them.
                g.with_smooth_normals()
            } else {
                g
            }
        }
        "rectangle" => shapes::rectangle().transformed(&to_world, true),
        "cube" => shapes::cube().transformed(&to_world, true),
        "disk" => shapes::disk().transformed(&to_world, true),
        "sphere" => {
            let center = plugin.point("center")?.unwrap_or(DVec3::ZERO);
            let radius = plugin.float_or("radius", 1.0)?;
            if radius.is_nan() || radius <= 0.0 {
                return Err(plugin.error(format!("radius {radius} must be positive")));
            }
            let m = to_world
                * DMat4::from_translation(center)
                * DMat4::from_scale(DVec3::splat(radius));
            // Mitsuba's sphere is a sphere whatever to_world does: its centre is where the
            // matrix takes the origin and its radius the length it gives the x axis (a
            // non-uniform scale or a shear is dropped, as Mitsuba's own images show).
            let x = m.transform_vector3(DVec3::X);
            let r = x.length();
            let c = m.transform_point3(DVec3::ZERO);
            let uniform = [DVec3::Y, DVec3::Z].iter().all(|&a| {
                let a = m.transform_vector3(a);
                (a.length() - r).abs() <= 1e-9 * r && a.dot(x).abs() <= 1e-9 * r * r
            });
            let m = if uniform {
                m
            } else {
                warnings.push(format!(
                    "{}: sphere: to_world scales or shears it unevenly; like Mitsuba, passgraph renders a sphere of radius {r} (the length of its x axis) at {c}",
                    plugin.at.location()
                ));
                DMat4::from_translation(c) * DMat4::from_scale(DVec3::splat(r))
            };
            shapes::sphere().transformed(&m, true)
        }
        "cylinder" => {
            let p0 = plugin.point("p0")?.unwrap_or(DVec3::ZERO);
            let p1 = plugin.point("p1")?.unwrap_or(DVec3::Z);
            let radius = plugin.float_or("radius", 1.0)?;
            if radius.is_nan() || radius <= 0.0 {
                return Err(plugin.error(format!("radius {radius} must be positive")));
            }
            let frame = shapes::cylinder_frame(p0, p1, radius)
                .ok_or_else(|| plugin.error("p0 and p1 must differ"))?;
            shapes::cylinder().transformed(&(to_world * frame), true)
        }
        other => {
            return Err(plugin.error(format!(
                "shape type '{other}' is not supported (supported: obj, ply, serialized, rectangle, cube, disk, sphere, cylinder, shapegroup, instance)"
            )));
        }
    };
    if flip {
        geometry = geometry.flipped();
    }
    Ok(geometry)
}

impl Builder {
    fn shape_bsdf(&mut self, plugin: &Plugin) -> Result<Bsdf, SceneError> {
        let emits = plugin.children.iter().any(|c| c.plugin.class == "emitter");
        Ok(match plugin.child_of("bsdf")? {
            // Mitsuba's default: a diffuse of reflectance 0.5, or 0 on an emitter (its light
            // reflects nothing, as the references show: a lit card's pixels are its radiance).
            None => Bsdf {
                material: Material::diffuse([if emits { 0.0 } else { 0.5 }; 3]),
                to_uv: None,
                back: if emits { Back::Same } else { Back::Black },
                null: false,
            },
            Some(c) => bsdf(self, &c.plugin)?,
        })
    }

    fn shape(
        &mut self,
        plugin: &Plugin,
        number: usize,
        groups: &mut Groups,
    ) -> Result<(), SceneError> {
        match plugin.kind.as_str() {
            "shapegroup" => return self.shapegroup(plugin, groups),
            "instance" => return self.instance(plugin, groups),
            _ => {}
        }
        let mut warnings = Vec::new();
        let geometry = geometry(self, plugin, &mut warnings)?;
        self.warnings.extend(warnings);
        let b = self.shape_bsdf(plugin)?;
        let mut material = b.material;
        if let Some(e) = plugin.child_of("emitter")? {
            let e = &e.plugin;
            if e.kind != "area" {
                return Err(e.error("only an area emitter can be nested in a shape"));
            }
            let radiance = e.constant_color("radiance", [1.0; 3])?;
            if radiance.iter().any(|v| !v.is_finite() || *v < 0.0) {
                return Err(e.error(format!(
                    "radiance {radiance:?} must be finite and not negative"
                )));
            }
            e.finish()?;
            material.ke = radiance.map(|v| v as f32);
        }
        plugin.finish()?;
        let name = format!("shape {number} ({}, {})", plugin.kind, plugin.at.location());
        let index = self.material(material, &b.back, name);
        self.add(plugin, &geometry, index, b.to_uv)
    }

    fn shapegroup(&mut self, plugin: &Plugin, groups: &mut Groups) -> Result<(), SceneError> {
        let mut shapes = Vec::new();
        for c in plugin.children_of("shape") {
            let s = &c.plugin;
            if matches!(s.kind.as_str(), "shapegroup" | "instance") {
                return Err(s.error("a shapegroup cannot hold another shapegroup or an instance"));
            }
            if s.children.iter().any(|c| c.plugin.class == "emitter") {
                return Err(s.error("a shape in a shapegroup cannot emit (as in Mitsuba)"));
            }
            let mut warnings = Vec::new();
            let g = geometry(self, s, &mut warnings)?;
            self.warnings.extend(warnings);
            let b = self.shape_bsdf(s)?;
            s.finish()?;
            shapes.push((
                g,
                b,
                format!("{} in shapegroup ({})", s.kind, s.at.location()),
            ));
        }
        plugin.finish()?;
        groups.insert(plugin as *const Plugin, shapes);
        Ok(())
    }

    fn instance(&mut self, plugin: &Plugin, groups: &Groups) -> Result<(), SceneError> {
        let group = plugin
            .child_of("shape")?
            .filter(|c| c.plugin.kind == "shapegroup")
            .ok_or_else(|| plugin.error("an instance needs a <ref> to a shapegroup"))?;
        let to_world = plugin
            .transform("to_world")?
            .map_or(DMat4::IDENTITY, |(m, _)| m);
        plugin.finish()?;
        let key = Rc::as_ptr(&group.plugin);
        let shapes = groups
            .get(&key)
            .cloned()
            .ok_or_else(|| plugin.error("the shapegroup must be declared before its instances"))?;
        for (g, b, name) in shapes {
            let index = self.material(b.material, &b.back, name);
            // Mitsuba's instance moves the group's shapes as they are (meshes and analytic
            // ones alike: it does not re-derive an analytic shape's normal).
            self.add(plugin, &g.transformed(&to_world, false), index, b.to_uv)?;
        }
        Ok(())
    }
}

/// The integrator's longest path (Mitsuba's max_depth; `direct` is 2: emitters and direct
/// light) and Russian roulette (`path`'s rr_depth, Mitsuba's default 5; none where it would
/// start past the longest path). Wrappers (`moment`, `aov`) render their nested integrator.
fn integrator(plugin: &Plugin, options: &SceneOptions) -> Result<(u32, Option<u32>), SceneError> {
    let (depth, rr) = match plugin.kind.as_str() {
        "path" => {
            let depth = plugin.integer("max_depth")?.unwrap_or(-1);
            let rr = plugin.integer("rr_depth")?.unwrap_or(5);
            hide_emitters(plugin)?;
            plugin.finish()?;
            let depth = depth_of(plugin, depth, options)?;
            let rr_at = plugin
                .property("rr_depth")
                .map_or(plugin.at.clone(), |p| p.at.clone());
            let rr = crate::scene::description::check_rr_depth(rr)
                .map_err(|m| plugin.error_at(&rr_at, m))?;
            // The k-th BSDF sample ends a path of k + 1 segments: past max_depth - 1, none.
            (depth, (rr < depth).then_some(rr))
        }
        "direct" => {
            // The sample counts change the noise, not the expectation.
            for name in ["emitter_samples", "bsdf_samples", "shading_samples"] {
                plugin.accept(name);
            }
            hide_emitters(plugin)?;
            plugin.finish()?;
            (2, None)
        }
        "moment" | "aov" => {
            // The AOVs are extra image channels; passgraph renders the image.
            plugin.accept("aovs");
            let nested = plugin.child_of("integrator")?.ok_or_else(|| {
                plugin.error(format!("{} needs a nested <integrator>", plugin.kind))
            })?;
            let depth = integrator(&nested.plugin, options)?;
            plugin.finish()?;
            depth
        }
        other => {
            return Err(plugin.error(format!(
                "integrator type '{other}' is not supported (supported: path, direct, moment, aov)"
            )));
        }
    };
    match options.max_depth {
        Some(d) => Ok((d, rr.filter(|&rr| rr < d))),
        None => Ok((depth, rr)),
    }
}

fn hide_emitters(plugin: &Plugin) -> Result<(), SceneError> {
    if plugin.boolean_or("hide_emitters", false)? {
        return Err(plugin.error("hide_emitters true is not supported"));
    }
    Ok(())
}

fn depth_of(plugin: &Plugin, depth: i64, options: &SceneOptions) -> Result<u32, SceneError> {
    if let Some(d) = options.max_depth {
        // The command line's --max-depth replaces the file's (unbounded included).
        return Ok(d);
    }
    let at = plugin
        .property("max_depth")
        .map_or(plugin.at.clone(), |p| p.at.clone());
    match depth {
        // Unbounded: Russian roulette ends the paths.
        -1 => Ok(MAX_MAX_DEPTH),
        d if d >= 1 && d <= i64::from(MAX_MAX_DEPTH) => Ok(d as u32),
        d => Err(plugin.error_at(
            &at,
            format!("max_depth {d} is not supported (1 to {MAX_MAX_DEPTH}, or -1)"),
        )),
    }
}

/// Builds the scene of a parsed file.
pub fn build(
    parsed: ParsedScene,
    path: &Path,
    options: &SceneOptions,
) -> Result<Built, SceneError> {
    let root = &parsed.root;
    let mut b = Builder::new(parsed.search.clone());
    // Without an integrator, Mitsuba's default: path, unbounded, Russian roulette from 5.
    let (max_depth, rr_depth) = match root.child_of("integrator")? {
        Some(c) => integrator(&c.plugin, options)?,
        None => {
            let depth = options.max_depth.unwrap_or(MAX_MAX_DEPTH);
            (depth, (5 < depth).then_some(5))
        }
    };
    let sensors = root.children_of("sensor");
    let sensor: Sensor = match sensors[..] {
        [one] => sensor(&one.plugin)?,
        [] => {
            return Err(SceneError::Mitsuba {
                at: root.at.location(),
                plugin: "scene".into(),
                message: "the scene has no <sensor> (passgraph needs its camera and film)".into(),
            });
        }
        [_, second, ..] => {
            return Err(second
                .plugin
                .error("a second sensor is not supported (passgraph renders one camera)"));
        }
    };
    for c in root.children_of("emitter") {
        emitter(&mut b, &c.plugin)?;
    }
    let mut groups = Groups::new();
    let mut number = 0;
    for c in root.children_of("shape") {
        number += 1;
        b.shape(&c.plugin, number, &mut groups)?;
    }
    // BSDFs and textures declared at the top level are used through their ids (a <ref>).
    for class in ["bsdf", "texture"] {
        for c in root.children_of(class) {
            if c.plugin.id.is_none() {
                return Err(c.plugin.error(
                    "a top-level plugin without an id cannot be used (give it an id and <ref> it)",
                ));
            }
        }
    }
    root.finish()?;
    if b.triangles.is_empty() {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    if let Some((far, at)) = &sensor.far_clip {
        let eye = sensor.camera.eye();
        let farthest = b
            .triangles
            .iter()
            .flat_map(|t| t.vertices)
            .map(|v| f64::from(v.distance(eye)))
            .fold(0.0, f64::max);
        if farthest > *far {
            return Err(SceneError::Mitsuba {
                at: at.location(),
                plugin: "sensor".into(),
                message: format!(
                    "far_clip {far} cuts the scene (a vertex lies {farthest} from the eye); passgraph's camera rays do not stop: raise far_clip or remove it"
                ),
            });
        }
    }
    b.warnings.extend(sensor.border_note.clone());
    // Every opacity a Mitsuba scene gives is a mask's (bsdf.rs): a null interaction where
    // the surface is not hit, not a cut-out.
    let null_masks = (0..b.materials.len() as u32)
        .filter(|&i| b.materials[i as usize].has_opacity())
        .collect();
    let mesh = Mesh {
        path: path.to_path_buf(),
        triangles: b.triangles,
        materials: b.materials,
        material_names: b.material_names,
        textures: b.textures,
        back_materials: b.back_materials,
        null_masks,
        warnings: b.warnings,
    };
    Ok(Built {
        scene: Scene {
            path: path.to_path_buf(),
            mesh,
            camera: sensor.camera,
            max_depth,
            rr_depth,
            emitters: Emitters {
                lights: b.lights,
                environment: b.environment,
            },
            filter: sensor.filter,
        },
        film_size: sensor.size,
        sample_count: sensor.sample_count,
    })
}
