//! Orbiting the camera with the mouse: the eye turns about the point it looks at, first about
//! the scene's up (yaw), then up or down over it (pitch), stopping short of straight above or
//! below, where "up" would no longer say which way the image's top is.
//!
//! A camera placed otherwise than by `from`, `to` and `up` (Computer Graphics from Scratch's
//! viewport camera, the optics model's zoom camera, a glTF file's own cameras) orbits the
//! point its image's centre sees ([`implied_look_at`]), about its image's up.
//!
//! The camera is moved as a rigid body (its view transform composed with the rotation about
//! the target), not rebuilt from `from`, `to` and `up`, so that everything else about its
//! placement (the book's or the right-handed convention, its roll) is kept as the scene set it.

use glam::DVec3;
use rayforge::camera::Camera;
use rayforge::World;
use rayforge_scene::LookAt;

/// How close to straight above or below the target the eye may come, in radians (one degree).
const POLE_MARGIN: f64 = std::f64::consts::PI / 180.0;

/// The camera placed at `look_at`, after turning its eye `yaw` degrees about the scene's up
/// through the target (counter-clockwise seen from above) and raising it `pitch` degrees
/// toward the up (negative: lowering it). The pitch is cut to keep the eye at least
/// [`POLE_MARGIN`] from the up's axis. `None` when the angles are not finite or the result
/// cannot be inverted.
pub fn orbit(camera: &Camera, look_at: &LookAt, yaw: f64, pitch: f64) -> Option<Camera> {
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
    camera.turned_about(look_at.to, rotation)
}

/// Where a camera placed without `from`, `to` and `up` stands and looks, for [`orbit`]: from
/// its image centre's ray's origin, at the first surface that ray meets (else at the centre of
/// the objects' bounds, taken along the ray; else 5 units ahead), with the image's up, the way
/// from the centre's ray to the top row's. Found from the camera's rays, so it holds for every
/// kind of camera (pinhole, viewport, orthographic) and convention. `None` for an image less
/// than 2 pixels high or rays that do not make a frame.
pub fn implied_look_at(camera: &Camera, world: &World) -> Option<LookAt> {
    let (width, height) = (camera.hsize() as f64, camera.vsize() as f64);
    let centre = camera.ray_through(width / 2.0, height / 2.0);
    let top = camera.ray_through(width / 2.0, 0.0);
    let ahead = centre.direction.try_normalize()?;
    let distance = world
        .intersect(&centre)
        .iter()
        .map(|hit| hit.t * centre.direction.length())
        .find(|&t| t > 1e-9 && t.is_finite())
        .or_else(|| {
            let bounds = world
                .objects
                .iter()
                .map(|o| o.bounds())
                .filter(|b| b.min.is_finite() && b.max.is_finite())
                .reduce(|a, b| a.union(&b))?;
            let along = (bounds.centroid() - centre.origin).dot(ahead);
            (along > 1e-9 && along.is_finite()).then_some(along)
        })
        .unwrap_or(5.0);
    let up = (top.origin + top.direction.normalize()) - (centre.origin + ahead);
    let up = (up - ahead * up.dot(ahead)).try_normalize()?;
    Some(LookAt {
        from: centre.origin,
        to: centre.origin + ahead * distance,
        up,
    })
}

