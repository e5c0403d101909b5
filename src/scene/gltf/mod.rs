//! glTF 2.0 scenes (`.gltf` with embedded or external buffers and images, `.glb`) through the
//! `gltf` crate: the default scene's node tree flattened into one triangle mesh (TRS and matrix
//! transforms; a negative determinant flips the winding, as the specification says), triangle
//! primitives (lists, strips, fans; indexed or not) with `POSITION`, `NORMAL` and `TEXCOORD_0`,
//! the materials (materials.rs), the first camera or one named by `--camera`, and
//! `KHR_lights_punctual` lights.
//!
//! Units as Blender's importer converts them (its default, "Standard"): a point or spot light of
//! I candela has a radiant intensity of I / 683 W/sr, a directional light of E lux an irradiance
//! of E / 683 W/m². A spot's cone: full intensity out to `innerConeAngle`, falling to 0 at
//! `outerConeAngle` (linearly in angle, passgraph's spot, where glTF's falls smoothly in cos).
//! `range` is not read (Blender ignores it too): the light falls off as 1 / d².
//!
//! Tangents for normal maps come from each triangle's UV derivatives (as Mitsuba's; Cycles
//! computes MikkTSpace from the UVs too), so a `TANGENT` attribute is not read.

mod accessors;
pub mod materials;
mod resources;

use super::camera::{CameraDesc, FovAxis, Projection};
use super::description::Scene;
use super::emitters::{AnalyticLight, Emitters};
use super::error::{Location, SceneError};
use super::filter::PixelFilter;
use super::mesh::{Mesh, MeshTriangle};
use accessors::{check, check_finite};
use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

/// The longest path of a glTF scene unless `--max-depth` says otherwise: glossy and glass
/// materials are the format's everyday content, and they need more than one bounce.
pub const GLTF_MAX_DEPTH: u32 = 8;

/// Lumens per watt at 555 nm: Blender's glTF importer's PBR_WATTS_TO_LUMENS.
pub const WATTS_TO_LUMENS: f32 = 683.0;

/// Extensions passgraph reads, so a file may require them.
const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
];

/// Whether a scene path is a glTF file (`.gltf` or `.glb`, any case).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

fn error(path: &Path, message: String) -> SceneError {
    SceneError::Syntax {
        at: Location {
            path: path.to_path_buf(),
            line: None,
            item: None,
        },
        message,
    }
}

/// Loads a glTF 2.0 file as a scene; `camera` picks a camera by its name or its node's name.
pub fn load_gltf(path: &Path, camera: Option<&str>) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| error(path, format!("not a valid glTF 2.0 file: {e}")))?;
    let mut warnings = Vec::new();
    check_extensions(&gltf.document, &mut warnings).map_err(|e| error(path, e))?;
    let document = gltf::Document::from_json(gltf.document.into_json())
        .map_err(|e| error(path, e.to_string()))?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let blob = gltf.blob;
    let buffers = resources::read_buffers(&document, folder, blob).map_err(|e| error(path, e))?;
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| error(path, "the file has no scene".into()))?;

    let mut textures = materials::Textures::new(path, folder, &buffers);
    let mut builder = Builder {
        triangles: Vec::new(),
        materials: Vec::new(),
        names: Vec::new(),
        by_gltf: HashMap::new(),
        lights: Vec::new(),
        cameras: Vec::new(),
        warnings,
    };
    let mut stack: Vec<(gltf::Node<'_>, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    stack.reverse();
    let node_count = document.nodes().len();
    while let Some((node, parent, depth)) = stack.pop() {
        // A tree is at most as deep as it has nodes: deeper, a node is its own ancestor.
        if depth > node_count {
            return Err(error(
                path,
                format!(
                    "{} is its own ancestor: the node hierarchy is not a tree",
                    node_name(&node)
                ),
            ));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(error(
                path,
                format!("{}: its transform is not finite", node_name(&node)),
            ));
        }
        if let Some(mesh) = node.mesh() {
            builder
                .add_mesh(&mesh, &world, &buffers, &mut textures)
                .map_err(|e| error(path, format!("{}: {e}", node_name(&node))))?;
        }
        if let Some(light) = node.light() {
            builder
                .add_light(&light, &world)
                .map_err(|e| error(path, format!("{}: {e}", node_name(&node))))?;
        }
        if let Some(c) = node.camera() {
            builder
                .cameras
                .push((c, node.name().map(str::to_string), world));
        }
        let mut children: Vec<_> = node.children().map(|c| (c, world, depth + 1)).collect();
        children.reverse();
        stack.extend(children);
    }
    if builder.triangles.is_empty() {
        return Err(SceneError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    let mut mesh = Mesh {
        path: path.to_path_buf(),
        triangles: builder.triangles,
        materials: builder.materials,
        material_names: builder.names,
        textures: textures.textures,
        back_materials: BTreeMap::new(),
        null_masks: BTreeSet::new(),
        warnings: builder.warnings,
    };
    let camera = pick_camera(&builder.cameras, camera, &mesh).map_err(|e| error(path, e))?;
    mesh.warnings.dedup();
    Ok(Scene {
        path: path.to_path_buf(),
        mesh,
        camera,
        max_depth: GLTF_MAX_DEPTH,
        rr_depth: None,
        emitters: Emitters {
            lights: builder.lights,
            environment: None,
        },
        filter: PixelFilter::Box,
    })
}

/// A required extension passgraph does not read is an error (named, with what is supported);
/// an optional one a warning, once.
fn check_extensions(document: &gltf::Document, warnings: &mut Vec<String>) -> Result<(), String> {
    for ext in document.extensions_required() {
        if SUPPORTED_EXTENSIONS.contains(&ext) {
            continue;
        }
        let what = match ext {
            "KHR_draco_mesh_compression" => "Draco mesh compression is not supported",
            "EXT_meshopt_compression" | "KHR_meshopt_compression" => {
                "meshopt compression is not supported"
            }
            _ => "it is not supported",
        };
        return Err(format!(
            "the file requires the extension {ext}: {what} (passgraph reads {}); decompress or re-export the file without it",
            SUPPORTED_EXTENSIONS.join(", ")
        ));
    }
    for ext in document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            warnings.push(format!(
                "the file uses the optional extension {ext}, which passgraph does not read: it renders without it"
            ));
        }
    }
    Ok(())
}

