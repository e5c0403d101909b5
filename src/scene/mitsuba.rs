//! The loaded scene as a Mitsuba 3 scene: `scene.xml` and one OBJ per material, written from
//! the same [`Scene`] the renderer draws (one parser for both), so that a reference renders
//! what passgraph renders.
//!
//! The XML takes Mitsuba parameters with defaults (`$spp`, `$sampler_type`, `$max_depth`,
//! `$seed`): `mi.load_file(xml, spp=64, sampler_type="multijitter")`. Each material kind has its
//! Mitsuba plugin (see [`bsdf_xml`]); Blinn-Phong has none and is an error.

use super::camera::{CameraDesc, CameraKind, Projection};
use super::description::{MAX_MAX_DEPTH, Scene};
use super::emitters::AnalyticLight;
use super::environment::{Environment, EnvironmentMap};
use super::filter::PixelFilter;
use super::mesh::MeshTriangle;
use super::texture::Texture;
use crate::bsdf::microfacet::Distribution;
use crate::material::{
    FRESNEL_CONDUCTOR, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_LAMBERT,
    MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC,
    Material, NO_TEXTURE, SURFACE_MAP_BUMP,
};
use glam::Vec3;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// What the command line sets besides the scene.
#[derive(Clone, Debug)]
pub struct ExportOptions {
    pub size: [u32; 2],
    /// Replaces the scene's `max_depth` (the `$max_depth` default).
    pub max_depth: Option<u32>,
}

/// Writes `dir/scene.xml` and `dir/meshes/*.obj`; returns the files written.
pub fn export(scene: &Scene, dir: &Path, options: &ExportOptions) -> Result<Vec<PathBuf>, String> {
    let groups = material_groups(scene);
    // Every material is checked before anything is written.
    let mut shapes = Vec::new();
    for (n, (material, triangles)) in groups.iter().enumerate() {
        let file = format!("meshes/mesh{n}.obj");
        let bsdf = bsdf_xml(scene, *material)?;
        shapes.push((file, *material, bsdf, triangles));
    }
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes)
        .map_err(|e| format!("{}: cannot create: {e}", meshes.display()))?;
    let mut written = Vec::new();
    let mut shape_xml = String::new();
    for (file, material, bsdf, triangles) in &shapes {
        let path = dir.join(file);
        let (obj, has_normals) = mesh_obj(triangles);
        crate::atomic_write::write_atomic(&path, obj.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        written.push(path);
        shape_xml += &shape(scene, *material, file, has_normals, bsdf);
    }
    let emitters = emitters_xml(scene)?;
    if let Some(Environment::Map(map)) = &scene.emitters.environment {
        let path = dir.join(ENVIRONMENT_FILE);
        crate::atomic_write::write_atomic(&path, &environment_exr(map)?)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        written.push(path);
    }
    shape_xml += &emitters;
    let xml = scene_xml(scene, options, &shape_xml);
    let path = dir.join("scene.xml");
    crate::atomic_write::write_atomic(&path, xml.as_bytes())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    written.push(path);
    Ok(written)
}

/// The environment image beside `scene.xml`: the texels passgraph loaded, unscaled, as float
/// OpenEXR, so Mitsuba reads the same numbers whatever the original file's encoding.
const ENVIRONMENT_FILE: &str = "environment.exr";

fn environment_exr(map: &EnvironmentMap) -> Result<Vec<u8>, String> {
    let img = &map.image;
    let data: Vec<f32> = img.texels.iter().flatten().copied().collect();
    let buffer = image::Rgb32FImage::from_raw(img.width, img.height, data)
        .ok_or("environment image: texel count does not match its size")?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb32F(buffer)
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .map_err(|e| format!("{}: cannot encode: {e}", map.path.display()))?;
    Ok(bytes.into_inner())
}

/// `<point name="position" x=".." .../>` and the like.
fn point_xml(tag: &str, name: &str, v: Vec3) -> String {
    format!(
        "<{tag} name=\"{name}\" x=\"{}\" y=\"{}\" z=\"{}\"/>",
        v.x, v.y, v.z
    )
}