/// The angle between two vectors, in radians (0 to π), exact near both ends.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::math::{view_transform, Transform};

    /// The view transform of the camera at `view` orbited so.
    fn orbit_view(view: &Transform, look_at: &LookAt, yaw: f64, pitch: f64) -> Option<Transform> {
        let camera = rayforge::camera::Camera::new(2, 2, 1.0).with_transform_of(*view);
        orbit(&camera, look_at, yaw, pitch).map(|c| *c.transform())
    }

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
        let same = orbit_view(&view, &look_at, 0.0, 0.0).expect("orbits");
        assert!(same.matrix().abs_diff_eq(view.matrix(), 1e-12));
    }

    #[test]
    fn a_quarter_turn_of_yaw_moves_the_eye_about_the_up() {
        let (view, look_at) = scene_view();
        let turned = orbit_view(&view, &look_at, 90.0, 0.0).expect("orbits");
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
        let raised = orbit_view(&view, &look_at, 0.0, 30.0).expect("orbits");
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
            let e = eye(&orbit_view(&view, &look_at, 0.0, pitch).expect("orbits"));
            let from_up = angle_between(e, look_at.up);
            assert!((from_up - POLE_MARGIN).abs() < 1e-9, "{pitch}: {from_up}");
            let e = eye(&orbit_view(&view, &look_at, 10.0, -pitch).expect("orbits"));
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
        assert!(orbit_view(&view, &look_at, f64::NAN, 0.0).is_none());
        assert!(orbit_view(&view, &look_at, 0.0, f64::INFINITY).is_none());
    }

    /// Computer Graphics from Scratch's viewport camera: at the origin looking along +z, 400
    /// pixels square. (Its rays go through the book's points, half a pixel off the pixels'
    /// centres: what the image's centre sees is within a pixel's width of the axis, which the
    /// tolerances below allow.)
    fn viewport_camera() -> Camera {
        Camera::viewport(400, 400, rayforge::camera::Viewport::BOOK).expect("a camera")
    }

    /// A pixel's width at 5 units from the viewport camera.
    const PIXEL: f64 = 5.0 / 400.0;

    #[test]
    fn a_camera_placed_otherwise_looks_at_what_its_centre_sees() {
        let camera = viewport_camera();
        let mut world = rayforge::World::new();
        let mut sphere = rayforge::Object::sphere();
        sphere.set_transform(rayforge::math::translation(0.0, 0.0, 5.0));
        world.objects.push(sphere);
        let at = implied_look_at(&camera, &world).expect("a frame");
        assert!(at.from.abs_diff_eq(DVec3::ZERO, 1e-12), "{:?}", at.from);
        assert!(
            at.to.abs_diff_eq(DVec3::new(0.0, 0.0, 4.0), PIXEL),
            "{:?}",
            at.to
        );
        assert!(at.up.abs_diff_eq(DVec3::Y, 3e-3), "{:?}", at.up);
        // Nothing in front of it: the middle of the bounded objects, along the ray.
        let mut behind = rayforge::World::new();
        let mut sphere = rayforge::Object::sphere();
        sphere.set_transform(rayforge::math::translation(3.0, 0.0, 7.0));
        behind.objects.push(sphere);
        let at = implied_look_at(&camera, &behind).expect("a frame");
        assert!(
            at.to.abs_diff_eq(DVec3::new(0.0, 0.0, 7.0), 2.0 * PIXEL),
            "{:?}",
            at.to
        );
        // An empty world: 5 units ahead.
        let at = implied_look_at(&camera, &rayforge::World::new()).expect("a frame");
        assert!(
            at.to.abs_diff_eq(DVec3::new(0.0, 0.0, 5.0), PIXEL),
            "{:?}",
            at.to
        );
    }

    #[test]
    fn a_camera_placed_otherwise_orbits_about_its_implied_target() {
        let camera = viewport_camera();
        let at = implied_look_at(&camera, &rayforge::World::new()).expect("a frame");
        let turned = orbit(&camera, &at, 90.0, 0.0).expect("orbits");
        // A quarter turn about +y through (0, 0, 5): the eye from the origin to (-5, 0, 5),
        // looking along +x at the target.
        let centre = turned.ray_through(200.0, 200.0);
        assert!(
            centre.origin.abs_diff_eq(DVec3::new(-5.0, 0.0, 5.0), PIXEL),
            "{centre:?}"
        );
        assert!(
            centre.direction.normalize().abs_diff_eq(DVec3::X, 3e-3),
            "{centre:?}"
        );
        let top = turned.ray_through(200.0, 0.0).direction;
        assert!(top.y > 0.0, "the image's top still up: {top:?}");
    }
}
