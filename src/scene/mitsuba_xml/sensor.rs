//! The sensor (`perspective`, `thinlens`, `orthographic`) with its film (`hdrfilm`), pixel
//! filter (`rfilter`) and sampler, as passgraph's camera, image size, [`PixelFilter`] and
//! frame count.

use super::parse::{At, Plugin};
use crate::scene::camera::{CameraDesc, FovAxis, Lens, Projection};
use crate::scene::error::SceneError;
use crate::scene::filter::PixelFilter;
use glam::{DMat4, DVec3, Vec3};

/// What the scene's sensor says.
#[derive(Clone, Debug)]
pub struct Sensor {
    pub camera: CameraDesc,
    pub size: [u32; 2],
    pub filter: PixelFilter,
    pub sample_count: u32,
    /// Mitsuba's sensors stop camera rays here; passgraph's do not, so the builder checks
    /// that no geometry lies beyond it.
    pub far_clip: Option<(f64, At)>,
    /// A wider filter than the box without `sample_border`: Mitsuba renormalises it at the
    /// image's edge where passgraph samples beyond it (the builder warns).
    pub border_note: Option<String>,
}

/// Mitsuba's samplers: they change the noise, not the expectation, so passgraph renders
/// their sample count with its own sampler.
const SAMPLERS: &[&str] = &[
    "independent",
    "stratified",
    "multijitter",
    "orthogonal",
    "ldsampler",
];

/// `fov` along `fov_axis`, or else Mitsuba's `focal_length` (default "50mm"): a 35 mm film
/// equivalent, its diagonal (sqrt(36^2 + 24^2) mm) seen at that focal length, which Mitsuba
/// maps onto the image's own diagonal.
fn field_of_view(plugin: &Plugin) -> Result<(f64, FovAxis), SceneError> {
    match (plugin.float("fov")?, plugin.string("focal_length")?) {
        (Some(_), Some((_, at))) => Err(plugin.error_at(&at, "give fov or focal_length, not both")),
        (Some(fov), None) => Ok((fov, fov_axis(plugin)?)),
        (None, focal) => {
            let (text, at) = focal.unwrap_or(("50mm".to_string(), plugin.at.clone()));
            let f = text
                .trim()
                .strip_suffix("mm")
                .unwrap_or(text.trim())
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|f| f.is_finite() && *f > 0.0)
                .ok_or_else(|| {
                    plugin.error_at(
                        &at,
                        format!("focal_length '{text}' is not a positive length in mm (e.g. 50mm)"),
                    )
                })?;
            let diagonal = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
            Ok((
                (2.0 * (diagonal / (2.0 * f)).atan()).to_degrees(),
                FovAxis::Diagonal,
            ))
        }
    }
}

fn fov_axis(plugin: &Plugin) -> Result<FovAxis, SceneError> {
    Ok(match plugin.string("fov_axis")? {
        None => FovAxis::X,
        Some((s, at)) => match s.as_str() {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "diagonal" => FovAxis::Diagonal,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            other => {
                return Err(plugin.error_at(
                    &at,
                    format!("fov_axis '{other}' is not one of x, y, diagonal, smaller, larger"),
                ));
            }
        },
    })
}

/// The sensor's frame from its to_world: eye, view direction, up, and the scale of its x and y
/// axes. Errors for frames passgraph's cameras cannot take (sheared, mirrored, non-uniform).
fn frame(
    plugin: &Plugin,
    m: &DMat4,
    at: &At,
    perspective: bool,
) -> Result<(DVec3, DVec3, DVec3, f64), SceneError> {
    let (x, y, z) = (
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    );
    let eye = m.w_axis.truncate();
    let (sx, sy, sz) = (x.length(), y.length(), z.length());
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
    let orthogonal = x.dot(y).abs() <= 1e-6 * sx * sy
        && x.dot(z).abs() <= 1e-6 * sx * sz
        && y.dot(z).abs() <= 1e-6 * sy * sz;
    if !(orthogonal && close(sx, sy) && sx > 0.0 && sz > 0.0) || (perspective && !close(sx, sz)) {
        return Err(plugin.error_at(
            at,
            format!(
                "to_world must be a rotation and translation{} (a lookat, optionally scaled uniformly); axes scaled {sx:.6}, {sy:.6}, {sz:.6}",
                if perspective { "" } else { " with x and y scaled alike" }
            ),
        ));
    }
    if x.dot(y.cross(z)) < 0.0 {
        // Mitsuba's camera frame has x = up x dir (the image's left): the other handedness
        // would mirror the image.
        return Err(plugin.error_at(
            at,
            "to_world mirrors the image (its x axis is not up x direction, as a lookat's is)",
        ));
    }
    Ok((eye, z / sz, y / sy, sx))
}