fn node_name(node: &gltf::Node<'_>) -> String {
    match node.name() {
        Some(n) => format!("node {} ('{n}')", node.index()),
        None => format!("node {}", node.index()),
    }
}

struct Builder<'a> {
    triangles: Vec<MeshTriangle>,
    materials: Vec<crate::material::Material>,
    names: Vec<String>,
    /// (glTF material index or None for the default, whether the primitive has UVs) ->
    /// passgraph's material and its UV transform.
    by_gltf: HashMap<(Option<usize>, bool), (u32, Option<Mat3>)>,
    lights: Vec<AnalyticLight>,
    cameras: Vec<(gltf::Camera<'a>, Option<String>, Mat4)>,
    warnings: Vec<String>,
}

impl Builder<'_> {
    /// passgraph's material for a primitive's glTF material; a primitive without UVs gets a
    /// copy without textures (a texture lookup needs them).
    fn material(
        &mut self,
        material: &gltf::Material<'_>,
        has_uvs: bool,
        textures: &mut materials::Textures<'_>,
    ) -> Result<(u32, Option<Mat3>), String> {
        let key = (material.index(), has_uvs);
        if let Some(&m) = self.by_gltf.get(&key) {
            return Ok(m);
        }
        let (mut m, uv_transform) = if material.index().is_none() {
            (materials::default_material(), None)
        } else {
            let c = materials::convert(material, textures)?;
            self.warnings.extend(c.warnings);
            (c.material, c.uv_transform)
        };
        if !has_uvs {
            use crate::material::NO_TEXTURE;
            m.map_kd = NO_TEXTURE;
            m.map_ks = NO_TEXTURE;
            m.map_pr = NO_TEXTURE;
            m.map_d = NO_TEXTURE;
            m.surface_map = NO_TEXTURE;
        }
        self.materials.push(m);
        self.names.push(match (material.index(), material.name()) {
            (_, Some(n)) => n.to_string(),
            (Some(i), None) => format!("material{i}"),
            (None, None) => "default".to_string(),
        });
        let entry = ((self.materials.len() - 1) as u32, uv_transform);
        self.by_gltf.insert(key, entry);
        Ok(entry)
    }

    fn add_mesh(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        world: &Mat4,
        buffers: &[Vec<u8>],
        textures: &mut materials::Textures<'_>,
    ) -> Result<(), String> {
        let normal_matrix = Mat3::from_mat4(*world).inverse().transpose();
        let flip = world.determinant() < 0.0;
        for primitive in mesh.primitives() {
            let what = match mesh.name() {
                Some(n) => format!(
                    "mesh {} ('{n}') primitive {}",
                    mesh.index(),
                    primitive.index()
                ),
                None => format!("mesh {} primitive {}", mesh.index(), primitive.index()),
            };
            let read = read_primitive(&primitive, buffers, &what)?;
            let Some(read) = read else { continue };
            let has_uvs = read.uvs.is_some();
            let (material, uv_transform) = self
                .material(&primitive.material(), has_uvs, textures)
                .map_err(|e| format!("{what}: {e}"))?;
            let position = |i: u32| world.transform_point3(Vec3::from(read.positions[i as usize]));
            for [a, b, c] in read.triangles {
                let corners = if flip { [a, c, b] } else { [a, b, c] };
                let normals = read.normals.as_ref().and_then(|n| {
                    let ns = corners
                        .map(|i| (normal_matrix * Vec3::from(n[i as usize])).normalize_or_zero());
                    ns.iter().all(|n| *n != Vec3::ZERO).then_some(ns)
                });
                let uvs = read.uvs.as_ref().map(|uv| {
                    corners.map(|i| {
                        let mut t = Vec2::from(uv[i as usize]);
                        if let Some(m) = &uv_transform {
                            t = materials::transform_uv(m, t);
                        }
                        // glTF's v runs down the image, passgraph's (Mitsuba's) up.
                        Vec2::new(t.x, 1.0 - t.y)
                    })
                });
                self.triangles.push(MeshTriangle {
                    vertices: corners.map(position),
                    material,
                    normals,
                    uvs,
                });
            }
        }
        Ok(())
    }

    fn add_light(
        &mut self,
        light: &gltf::khr_lights_punctual::Light<'_>,
        world: &Mat4,
    ) -> Result<(), String> {
        let what = match light.name() {
            Some(n) => format!("light {} ('{n}')", light.index()),
            None => format!("light {}", light.index()),
        };
        let intensity = light.intensity();
        if !(intensity.is_finite() && intensity >= 0.0) {
            return Err(format!(
                "{what}: intensity {intensity} must be a finite number >= 0"
            ));
        }
        let color = Vec3::from(light.color());
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(format!("{what}: color {color} must be finite and >= 0"));
        }
        let power = color * (intensity / WATTS_TO_LUMENS);
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if forward == Vec3::ZERO {
            return Err(format!(
                "{what}: its node's transform collapses the light's direction"
            ));
        }
        self.lights.push(match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => AnalyticLight::Point {
                position,
                intensity: power,
            },
            gltf::khr_lights_punctual::Kind::Directional => AnalyticLight::Directional {
                direction: forward,
                irradiance: power,
            },
            gltf::khr_lights_punctual::Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let (inner, outer) = (inner_cone_angle.to_degrees(), outer_cone_angle.to_degrees());
                if !(outer > 0.0 && outer <= 90.0 && inner >= 0.0 && inner < outer) {
                    return Err(format!(
                        "{what}: the cone angles {inner_cone_angle} and {outer_cone_angle} must satisfy 0 <= inner < outer <= pi/2"
                    ));
                }
                AnalyticLight::Spot {
                    position,
                    target: position + forward,
                    up: if up.cross(forward) == Vec3::ZERO { Vec3::X } else { up },
                    intensity: power,
                    cutoff_angle: outer,
                    beam_width: inner,
                    texture: None,
                }
            }
        });
        Ok(())
    }
}