/// The scene's point, spot and directional lights and its environment as Mitsuba emitters (an
/// environment image is read from [`ENVIRONMENT_FILE`] beside the XML).
fn emitters_xml(scene: &Scene) -> Result<String, String> {
    let mut xml = String::new();
    for light in &scene.emitters.lights {
        match *light {
            AnalyticLight::Point {
                position,
                intensity,
            } => {
                let _ = write!(
                    xml,
                    "    <emitter type=\"point\">\n        {}\n        <rgb name=\"intensity\" value=\"{}\"/>\n    </emitter>\n",
                    point_xml("point", "position", position),
                    rgb(intensity.into())
                );
            }
            AnalyticLight::Spot {
                position,
                target,
                up,
                intensity,
                cutoff_angle,
                beam_width,
                ref texture,
            } => {
                let texture = match texture {
                    None => String::new(),
                    Some(t) => indent(&bitmap("texture", t, false, "spot light")?, 2),
                };
                let _ = write!(
                    xml,
                    "    <emitter type=\"spot\">\n        <transform name=\"to_world\">\n            <lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>\n        </transform>\n        <rgb name=\"intensity\" value=\"{}\"/>\n        <float name=\"cutoff_angle\" value=\"{cutoff_angle}\"/>\n        <float name=\"beam_width\" value=\"{beam_width}\"/>\n{texture}    </emitter>\n",
                    rgb(position.into()),
                    rgb(target.into()),
                    rgb(up.into()),
                    rgb(intensity.into())
                );
            }
            AnalyticLight::Directional {
                direction,
                irradiance,
            } => {
                let _ = write!(
                    xml,
                    "    <emitter type=\"directional\">\n        {}\n        <rgb name=\"irradiance\" value=\"{}\"/>\n    </emitter>\n",
                    point_xml("vector", "direction", direction),
                    rgb(irradiance.into())
                );
            }
        }
    }
    match &scene.emitters.environment {
        None => {}
        Some(Environment::Constant { radiance }) => {
            let _ = write!(
                xml,
                "    <emitter type=\"constant\">\n        <rgb name=\"radiance\" value=\"{}\"/>\n    </emitter>\n",
                rgb((*radiance).into())
            );
        }
        Some(Environment::Map(map)) => {
            let m = map.to_world;
            let matrix: Vec<String> = (0..4)
                .flat_map(|r| {
                    (0..4).map(move |c| match (r, c) {
                        (3, 3) => "1".to_string(),
                        (3, _) | (_, 3) => "0".to_string(),
                        _ => m.col(c)[r].to_string(),
                    })
                })
                .collect();
            let _ = write!(
                xml,
                "    <emitter type=\"envmap\">\n        <string name=\"filename\" value=\"{ENVIRONMENT_FILE}\"/>\n        <float name=\"scale\" value=\"{}\"/>\n        <transform name=\"to_world\">\n            <matrix value=\"{}\"/>\n        </transform>\n    </emitter>\n",
                map.scale,
                matrix.join(" ")
            );
        }
    }
    Ok(xml)
}

/// The triangles of each used material, in file order, by material index.
fn material_groups(scene: &Scene) -> Vec<(u32, Vec<&MeshTriangle>)> {
    let mut groups: Vec<(u32, Vec<&MeshTriangle>)> = Vec::new();
    for t in &scene.mesh.triangles {
        match groups.iter_mut().find(|(m, _)| *m == t.material) {
            Some((_, list)) => list.push(t),
            None => groups.push((t.material, vec![t])),
        }
    }
    groups
}

/// An OBJ of unshared triangles (front faces counter-clockwise, as loaded); with `vn` when a
/// triangle has normals (the others get their face normal: flat, as passgraph shades them) and
/// `vt` when one has uvs (the others (0, 0), what `shading_uv` gives them). Returns the text
/// and whether it has normals.
fn mesh_obj(triangles: &[&MeshTriangle]) -> (String, bool) {
    let has_normals = triangles.iter().any(|t| t.normals.is_some());
    let has_uvs = triangles.iter().any(|t| t.uvs.is_some());
    let mut text = String::new();
    for t in triangles {
        for p in t.vertices {
            let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
        }
        if has_uvs {
            for uv in t.uvs.unwrap_or_default() {
                let _ = writeln!(text, "vt {} {}", uv.x, uv.y);
            }
        }
        if has_normals {
            let [a, b, c] = t.vertices;
            let face = (b - a).cross(c - a).normalize_or(Vec3::Z);
            for n in t.normals.unwrap_or([face; 3]) {
                let _ = writeln!(text, "vn {} {} {}", n.x, n.y, n.z);
            }
        }
    }
    for k in 0..triangles.len() {
        let corner = |i: usize| {
            let i = 3 * k + i + 1;
            match (has_uvs, has_normals) {
                (false, false) => format!("{i}"),
                (true, false) => format!("{i}/{i}"),
                (false, true) => format!("{i}//{i}"),
                (true, true) => format!("{i}/{i}/{i}"),
            }
        };
        let _ = writeln!(text, "f {} {} {}", corner(0), corner(1), corner(2));
    }
    (text, has_normals)
}

fn shape(scene: &Scene, material: u32, file: &str, has_normals: bool, bsdf: &str) -> String {
    let m = scene.mesh.materials[material as usize];
    let mut xml = format!(
        "    <!-- {} -->\n    <shape type=\"obj\">\n        <string name=\"filename\" value=\"{}\"/>\n",
        comment(&scene.mesh.material_names[material as usize]),
        attribute(file)
    );
    if !has_normals {
        xml += "        <boolean name=\"face_normals\" value=\"true\"/>\n";
    }
    xml += &indent(bsdf, 2);
    if m.is_emissive() {
        // Mitsuba's area lights emit on the front face only, as passgraph's.
        let _ = write!(
            xml,
            "        <emitter type=\"area\">\n            <rgb name=\"radiance\" value=\"{}\"/>\n        </emitter>\n",
            rgb(m.ke)
        );
    }
    xml + "    </shape>\n"
}