pub fn sensor(plugin: &Plugin) -> Result<Sensor, SceneError> {
    let kind = plugin.kind.as_str();
    let (m, at) = plugin
        .transform("to_world")?
        .unwrap_or((DMat4::IDENTITY, plugin.at.clone()));
    let projection;
    let (eye, dir, up, scale);
    match kind {
        "perspective" | "thinlens" => {
            (eye, dir, up, scale) = frame(plugin, &m, &at, true)?;
            let (fov, axis) = field_of_view(plugin)?;
            let lens = if kind == "thinlens" {
                let r = plugin
                    .float("aperture_radius")?
                    .ok_or_else(|| plugin.error("thinlens needs aperture_radius"))?;
                let d = plugin
                    .float("focus_distance")?
                    .ok_or_else(|| plugin.error("thinlens needs focus_distance"))?;
                // Mitsuba takes both in the sensor's local space, which to_world scales.
                Some(Lens {
                    aperture_radius: (r * scale) as f32,
                    focus_distance: (d * scale) as f32,
                })
            } else {
                None
            };
            projection = Projection::Perspective {
                fov_degrees: fov as f32,
                fov_axis: axis,
                lens,
            };
        }
        "orthographic" => {
            (eye, dir, up, scale) = frame(plugin, &m, &at, false)?;
            // Mitsuba's orthographic view spans x in [-1, 1] before to_world.
            projection = Projection::Orthographic {
                width: (2.0 * scale) as f32,
            };
        }
        other => {
            return Err(plugin.error(format!(
                "sensor type '{other}' is not supported (supported: perspective, thinlens, orthographic)"
            )));
        }
    }
    let far_clip = plugin.float("far_clip")?.map(|f| {
        (
            f,
            plugin
                .property("far_clip")
                .map_or(plugin.at.clone(), |p| p.at.clone()),
        )
    });
    if let Some(p) = plugin.property("near_clip") {
        let near = plugin.float("near_clip")?.unwrap_or(0.0);
        // Mitsuba hides what is nearer than near_clip; passgraph starts rays at the eye. The
        // default (0.01) and smaller are accepted: no scene of the subset puts geometry there.
        if near > 0.01 {
            return Err(plugin.error_at(&p.at, format!("near_clip {near} is not supported (passgraph's camera rays start at the eye; at most Mitsuba's default 0.01)")));
        }
    }
    let f = |v: DVec3| Vec3::new(v.x as f32, v.y as f32, v.z as f32);
    // A lookat's own points where the file has them (the same frame, without the rounding
    // of target = eye + direction).
    let (eye, target, up) = match plugin.lookat("to_world") {
        Some([origin, target, up]) => (f(origin), f(target), f(up)),
        None => (f(eye), f(eye + dir), f(up)),
    };
    let camera = CameraDesc::with_projection(eye, target, up, projection).map_err(|e| {
        SceneError::Camera {
            at: plugin.at.location(),
            source: e,
        }
    })?;

    let film = plugin.child_of("film")?;
    let (size, filter, border_note) = match film {
        None => ([768, 576], PixelFilter::Gaussian { stddev: 0.5 }, None),
        Some(c) => film_of(&c.plugin)?,
    };
    let sample_count = match plugin.child_of("sampler")? {
        None => 4,
        Some(c) => sampler(&c.plugin)?,
    };
    plugin.finish()?;
    Ok(Sensor {
        camera,
        size,
        filter,
        sample_count,
        far_clip,
        border_note,
    })
}

fn positive_u32(plugin: &Plugin, name: &str, default: u32) -> Result<u32, SceneError> {
    match plugin.integer(name)? {
        None => Ok(default),
        Some(v) => u32::try_from(v)
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| plugin.error(format!("{name} {v} must be a positive integer"))),
    }
}

fn film_of(film: &Plugin) -> Result<([u32; 2], PixelFilter, Option<String>), SceneError> {
    if film.kind != "hdrfilm" {
        return Err(film.error(format!(
            "film type '{}' is not supported (supported: hdrfilm)",
            film.kind
        )));
    }
    let size = [
        positive_u32(film, "width", 768)?,
        positive_u32(film, "height", 576)?,
    ];
    // The output's channels and precision are passgraph's own (--out); the image is the same.
    for name in ["pixel_format", "component_format"] {
        if let Some((v, at)) = film.string(name)? {
            let ok = match name {
                "pixel_format" => matches!(v.as_str(), "rgb" | "rgba"),
                _ => matches!(v.as_str(), "float16" | "float32"),
            };
            if !ok {
                return Err(film.error_at(
                    &at,
                    format!(
                        "{name} '{v}' is not supported (supported: rgb, rgba; float16, float32)"
                    ),
                ));
            }
        }
    }
    let sample_border = film.boolean_or("sample_border", false)?;
    let filter = match film.child_of("rfilter")? {
        None => PixelFilter::Gaussian { stddev: 0.5 },
        Some(c) => {
            let r = &c.plugin;
            let filter = match r.kind.as_str() {
                "box" => PixelFilter::Box,
                "gaussian" => PixelFilter::Gaussian {
                    stddev: r.float_or("stddev", 0.5)? as f32,
                },
                "tent" => PixelFilter::Tent {
                    radius: r.float_or("radius", 1.0)? as f32,
                },
                other => {
                    return Err(r.error(format!(
                        "rfilter type '{other}' is not supported (supported: box, gaussian, tent)"
                    )));
                }
            };
            r.finish()?;
            filter.check().map_err(|m| r.error(m))?
        }
    };
    let note = (filter != PixelFilter::Box && !sample_border).then(|| {
        format!(
            "{}: the {} filter without sample_border: Mitsuba renormalises the filter where the image edge cuts it, passgraph samples beyond the edge (as with sample_border true); pixels within {} of the edge differ",
            film.at.location(),
            r_kind(filter),
            filter.radius()
        )
    });
    film.finish()?;
    Ok((size, filter, note))
}

fn r_kind(f: PixelFilter) -> &'static str {
    match f {
        PixelFilter::Box => "box",
        PixelFilter::Gaussian { .. } => "gaussian",
        PixelFilter::Tent { .. } => "tent",
    }
}

fn sampler(s: &Plugin) -> Result<u32, SceneError> {
    if !SAMPLERS.contains(&s.kind.as_str()) {
        return Err(s.error(format!(
            "sampler type '{}' is not supported (supported: {})",
            s.kind,
            SAMPLERS.join(", ")
        )));
    }
    let count = positive_u32(s, "sample_count", 4)?;
    // Seeds and the samplers' own settings change the noise, not the expectation: passgraph
    // draws its own samples (its --seed).
    for name in ["seed", "jitter", "strength", "dimension"] {
        s.accept(name);
    }
    s.finish()?;
    Ok(count)
}