/// A primitive's triangles as index triples, and its vertex attributes.
struct Primitive {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    triangles: Vec<[u32; 3]>,
}

/// Reads a primitive, every accessor checked first; `None` for a primitive with no
/// triangles (a strip of two vertices).
fn read_primitive(
    primitive: &gltf::Primitive<'_>,
    buffers: &[Vec<u8>],
    what: &str,
) -> Result<Option<Primitive>, String> {
    use gltf::mesh::Mode;
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Err(format!(
            "{what} has mode {mode:?}; passgraph renders triangles (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN)"
        ));
    }
    let f32_vec3 = [(DataType::F32, Dimensions::Vec3)];
    let Some(pos) = primitive.get(&gltf::Semantic::Positions) else {
        return Err(format!("{what} has no POSITION attribute"));
    };
    check(&pos, &format!("POSITION of {what}"), &f32_vec3, buffers)?;
    let get = |b: gltf::Buffer<'_>| buffers.get(b.index()).map(Vec::as_slice);
    let reader = primitive.reader(get);
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| format!("{what}: POSITION cannot be read"))?
        .collect();
    check_finite(&positions, &pos, &format!("POSITION of {what}"))?;
    let normals = match primitive.get(&gltf::Semantic::Normals) {
        Some(acc) => {
            let role = format!("NORMAL of {what}");
            check(&acc, &role, &f32_vec3, buffers)?;
            let n: Vec<[f32; 3]> = reader
                .read_normals()
                .ok_or_else(|| format!("{what}: NORMAL cannot be read"))?
                .collect();
            check_finite(&n, &acc, &role)?;
            same_count(what, "NORMAL", n.len(), positions.len())?;
            Some(n)
        }
        None => None,
    };
    let uvs = match primitive.get(&gltf::Semantic::TexCoords(0)) {
        Some(acc) => {
            let role = format!("TEXCOORD_0 of {what}");
            let allowed = [
                (DataType::F32, Dimensions::Vec2),
                (DataType::U8, Dimensions::Vec2),
                (DataType::U16, Dimensions::Vec2),
            ];
            check(&acc, &role, &allowed, buffers)?;
            let uv: Vec<[f32; 2]> = reader
                .read_tex_coords(0)
                .ok_or_else(|| format!("{what}: TEXCOORD_0 cannot be read"))?
                .into_f32()
                .collect();
            check_finite(&uv, &acc, &role)?;
            same_count(what, "TEXCOORD_0", uv.len(), positions.len())?;
            Some(uv)
        }
        None => None,
    };
    let count = positions.len();
    let indices: Vec<u32> = match primitive.indices() {
        Some(acc) => {
            let allowed = [
                (DataType::U8, Dimensions::Scalar),
                (DataType::U16, Dimensions::Scalar),
                (DataType::U32, Dimensions::Scalar),
            ];
            check(&acc, &format!("indices of {what}"), &allowed, buffers)?;
            let indices: Vec<u32> = reader
                .read_indices()
                .ok_or_else(|| format!("{what}: its indices cannot be read"))?
                .into_u32()
                .collect();
            if let Some((i, &v)) = indices
                .iter()
                .enumerate()
                .find(|(_, v)| **v as usize >= count)
            {
                return Err(format!(
                    "{what}: index {i} is {v}, but POSITION has {count} vertices (valid: 0..{count})"
                ));
            }
            indices
        }
        None => (0..count as u32).collect(),
    };
    let triangles: Vec<[u32; 3]> = match mode {
        Mode::Triangles => indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        // Every other strip triangle swaps two corners to keep the winding.
        Mode::TriangleStrip => (2..indices.len())
            .map(|i| {
                if i % 2 == 0 {
                    [indices[i - 2], indices[i - 1], indices[i]]
                } else {
                    [indices[i - 1], indices[i - 2], indices[i]]
                }
            })
            .collect(),
        _ => (2..indices.len())
            .map(|i| [indices[0], indices[i - 1], indices[i]])
            .collect(),
    };
    if triangles.is_empty() {
        return Ok(None);
    }
    Ok(Some(Primitive {
        positions,
        normals,
        uvs,
        triangles,
    }))
}