fn scene_xml(scene: &Scene, options: &ExportOptions, shapes: &str) -> String {
    let c = &scene.camera;
    let [w, h] = options.size;
    let depth = options.max_depth.unwrap_or(scene.max_depth);
    // Unbounded is Mitsuba's -1.
    let depth = if depth == MAX_MAX_DEPTH {
        -1
    } else {
        i64::from(depth)
    };
    let (rr_comment, rr_depth) = match scene.rr_depth {
        Some(rr) => (
            "Russian roulette as the passgraph scene's rr_depth (-D rr_depth=N changes it).",
            rr,
        ),
        None => (
            "No Russian roulette, as the passgraph scene (-D rr_depth=5: Mitsuba's default).",
            MAX_MAX_DEPTH,
        ),
    };
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<!-- {source}, written by `passgraph mitsuba-scene`. -->
<scene version="3.0.0">
    <default name="spp" value="4"/>
    <default name="sampler_type" value="independent"/>
    <default name="max_depth" value="{depth}"/>
    <default name="seed" value="0"/>
    <!-- {rr_comment} -->
    <default name="rr_depth" value="{rr_depth}"/>
    <integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
        <integer name="rr_depth" value="$rr_depth"/>
    </integrator>
    <sensor type="{sensor}">
{projection}        <transform name="to_world">
{scale}            <lookat origin="{eye}" target="{target}" up="{up}"/>
        </transform>
        <sampler type="$sampler_type">
            <integer name="sample_count" value="$spp"/>
            <integer name="seed" value="$seed"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="{w}"/>
            <integer name="height" value="{h}"/>
            <string name="pixel_format" value="rgb"/>
{filter}        </film>
    </sensor>
{shapes}</scene>
"#,
        source = comment(&scene.path.display().to_string()),
        sensor = sensor_type(c),
        projection = indent(&(sensor_parameters(c) + &far_clip(scene)), 2),
        scale = indent(&sensor_scale(c), 3),
        filter = indent(&film_filter(scene.filter), 3),
        eye = rgb(c.eye().into()),
        target = rgb(c.target().into()),
        up = rgb(c.up().into()),
    )
}

/// The Mitsuba sensor plugin of a camera.
fn sensor_type(c: &CameraDesc) -> &'static str {
    match c.kind() {
        CameraKind::Pinhole => "perspective",
        CameraKind::ThinLens => "thinlens",
        CameraKind::Orthographic => "orthographic",
    }
}

/// The sensor's field of view and lens.
fn sensor_parameters(c: &CameraDesc) -> String {
    match c.projection() {
        Projection::Perspective {
            fov_degrees,
            fov_axis,
            lens,
        } => {
            let mut xml = format!(
                "<string name=\"fov_axis\" value=\"{}\"/>\n<float name=\"fov\" value=\"{fov_degrees}\"/>\n",
                fov_axis.mitsuba_name()
            );
            if let Some(lens) = lens {
                let _ = write!(
                    xml,
                    "<float name=\"aperture_radius\" value=\"{}\"/>\n<float name=\"focus_distance\" value=\"{}\"/>\n",
                    lens.aperture_radius, lens.focus_distance
                );
            }
            xml
        }
        Projection::Orthographic { .. } => String::new(),
    }
}

/// Mitsuba's sensors stop camera rays at `far_clip` (default 1e4) where passgraph's run on:
/// beyond twice the farthest vertex from the eye, so both see the whole scene (the outdoor
/// showcase's ground reaches 2e4 away: with the default, Mitsuba's horizon showed sky where
/// passgraph's showed ground).
fn far_clip(scene: &Scene) -> String {
    let eye = scene.camera.eye();
    let farthest = scene
        .mesh
        .triangles
        .iter()
        .flat_map(|t| t.vertices)
        .map(|v| v.distance(eye))
        .fold(0.0f32, f32::max);
    format!(
        "<float name=\"far_clip\" value=\"{}\"/>\n",
        (2.0 * farthest).max(1e4)
    )
}

/// An orthographic sensor's plane spans x in [-1, 1] before to_world: scaled to half the width
/// (applied before the lookat, as Mitsuba composes transform elements in order).
fn sensor_scale(c: &CameraDesc) -> String {
    match c.projection() {
        Projection::Orthographic { width } => {
            let half = 0.5 * width;
            format!("<scale x=\"{half}\" y=\"{half}\"/>\n")
        }
        Projection::Perspective { .. } => String::new(),
    }
}

/// The film's reconstruction filter. A wider one than the box also samples the border, the
/// filter's radius beyond the image: passgraph's filter importance sampling draws positions
/// there for the edge pixels too, so both converge to the same filtered image.
fn film_filter(filter: PixelFilter) -> String {
    let mut xml = filter.mitsuba_xml() + "\n";
    if filter != PixelFilter::Box {
        xml += "<boolean name=\"sample_border\" value=\"true\"/>\n";
    }
    xml
}

