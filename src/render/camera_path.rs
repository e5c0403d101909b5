//! Scripted camera paths for headless runs (`passgraph --camera-path PATH.ron`): segments of
//! frames, each at one camera, each optionally measured frame by frame against a reference of
//! its view. What reprojection is judged by (graphs/pathtracer-reproject.ron).
//!
//! ```ron
//! CameraPath([
//!     (frames: 64),                                            // the scene's camera
//!     (frames: 8, eye: (298, 273, -790), reference: "b.exr"),  // moved; target, up, fov kept
//! ])
//! ```

use crate::scene::{CameraDesc, CameraError, FovAxis, Projection};
use glam::Vec3;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
#[serde(rename = "CameraPath")]
struct CameraPathFile(Vec<SegmentDecl>);

#[derive(Deserialize)]
#[serde(rename = "Segment", deny_unknown_fields)]
struct SegmentDecl {
    frames: u32,
    #[serde(default)]
    eye: Option<[f32; 3]>,
    #[serde(default)]
    target: Option<[f32; 3]>,
    #[serde(default)]
    up: Option<[f32; 3]>,
    #[serde(default)]
    fov_y: Option<f32>,
    /// Relative to the path file.
    #[serde(default)]
    reference: Option<PathBuf>,
}

/// Frames rendered at one camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub frames: u32,
    pub camera: CameraDesc,
    pub reference: Option<PathBuf>,
}

/// `camera` with a vertical field of view of `fov_y` degrees (its lens kept).
fn with_fov_y(camera: &CameraDesc, fov_y: f32) -> Result<CameraDesc, CameraError> {
    match camera.projection() {
        Projection::Perspective { lens, .. } => {
            if !(fov_y > 0.0 && fov_y < 180.0) {
                return Err(CameraError::FieldOfView(fov_y));
            }
            let projection = Projection::Perspective {
                fov_degrees: fov_y,
                fov_axis: FovAxis::Y,
                lens,
            };
            CameraDesc::with_projection(camera.eye(), camera.target(), camera.up(), projection)
        }
        Projection::Orthographic { .. } => Err(CameraError::FovOfOrthographic),
    }
}

/// Reads a camera path; each segment's camera is the previous one's (the scene's for the
/// first) with the fields it names replaced. Errors name the file and, for syntax, the line.
pub fn load_camera_path(path: &Path, start: CameraDesc) -> Result<Vec<Segment>, String> {
    let text = crate::text_file::read_utf8(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    // Fields are optional: `eye: (1, 2, 3)`, not `eye: Some((1, 2, 3))`.
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: CameraPathFile = options.from_str(&text).map_err(|e| {
        format!(
            "{}:{}:{}: {}",
            path.display(),
            e.span.start.line,
            e.span.start.col,
            e.code
        )
    })?;
    if file.0.is_empty() {
        return Err(format!(
            "{}: the camera path has no segment",
            path.display()
        ));
    }
    let base = path.parent().unwrap_or(Path::new("."));
    let mut camera = start;
    let mut segments = Vec::with_capacity(file.0.len());
    for (i, s) in file.0.into_iter().enumerate() {
        let v = |x: Option<[f32; 3]>, old: Vec3| x.map_or(old, Vec3::from);
        // A segment keeps the camera's projection and lens; fov_y makes it a vertical field of
        // view (an orthographic camera has none to change).
        let moved = match s.fov_y {
            None => camera.moved(
                v(s.eye, camera.eye()),
                v(s.target, camera.target()),
                v(s.up, camera.up()),
            ),
            Some(fov_y) => with_fov_y(&camera, fov_y).and_then(|c| {
                c.moved(
                    v(s.eye, camera.eye()),
                    v(s.target, camera.target()),
                    v(s.up, camera.up()),
                )
            }),
        };
        camera = moved.map_err(|e| format!("{}: segment {}: {e}", path.display(), i + 1))?;
        if s.frames == 0 {
            return Err(format!(
                "{}: segment {}: frames must be at least 1",
                path.display(),
                i + 1
            ));
        }
        segments.push(Segment {
            frames: s.frames,
            camera,
            reference: s.reference.map(|r| base.join(r)),
        });
    }
    Ok(segments)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> CameraDesc {
        CameraDesc::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 40.0).unwrap()
    }

    fn write(text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("path.ron");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn segments_inherit_the_previous_camera_and_resolve_references() {
        let (dir, path) = write(
            "CameraPath([(frames: 4), (frames: 2, eye: (1, 0, -5), reference: \"b.exr\"), (frames: 1, fov_y: 20)])",
        );
        let s = load_camera_path(&path, start()).unwrap();
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].camera, start());
        assert_eq!(s[1].camera.eye(), Vec3::new(1.0, 0.0, -5.0));
        assert_eq!(s[1].camera.target(), Vec3::ZERO);
        assert_eq!(s[1].reference, Some(dir.path().join("b.exr")));
        assert_eq!(s[2].camera.eye(), Vec3::new(1.0, 0.0, -5.0));
        assert_eq!(s[2].camera.fov_y_degrees_for(1, 1), Some(20.0));
    }

    #[test]
    fn errors_name_the_file_line_and_segment() {
        let (_dir, path) = write(
            "CameraPath([\n(frames: 4),\n(frames: 2, eye: (0, 0, 0), target: (0, 0, 0)),\n])",
        );
        let e = load_camera_path(&path, start()).unwrap_err();
        assert!(
            e.contains("path.ron: segment 2") && e.contains("same point"),
            "{e}"
        );
        let (_dir, path) = write("CameraPath([\n(frames: 4, speed: 2),\n])");
        let e = load_camera_path(&path, start()).unwrap_err();
        assert!(e.contains("path.ron:2:") && e.contains("speed"), "{e}");
        let (_dir, path) = write("CameraPath([(frames: 0)])");
        let e = load_camera_path(&path, start()).unwrap_err();
        assert!(e.contains("at least 1"), "{e}");
    }
}