/// The camera the user named, or the file's first, or a default framing of the mesh: from +z
/// (glTF's front), a 39.6-degree field of view on the longer side (Blender's default 50 mm
/// lens), the whole bounding sphere in view.
fn pick_camera(
    cameras: &[(gltf::Camera<'_>, Option<String>, Mat4)],
    name: Option<&str>,
    mesh: &Mesh,
) -> Result<CameraDesc, String> {
    let chosen = match name {
        Some(name) => Some(
            cameras
                .iter()
                .find(|(c, node, _)| c.name() == Some(name) || node.as_deref() == Some(name))
                .ok_or_else(|| {
                    let names: Vec<String> = cameras
                        .iter()
                        .map(|(c, node, _)| {
                            c.name()
                                .or(node.as_deref())
                                .map_or_else(|| format!("camera {}", c.index()), str::to_string)
                        })
                        .collect();
                    format!(
                        "--camera {name}: no camera or camera node has that name (cameras: {})",
                        if names.is_empty() {
                            "none".to_string()
                        } else {
                            names.join(", ")
                        }
                    )
                })?,
        ),
        None => cameras.first(),
    };
    let Some((camera, _, world)) = chosen else {
        return default_camera(mesh);
    };
    let eye = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
    let projection = match camera.projection() {
        gltf::camera::Projection::Perspective(p) => Projection::Perspective {
            fov_degrees: p.yfov().to_degrees(),
            fov_axis: FovAxis::Y,
            lens: None,
        },
        // xmag is half the width; the height follows the image (ymag is not read).
        gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
            width: 2.0 * o.xmag(),
        },
    };
    CameraDesc::with_projection(eye, eye + forward, up, projection)
        .map_err(|e| format!("camera {}: {e}", camera.index()))
}

fn default_camera(mesh: &Mesh) -> Result<CameraDesc, String> {
    let (lo, hi) = mesh.triangles.iter().flat_map(|t| t.vertices).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-3);
    let fov: f32 = 39.6;
    let distance = radius / (fov.to_radians() * 0.5).sin();
    CameraDesc::with_projection(
        centre + Vec3::Z * distance,
        centre,
        Vec3::Y,
        Projection::Perspective {
            fov_degrees: fov,
            fov_axis: FovAxis::Larger,
            lens: None,
        },
    )
    .map_err(|e| format!("the default camera: {e}"))
}

/// A vertex attribute has one element per position.
fn same_count(what: &str, attribute: &str, count: usize, positions: usize) -> Result<(), String> {
    if count == positions {
        return Ok(());
    }
    Err(format!(
        "{what}: {attribute} has {count} elements, POSITION {positions}"
    ))
}