/// A conductor's Fresnel term as Mitsuba's parameters: its complex index as `eta` and `k`
/// (RGB), or `material none` (Fresnel 1).
fn conductor_ior(m: &Material) -> String {
    if m.fresnel == FRESNEL_CONDUCTOR {
        format!(
            "<rgb name=\"eta\" value=\"{}\"/>\n<rgb name=\"k\" value=\"{}\"/>\n",
            rgb(m.eta),
            rgb(m.k)
        )
    } else {
        "<string name=\"material\" value=\"none\"/>\n".to_string()
    }
}

/// The BSDF of material `index` as Mitsuba XML:
///
/// - Lambert: `twosided` + `diffuse`.
/// - Conductor: `twosided` + `roughconductor` (`material none`, Fresnel = kd, or `eta` and
///   `k` with `specular_reflectance` kd), or `conductor` when smooth.
/// - Plastic: `twosided` + `roughplastic` (`nonlinear false`), or `plastic` when smooth.
///
/// Rough models name their `distribution` (ggx or beckmann) and `alpha`.
/// - Dielectric: `roughdielectric`, or `dielectric` when smooth; one-sided, as passgraph's.
/// - Thin dielectric: `thindielectric` (two-sided by itself).
/// - Phong: an error (Mitsuba 3 has no Blinn-Phong).
///
/// Colour maps are `bitmap` textures (sRGB), `map_d` a raw one under a `mask`; `ext_ior` is
/// 1 (vacuum), as passgraph's. A normal map (`norm`) wraps the model in `normalmap`, a bump map
/// in `bumpmap` with its `scale`, both with raw bitmaps, inside `twosided`.
pub fn bsdf_xml(scene: &Scene, index: u32) -> Result<String, String> {
    let m: Material = scene.mesh.materials[index as usize];
    let name = &scene.mesh.material_names[index as usize];
    let textures = &scene.mesh.textures;
    let colour = |param: &str, value: [f32; 3], map: u32| -> Result<String, String> {
        if map == NO_TEXTURE {
            Ok(format!(
                "<rgb name=\"{param}\" value=\"{}\"/>\n",
                rgb(value)
            ))
        } else {
            bitmap(param, &textures[map as usize], false, name)
        }
    };
    if scene.mesh.back_materials.contains_key(&index) {
        return Err(format!(
            "material '{name}' shades its back face as another material (a Mitsuba scene's one-sided BSDF or twosided of two): render that Mitsuba file itself"
        ));
    }
    if m.map_pr != NO_TEXTURE {
        return Err(format!(
            "material '{name}' has a roughness map (map_Pr), which Mitsuba 3 cannot square into its GGX alpha"
        ));
    }
    let distribution = Distribution::from_u32(m.distribution).mitsuba_name();
    let microfacet = |smooth: &str, rough: &str, body: String| {
        if m.alpha > 0.0 {
            format!(
                "<bsdf type=\"{rough}\">\n    <string name=\"distribution\" value=\"{distribution}\"/>\n    <float name=\"alpha\" value=\"{}\"/>\n{}</bsdf>\n",
                m.alpha,
                indent(&body, 1)
            )
        } else {
            format!("<bsdf type=\"{smooth}\">\n{}</bsdf>\n", indent(&body, 1))
        }
    };
    let twosided =
        |inner: String| format!("<bsdf type=\"twosided\">\n{}</bsdf>\n", indent(&inner, 1));
    // A normal or bump map adapts the model inside `twosided`, as passgraph mirrors the
    // perturbed frame on back faces (src/scene/surface_map.rs); the flip of normals facing away
    // and the terminator shadowing are Mitsuba's defaults (since 3.7.1), written out because
    // passgraph models them.
    let mapped = |inner: String| -> Result<String, String> {
        if m.surface_map == NO_TEXTURE {
            return Ok(inner);
        }
        let inner = format!(
            "<boolean name=\"flip_invalid_normals\" value=\"true\"/>\n<boolean name=\"use_shadowing_function\" value=\"true\"/>\n{inner}"
        );
        let texture = &textures[(m.surface_map & !SURFACE_MAP_BUMP) as usize];
        Ok(if m.surface_map & SURFACE_MAP_BUMP == 0 {
            format!(
                "<bsdf type=\"normalmap\">\n{}{}</bsdf>\n",
                indent(&bitmap("normalmap", texture, true, name)?, 1),
                indent(&inner, 1)
            )
        } else {
            format!(
                "<bsdf type=\"bumpmap\">\n{}    <float name=\"scale\" value=\"{}\"/>\n{}</bsdf>\n",
                indent(&bitmap("height", texture, true, name)?, 1),
                m.bump_scale,
                indent(&inner, 1)
            )
        })
    };
    let ior = |m: &Material| {
        format!(
            "<float name=\"int_ior\" value=\"{}\"/>\n<float name=\"ext_ior\" value=\"1.0\"/>\n",
            m.ior
        )
    };
    let bsdf = match m.kind {
        MATERIAL_LAMBERT => twosided(mapped(format!(
            "<bsdf type=\"diffuse\">\n{}</bsdf>\n",
            indent(&colour("reflectance", m.kd, m.map_kd)?, 1)
        ))?),
        MATERIAL_CONDUCTOR => twosided(mapped(microfacet(
            "conductor",
            "roughconductor",
            format!(
                "{}{}",
                conductor_ior(&m),
                colour("specular_reflectance", m.kd, m.map_kd)?
            ),
        ))?),
        MATERIAL_PLASTIC => twosided(mapped(microfacet(
            "plastic",
            "roughplastic",
            format!(
                "{}{}{}<boolean name=\"nonlinear\" value=\"false\"/>\n",
                ior(&m),
                colour("diffuse_reflectance", m.kd, m.map_kd)?,
                colour("specular_reflectance", m.ks, m.map_ks)?
            ),
        ))?),
        MATERIAL_DIELECTRIC => mapped(microfacet(
            "dielectric",
            "roughdielectric",
            format!(
                "{}<rgb name=\"specular_transmittance\" value=\"{}\"/>\n",
                ior(&m),
                rgb(m.tf)
            ),
        ))?,
        // Two-sided by itself, as passgraph's.
        MATERIAL_THIN_DIELECTRIC => mapped(format!(
            "<bsdf type=\"thindielectric\">\n{}</bsdf>\n",
            indent(
                &format!(
                    "{}<rgb name=\"specular_transmittance\" value=\"{}\"/>\n",
                    ior(&m),
                    rgb(m.tf)
                ),
                1
            )
        ))?,
        MATERIAL_PHONG => {
            return Err(format!(
                "material '{name}' is Blinn-Phong, which Mitsuba 3 has no plugin for"
            ));
        }
        MATERIAL_METALLIC_ROUGHNESS => {
            return Err(format!(
                "material '{name}' is glTF's metallic-roughness model, which no Mitsuba 3 plugin \
                 reproduces (its principled BSDF adds specular tint, sheen and a different \
                 Fresnel mix)"
            ));
        }
        other => return Err(format!("material '{name}' has unknown kind {other}")),
    };
    // Cut-outs as Mitsuba's mask, which passes light through with probability 1 - opacity
    // but as a null interaction: a path segment, and a stop for shadow rays (the loader reads
    // it back so, Mesh::null_masks). The same image where max_depth cuts no path through it.
    if m.map_d != NO_TEXTURE {
        let opacity = bitmap("opacity", &textures[m.map_d as usize], true, name)?;
        return Ok(format!(
            "<bsdf type=\"mask\">\n{}{}</bsdf>\n",
            indent(&opacity, 1),
            indent(&bsdf, 1)
        ));
    }
    if m.opacity < 1.0 {
        return Ok(format!(
            "<bsdf type=\"mask\">\n    <float name=\"opacity\" value=\"{}\"/>\n{}</bsdf>\n",
            m.opacity,
            indent(&bsdf, 1)
        ));
    }
    Ok(bsdf)
}

