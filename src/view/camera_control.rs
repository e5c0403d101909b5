//! The fly camera: WASD (and Q/E down/up) move along the view, a mouse drag turns it, scrolling
//! changes the speed. It produces [`CameraDesc`]s; the session restarts on each new one.

use crate::scene::CameraDesc;
use glam::{Quat, Vec2, Vec3};

/// Radians of turn per pixel dragged.
const TURN_PER_PIXEL: f32 = 0.004;
/// Speed factor per scroll line.
const SPEED_PER_LINE: f32 = 1.25;
/// How close to straight up or down the view may turn (cosine), so `up` still orients it.
const MAX_PITCH_COS: f32 = 0.995;

pub struct FlyCamera {
    eye: Vec3,
    forward: Vec3,
    world_up: Vec3,
    /// Kept so the target stays as far from the eye as the scene put it.
    target_distance: f32,
    /// The scene's camera: moves keep its projection and lens.
    camera: CameraDesc,
    /// World units per second.
    speed: f32,
}

/// One frame's camera input.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraInput {
    /// -1, 0 or 1 along forward, right and world up.
    pub forward: f32,
    pub right: f32,
    pub up: f32,
    /// Pixels dragged with the left button.
    pub drag: Vec2,
    /// Lines scrolled (up is positive).
    pub scroll: f32,
}

impl FlyCamera {
    pub fn new(camera: &CameraDesc) -> FlyCamera {
        let target_distance = (camera.target() - camera.eye()).length();
        FlyCamera {
            eye: camera.eye(),
            forward: camera.basis()[0],
            world_up: camera.up().normalize(),
            target_distance,
            camera: *camera,
            // Half the eye-target distance per second: the Cornell box is crossed in seconds.
            speed: 0.5 * target_distance,
        }
    }

    pub fn speed(&self) -> f32 {
        self.speed
    }

    /// Applies `input` over `seconds`; returns the new camera if the view changed.
    pub fn update(&mut self, input: &CameraInput, seconds: f32) -> Option<CameraDesc> {
        if input.scroll != 0.0 {
            self.speed *= SPEED_PER_LINE.powf(input.scroll);
        }
        let mut changed = false;
        if input.drag != Vec2::ZERO {
            let right = self.forward.cross(self.world_up).normalize();
            // Dragging right turns right, dragging down looks down.
            let yaw = Quat::from_axis_angle(self.world_up, -input.drag.x * TURN_PER_PIXEL);
            let pitch = Quat::from_axis_angle(right, -input.drag.y * TURN_PER_PIXEL);
            let turned = (yaw * pitch * self.forward).normalize();
            let forward = if turned.dot(self.world_up).abs() < MAX_PITCH_COS {
                turned
            } else {
                // Too close to vertical: keep the yaw only.
                (yaw * self.forward).normalize()
            };
            changed |= forward != self.forward;
            self.forward = forward;
        }
        let right = self.forward.cross(self.world_up).normalize();
        let step = (self.forward * input.forward + right * input.right + self.world_up * input.up)
            * self.speed
            * seconds;
        if step != Vec3::ZERO && step.is_finite() {
            self.eye += step;
            changed = true;
        }
        if !changed {
            return None;
        }
        self.camera
            .moved(
                self.eye,
                self.eye + self.forward * self.target_distance,
                self.world_up,
            )
            .ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cornell() -> CameraDesc {
        CameraDesc::new(
            Vec3::new(278.0, 273.0, -800.0),
            Vec3::new(278.0, 273.0, 0.0),
            Vec3::Y,
            39.3,
        )
        .unwrap()
    }

    #[test]
    fn no_input_no_new_camera() {
        let mut fly = FlyCamera::new(&cornell());
        assert_eq!(fly.update(&CameraInput::default(), 0.1), None);
    }

    #[test]
    fn forward_moves_along_the_view_at_the_speed() {
        let mut fly = FlyCamera::new(&cornell());
        let input = CameraInput {
            forward: 1.0,
            ..Default::default()
        };
        let moved = fly.update(&input, 1.0).unwrap();
        assert!((moved.eye() - Vec3::new(278.0, 273.0, -400.0)).length() < 1e-3);
        assert!((moved.basis()[0] - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn dragging_right_turns_right_and_scrolling_up_speeds_up() {
        let mut fly = FlyCamera::new(&cornell());
        let before = fly.speed();
        let input = CameraInput {
            drag: Vec2::new(50.0, 0.0),
            scroll: 1.0,
            ..Default::default()
        };
        let turned = fly.update(&input, 0.0).unwrap();
        let [forward, right, _] = cornell().basis();
        assert!(turned.basis()[0].dot(right) > 0.1);
        assert!(turned.basis()[0].dot(forward) > 0.9);
        assert!(fly.speed() > before);
    }

    #[test]
    fn looking_straight_up_is_refused() {
        let mut fly = FlyCamera::new(&cornell());
        let input = CameraInput {
            drag: Vec2::new(0.0, -10_000.0),
            ..Default::default()
        };
        if let Some(c) = fly.update(&input, 0.0) {
            assert!(c.basis()[0].dot(Vec3::Y).abs() < MAX_PITCH_COS);
        }
    }
}
