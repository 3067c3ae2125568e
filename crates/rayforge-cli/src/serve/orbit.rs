//! Orbiting the camera with the mouse: the eye turns about the point it looks at, first about
//! the scene's up (yaw), then up or down over it (pitch), stopping short of straight above or
//! below, where "up" would no longer say which way the image's top is.
//!
//! The camera is moved as a rigid body (its view transform composed with the rotation about
//! the target), not rebuilt from `from`, `to` and `up`, so that everything else about its
//! placement (the book's or the right-handed convention, its roll) is kept as the scene set it.

use glam::{DMat4, DVec3};
use rayforge::math::Transform;
use rayforge_scene::LookAt;

/// How close to straight above or below the target the eye may come, in radians (one degree).
const POLE_MARGIN: f64 = std::f64::consts::PI / 180.0;

/// The view transform (`camera_from_world`) of the camera placed by `view` at `look_at`, after
/// turning its eye `yaw` degrees about the scene's up through the target (counter-clockwise
/// seen from above) and raising it `pitch` degrees toward the up (negative: lowering it). The
/// pitch is cut to keep the eye at least [`POLE_MARGIN`] from the up's axis. `None` when the
/// angles are not finite or the result cannot be inverted.
pub fn orbit(view: &Transform, look_at: &LookAt, yaw: f64, pitch: f64) -> Option<Transform> {
    if !(yaw.is_finite() && pitch.is_finite()) {
        return None;
    }
    let up = look_at.up.try_normalize()?;
    let offset = look_at.from - look_at.to;
    let turn = glam::DQuat::from_axis_angle(up, yaw.to_radians());
    let turned = turn * offset;
    // Rotating the eye about `up × eye` by a positive angle takes it away from the up, so its
    // angle to the up grows by the rotation's angle: the pitch is that angle's opposite.
    let rotation = match up.cross(turned).try_normalize() {
        Some(axis) => {
            let elevation = angle_between(turned, up);
            let lowest = POLE_MARGIN - elevation;
            let highest = std::f64::consts::PI - POLE_MARGIN - elevation;
            let angle = (-pitch.to_radians()).max(lowest).min(highest);
            glam::DQuat::from_axis_angle(axis, angle) * turn
        }
        // The eye is on the up's axis (only within rounding of the scene's check): yaw only.
        None => turn,
    };
    let target = look_at.to;
    // The world moves by the inverse of the eye's rotation about the target.
    let about_target = DMat4::from_translation(target)
        * DMat4::from_quat(rotation.inverse())
        * DMat4::from_translation(-target);
    Transform::try_new(view.matrix() * about_target).ok()
}

/// The angle between two vectors, in radians (0 to π), exact near both ends.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::math::view_transform;

    fn scene_view() -> (Transform, LookAt) {
        let look_at = LookAt {
            from: DVec3::new(0.0, 0.0, -5.0),
            to: DVec3::ZERO,
            up: DVec3::new(0.0, 1.0, 0.0),
        };
        let view = Transform::new(view_transform(look_at.from, look_at.to, look_at.up));
        (view, look_at)
    }

    /// Where the camera is, in the world.
    fn eye(view: &Transform) -> DVec3 {
        view.inverse_point(DVec3::ZERO)
    }

    #[test]
    fn no_turn_keeps_the_view() {
        let (view, look_at) = scene_view();
        let same = orbit(&view, &look_at, 0.0, 0.0).expect("orbits");
        assert!(same.matrix().abs_diff_eq(view.matrix(), 1e-12));
    }

    #[test]
    fn a_quarter_turn_of_yaw_moves_the_eye_about_the_up() {
        let (view, look_at) = scene_view();
        let turned = orbit(&view, &look_at, 90.0, 0.0).expect("orbits");
        assert!(eye(&turned).abs_diff_eq(DVec3::new(-5.0, 0.0, 0.0), 1e-9));
        // It still looks at the target, down its own -z axis, from the same distance.
        assert!(turned
            .point(look_at.to)
            .abs_diff_eq(DVec3::new(0.0, 0.0, -5.0), 1e-9));
        // And equals the camera the scene would place there.
        let placed = view_transform(DVec3::new(-5.0, 0.0, 0.0), look_at.to, look_at.up);
        assert!(turned.matrix().abs_diff_eq(placed, 1e-9));
    }

    #[test]
    fn pitch_raises_the_eye_toward_the_up() {
        let (view, look_at) = scene_view();
        let raised = orbit(&view, &look_at, 0.0, 30.0).expect("orbits");
        let e = eye(&raised);
        assert!((e.length() - 5.0).abs() < 1e-9);
        assert!((e.y - 5.0 * 30f64.to_radians().sin()).abs() < 1e-9, "{e}");
        assert!(raised
            .point(look_at.to)
            .abs_diff_eq(DVec3::new(0.0, 0.0, -5.0), 1e-9));
    }

    #[test]
    fn pitch_stops_short_of_the_poles() {
        let (view, look_at) = scene_view();
        for pitch in [89.5, 90.0, 400.0, 1e9] {
            let e = eye(&orbit(&view, &look_at, 0.0, pitch).expect("orbits"));
            let from_up = angle_between(e, look_at.up);
            assert!((from_up - POLE_MARGIN).abs() < 1e-9, "{pitch}: {from_up}");
            let e = eye(&orbit(&view, &look_at, 10.0, -pitch).expect("orbits"));
            let from_down = angle_between(e, -look_at.up);
            assert!(
                (from_down - POLE_MARGIN).abs() < 1e-9,
                "{pitch}: {from_down}"
            );
        }
    }

    #[test]
    fn angles_that_are_not_numbers_are_refused() {
        let (view, look_at) = scene_view();
        assert!(orbit(&view, &look_at, f64::NAN, 0.0).is_none());
        assert!(orbit(&view, &look_at, 0.0, f64::INFINITY).is_none());
    }
}