/// A `bitmap` texture of the image file (absolute, so the XML may move): bilinear, repeat (the
/// defaults), `raw` for scalar maps.
fn bitmap(param: &str, texture: &Texture, raw: bool, material: &str) -> Result<String, String> {
    let file = std::fs::canonicalize(&texture.path).map_err(|e| {
        format!(
            "material '{material}': texture '{}': {e}",
            texture.path.display()
        )
    })?;
    Ok(format!(
        "<texture type=\"bitmap\" name=\"{param}\">\n    <string name=\"filename\" value=\"{}\"/>\n    <boolean name=\"raw\" value=\"{raw}\"/>\n</texture>\n",
        attribute(&file.display().to_string())
    ))
}

fn rgb(v: [f32; 3]) -> String {
    format!("{}, {}, {}", v[0], v[1], v[2])
}

fn indent(text: &str, levels: usize) -> String {
    let pad = "    ".repeat(levels);
    text.lines().map(|l| format!("{pad}{l}\n")).collect()
}

fn attribute(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Text safe inside `<!-- -->`.
fn comment(text: &str) -> String {
    text.replace("--", "- -")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::camera::CameraDesc;
    use crate::scene::mesh::Mesh;
    use crate::scene::texture::{Encoding, Texture};

    fn scene(materials: Vec<Material>) -> Scene {
        let names = (0..materials.len()).map(|i| format!("m{i}")).collect();
        let mut texture = Texture::from_texels(1, 1, vec![[1.0; 4]]);
        texture.path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
        texture.encoding = Encoding::Srgb;
        Scene {
            path: "s.ron".into(),
            mesh: Mesh {
                path: "m.obj".into(),
                triangles: Vec::new(),
                materials,
                material_names: names,
                textures: vec![texture],
                back_materials: Default::default(),
                null_masks: Default::default(),
                warnings: Vec::new(),
            },
            camera: CameraDesc::new(Vec3::Z, Vec3::ZERO, Vec3::Y, 40.0).unwrap(),
            max_depth: 3,
            rr_depth: None,
            emitters: Default::default(),
            filter: PixelFilter::Box,
        }
    }

    #[test]
    fn lights_and_the_environment_become_mitsuba_emitters() {
        use crate::scene::emitters::{AnalyticLight, Emitters};
        use crate::scene::environment::{Environment, EnvironmentMap};
        use crate::scene::environment_image::EnvironmentImage;
        let mut s = scene(vec![Material::diffuse([0.5; 3])]);
        let image = EnvironmentImage::from_texels(2, 3, vec![[1.0; 3]; 6]).unwrap();
        s.emitters = Emitters {
            lights: vec![
                AnalyticLight::Point {
                    position: Vec3::new(1.0, 2.0, 3.0),
                    intensity: Vec3::splat(4.0),
                },
                AnalyticLight::Spot {
                    position: Vec3::ZERO,
                    target: Vec3::new(0.0, -1.0, 0.0),
                    up: Vec3::X,
                    intensity: Vec3::ONE,
                    cutoff_angle: 30.0,
                    beam_width: 10.0,
                    texture: None,
                },
                AnalyticLight::Directional {
                    direction: Vec3::new(0.0, -1.0, 0.0),
                    irradiance: Vec3::splat(2.0),
                },
            ],
            environment: Some(Environment::Map(EnvironmentMap::new(
                "sky.exr".into(),
                image,
                2.5,
                glam::Mat3::from_rotation_y(std::f32::consts::FRAC_PI_2),
            ))),
        };
        let xml = emitters_xml(&s).unwrap();
        assert_has(
            &xml,
            &[
                "<emitter type=\"point\">",
                "<point name=\"position\" x=\"1\" y=\"2\" z=\"3\"/>",
                "<rgb name=\"intensity\" value=\"4, 4, 4\"/>",
                "<emitter type=\"spot\">",
                "<lookat origin=\"0, 0, 0\" target=\"0, -1, 0\" up=\"1, 0, 0\"/>",
                "<float name=\"cutoff_angle\" value=\"30\"/>",
                "<float name=\"beam_width\" value=\"10\"/>",
                "<emitter type=\"directional\">",
                "<vector name=\"direction\" x=\"0\" y=\"-1\" z=\"0\"/>",
                "<emitter type=\"envmap\">",
                "<float name=\"scale\" value=\"2.5\"/>",
            ],
        );
        // The rotation, row by row: +90 degrees about y takes +z to +x.
        let matrix = xml.split("<matrix value=\"").nth(1).unwrap();
        let values: Vec<f32> = matrix
            .split('"')
            .next()
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        assert!((values[2] - 1.0).abs() < 1e-6, "{values:?}");
        assert!((values[8] + 1.0).abs() < 1e-6, "{values:?}");
        assert_eq!(values[15], 1.0);
    }

    fn bsdf(m: Material) -> Result<String, String> {
        bsdf_xml(&scene(vec![m]), 0)
    }

    fn assert_has(xml: &str, parts: &[&str]) {
        for p in parts {
            assert!(xml.contains(p), "expected {p} in\n{xml}");
        }
    }

    #[test]
    fn lambert_is_a_two_sided_diffuse() {
        let xml = bsdf(Material::diffuse([0.5, 0.25, 1.0])).unwrap();
        assert_has(
            &xml,
            &[
                "type=\"twosided\"",
                "type=\"diffuse\"",
                "name=\"reflectance\" value=\"0.5, 0.25, 1\"",
            ],
        );
    }

    #[test]
    fn conductors_are_ggx_or_smooth_with_kd_as_fresnel() {
        let rough = Material {
            kind: MATERIAL_CONDUCTOR,
            alpha: 0.25,
            ..Material::diffuse([1.0, 0.8, 0.3])
        };
        let xml = bsdf(rough).unwrap();
        assert_has(
            &xml,
            &[
                "twosided",
                "roughconductor",
                "value=\"ggx\"",
                "name=\"alpha\" value=\"0.25\"",
                "name=\"material\" value=\"none\"",
                "name=\"specular_reflectance\" value=\"1, 0.8, 0.3\"",
            ],
        );
        let xml = bsdf(Material {
            alpha: 0.0,
            ..rough
        })
        .unwrap();
        assert_has(&xml, &["type=\"conductor\""]);
        assert!(!xml.contains("alpha"), "{xml}");
    }

    /// Fails when a Beckmann material is written as GGX (Mitsuba would render the other
    /// distribution) or a complex-index conductor loses its eta and k.
    #[test]
    fn beckmann_and_complex_index_conductors_are_written_as_such() {
        let (eta, k) = crate::material::conductor::presets::conductor_preset("Au").unwrap();
        let gold = Material::conductor([1.0; 3], 0.2, Distribution::Beckmann, Some((eta, k)));
        let xml = bsdf(gold).unwrap();
        assert_has(
            &xml,
            &[
                "roughconductor",
                "name=\"distribution\" value=\"beckmann\"",
                "name=\"alpha\" value=\"0.2\"",
                &format!("name=\"eta\" value=\"{}, {}, {}\"", eta.x, eta.y, eta.z),
                &format!("name=\"k\" value=\"{}, {}, {}\"", k.x, k.y, k.z),
                "name=\"specular_reflectance\" value=\"1, 1, 1\"",
            ],
        );
        assert!(!xml.contains("\"none\""), "{xml}");
        let smooth = bsdf(Material { alpha: 0.0, ..gold }).unwrap();
        assert_has(&smooth, &["type=\"conductor\"", "name=\"eta\""]);
        for kind in [MATERIAL_PLASTIC, MATERIAL_DIELECTRIC] {
            let m = Material {
                kind,
                alpha: 0.1,
                ..Material::DEFAULT
            }
            .with_distribution(Distribution::Beckmann);
            assert_has(&bsdf(m).unwrap(), &["value=\"beckmann\""]);
        }
    }

    #[test]
    fn thin_dielectrics_are_mitsubas_thindielectric() {
        let xml = bsdf(Material::thin_dielectric(1.33, [0.9, 1.0, 1.0])).unwrap();
        assert!(!xml.contains("twosided"), "{xml}");
        assert_has(
            &xml,
            &[
                "type=\"thindielectric\"",
                "name=\"int_ior\" value=\"1.33\"",
                "name=\"ext_ior\" value=\"1.0\"",
                "name=\"specular_transmittance\" value=\"0.9, 1, 1\"",
            ],
        );
    }

    #[test]
    fn plastic_has_both_iors_and_linear_blending() {
        let m = Material {
            kind: MATERIAL_PLASTIC,
            alpha: 0.1,
            ior: 1.6,
            ks: [0.5; 3],
            map_kd: 0,
            ..Material::diffuse([0.1, 0.2, 0.3])
        };
        let xml = bsdf(m).unwrap();
        assert_has(
            &xml,
            &[
                "twosided",
                "roughplastic",
                "name=\"int_ior\" value=\"1.6\"",
                "name=\"ext_ior\" value=\"1.0\"",
                "<texture type=\"bitmap\" name=\"diffuse_reflectance\">",
                "name=\"raw\" value=\"false\"",
                "name=\"specular_reflectance\" value=\"0.5, 0.5, 0.5\"",
                "name=\"nonlinear\" value=\"false\"",
            ],
        );
        assert_has(
            &bsdf(Material { alpha: 0.0, ..m }).unwrap(),
            &["type=\"plastic\""],
        );
    }

    #[test]
    fn dielectrics_are_one_sided() {
        let m = Material {
            kind: MATERIAL_DIELECTRIC,
            ior: 1.33,
            tf: [0.9, 1.0, 1.0],
            ..Material::default()
        };
        let xml = bsdf(m).unwrap();
        assert!(!xml.contains("twosided"), "{xml}");
        assert_has(
            &xml,
            &[
                "type=\"dielectric\"",
                "name=\"int_ior\" value=\"1.33\"",
                "name=\"specular_transmittance\" value=\"0.9, 1, 1\"",
            ],
        );
        let xml = bsdf(Material { alpha: 0.04, ..m }).unwrap();
        assert_has(&xml, &["roughdielectric", "name=\"alpha\" value=\"0.04\""]);
    }

    #[test]
    fn cutouts_are_masks() {
        let xml = bsdf(Material {
            opacity: 0.5,
            ..Material::default()
        })
        .unwrap();
        assert_has(
            &xml,
            &["type=\"mask\"", "name=\"opacity\" value=\"0.5\"", "diffuse"],
        );
        let xml = bsdf(Material {
            map_d: 0,
            ..Material::default()
        })
        .unwrap();
        assert_has(
            &xml,
            &[
                "type=\"mask\"",
                "name=\"opacity\">",
                "name=\"raw\" value=\"true\"",
            ],
        );
    }

    #[test]
    fn surface_maps_adapt_the_model_inside_twosided_with_raw_bitmaps() {
        let xml = bsdf(Material {
            surface_map: 0,
            ..Material::default()
        })
        .unwrap();
        let (outer, inner) = (
            xml.find("twosided").unwrap(),
            xml.find("normalmap").unwrap(),
        );
        assert!(
            outer < inner && inner < xml.find("diffuse").unwrap(),
            "{xml}"
        );
        assert_has(
            &xml,
            &["name=\"normalmap\">", "name=\"raw\" value=\"true\""],
        );
        let xml = bsdf(Material {
            surface_map: SURFACE_MAP_BUMP,
            bump_scale: 0.25,
            ..Material::default()
        })
        .unwrap();
        assert_has(
            &xml,
            &[
                "type=\"bumpmap\"",
                "name=\"scale\" value=\"0.25\"",
                "name=\"use_shadowing_function\" value=\"true\"",
                "name=\"raw\" value=\"true\"",
            ],
        );
    }

    #[test]
    fn phong_is_an_error_naming_the_material() {
        let error = bsdf(Material {
            kind: MATERIAL_PHONG,
            ks: [0.5; 3],
            ..Material::default()
        })
        .unwrap_err();
        assert_eq!(
            error,
            "material 'm0' is Blinn-Phong, which Mitsuba 3 has no plugin for"
        );
    }

    #[test]
    fn the_scene_has_parameters_with_defaults_and_the_camera() {
        let s = scene(vec![Material::default()]);
        let options = ExportOptions {
            size: [64, 32],
            max_depth: Some(8),
        };
        let xml = scene_xml(&s, &options, "");
        assert_has(
            &xml,
            &[
                "<default name=\"spp\" value=\"4\"/>",
                "<default name=\"max_depth\" value=\"8\"/>",
                "<sampler type=\"$sampler_type\">",
                "<default name=\"rr_depth\" value=\"2147483647\"/>",
                "<integer name=\"rr_depth\" value=\"$rr_depth\"/>",
                "<lookat origin=\"0, 0, 1\" target=\"0, 0, 0\" up=\"0, 1, 0\"/>",
                "name=\"fov\" value=\"40\"",
                "name=\"width\" value=\"64\"",
                "<rfilter type=\"box\"/>",
            ],
        );
    }

    #[test]
    fn mitsubas_far_clip_lies_beyond_the_farthest_vertex() {
        use crate::scene::MeshTriangle;
        let options = ExportOptions {
            size: [8, 8],
            max_depth: None,
        };
        let mut s = scene(vec![Material::default()]);
        // Mitsuba's default (1e4) where the scene is smaller.
        assert_has(
            &scene_xml(&s, &options, ""),
            &["<float name=\"far_clip\" value=\"10000\"/>"],
        );
        // A ground 2e4 from the eye at (0, 0, 1).
        let far = [Vec3::new(0.0, -1.0, -20001.0), Vec3::X, Vec3::Y];
        s.mesh.triangles = vec![MeshTriangle::flat(far, 0)];
        assert_has(
            &scene_xml(&s, &options, ""),
            &["<float name=\"far_clip\" value=\"40004\"/>"],
        );
    }

    #[test]
    fn lens_orthographic_and_filters_become_mitsubas_sensors_and_rfilters() {
        use crate::scene::camera::{FovAxis, Lens, Projection};
        let options = ExportOptions {
            size: [64, 32],
            max_depth: None,
        };
        let mut s = scene(vec![Material::default()]);
        let lens = Projection::Perspective {
            fov_degrees: 30.0,
            fov_axis: FovAxis::Diagonal,
            lens: Some(Lens {
                aperture_radius: 0.25,
                focus_distance: 4.5,
            }),
        };
        s.camera = CameraDesc::with_projection(Vec3::Z, Vec3::ZERO, Vec3::Y, lens).unwrap();
        s.filter = PixelFilter::Gaussian { stddev: 0.75 };
        let xml = scene_xml(&s, &options, "");
        assert_has(
            &xml,
            &[
                "<sensor type=\"thinlens\">",
                "<string name=\"fov_axis\" value=\"diagonal\"/>",
                "name=\"fov\" value=\"30\"",
                "<float name=\"aperture_radius\" value=\"0.25\"/>",
                "<float name=\"focus_distance\" value=\"4.5\"/>",
                "<rfilter type=\"gaussian\">",
                "<float name=\"stddev\" value=\"0.75\"/>",
                "<boolean name=\"sample_border\" value=\"true\"/>",
            ],
        );
        let ortho = Projection::Orthographic { width: 3.0 };
        s.camera = CameraDesc::with_projection(Vec3::Z, Vec3::ZERO, Vec3::Y, ortho).unwrap();
        s.filter = PixelFilter::Tent { radius: 2.0 };
        let xml = scene_xml(&s, &options, "");
        assert_has(
            &xml,
            &[
                "<sensor type=\"orthographic\">",
                "<scale x=\"1.5\" y=\"1.5\"/>\n            <lookat",
                "<rfilter type=\"tent\">",
                "<float name=\"radius\" value=\"2\"/>",
            ],
        );
        assert!(!xml.contains("fov"), "{xml}");
    }

    #[test]
    fn meshes_keep_normals_and_uvs_and_give_the_others_flat_defaults() {
        let mut a = MeshTriangle::flat([Vec3::ZERO, Vec3::X, Vec3::Y], 0);
        let b = a;
        a.normals = Some([Vec3::Z; 3]);
        a.uvs = Some([glam::Vec2::new(0.5, 1.0); 3]);
        let (obj, normals) = mesh_obj(&[&a, &b]);
        assert!(normals);
        assert_eq!(obj.matches("vn 0 0 1").count(), 6, "{obj}");
        assert_eq!(obj.matches("vt 0.5 1").count(), 3, "{obj}");
        assert_eq!(obj.matches("vt 0 0").count(), 3, "{obj}");
        assert!(obj.contains("f 4/4/4 5/5/5 6/6/6"), "{obj}");
        let (obj, normals) = mesh_obj(&[&b]);
        assert!(!normals);
        assert!(obj.ends_with("f 1 2 3\n"), "{obj}");
    }
}
