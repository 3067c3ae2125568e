//! Motion blur from pbrt-v4's files: its times mapped onto rayforge's, and its moving shapes,
//! instances and camera placed.
//!
//! pbrt-v4 keeps two transforms, holding at `TransformTimes`' `start` and `end` (0 and 1 by
//! default), and casts each camera ray at an instant `t` of the camera's shutter,
//! `shutteropen` to `shutterclose` (0 and 1); a moving transform at `t` is its interpolation
//! at `(t − start) / (end − start)`, held at the nearer end outside `[start, end]`
//! (`AnimatedTransform::Interpolate`). rayforge's moving transforms run from time 0 to 1 and
//! clamp the same way, and its camera's shutter is in that time: a shutter of
//! `(open − start) / (end − start)` to `(close − start) / (end − start)` casts each ray at
//! exactly pbrt-v4's instant. A shutter `[0.25, 0.5]` over the times `[0, 1]` sees the motion
//! between those instants.
//!
//! What moves is what pbrt-v4 moves: shapes (an `AnimatedPrimitive` over the shape built in
//! its own space, so that only the moving transform is interpolated, not the shape's own
//! placement with it), object instances (the whole instance, its shapes swinging about its
//! origin) and the camera (its world-from-camera transform). pbrt-v4 interpolates an
//! instance's motion in its render space, the world moved so that the camera's eye (at the
//! middle of the camera's times) is the origin (its default `cameraworld`): the instance's
//! translation runs straight there, not in the world, which matters where it turns, and
//! rayforge interpolates it there too. A moving shape with an area
//! light, which pbrt-v4 refuses, is rendered moving, its light sampled where it is at each
//! ray's instant; lights, media and textures under a moving transform stand at its start,
//! with the reader's warning, as in pbrt-v4.

use super::reader::{Description, TransformTimes};
use crate::error::SceneError;
use glam::{DMat3, DMat4, DVec3};
use rayforge::math::{Motion, SingularTransform};
use rayforge::{Camera, Object, Transform};

/// Whether anything in `desc` moves: a shape (in the world or an object's definition), an
/// instance or the camera.
fn anything_moves(desc: &Description) -> bool {
    desc.options.camera_end.is_some()
        || desc
            .shapes
            .iter()
            .chain(desc.objects.values().flat_map(|(s, _)| s))
            .any(|s| s.world_from_object_end.is_some())
        || desc
            .instances
            .iter()
            .any(|i| i.world_from_instance_end.is_some())
}

/// The times' span, `end − start`, where it is one rayforge can interpolate over.
fn span(times: &TransformTimes) -> Option<f64> {
    let span = times.end - times.start;
    (span > 0.0 && span.is_finite() && times.start.is_finite()).then_some(span)
}

/// `camera` (placed where the scene's camera is at `TransformTimes`' start) moving as `desc`'s
/// camera does, its shutter mapped onto rayforge's time (see the [module](self)).
///
/// An error, where anything moves, for times whose end is not after their start (pbrt-v4
/// would jump from one transform to the other at `start` rather than move), and for a moving
/// camera whose `TransformTimes` differ from the world's (a `TransformTimes` after `Camera`):
/// rayforge's moving transforms share one clock.
pub fn camera(camera: Camera, desc: &Description) -> Result<Camera, SceneError> {
    let options = &desc.options;
    let times = &options.transform_times;
    let Some(span) = span(times) else {
        if !anything_moves(desc) {
            return Ok(camera);
        }
        let message = format!(
            "`TransformTimes {} {}`: things move between the two times, and the end comes \
             after the start for that (pbrt-v4 would jump from the start transform to the \
             end one rather than move)",
            times.start, times.end
        );
        return Err(match &times.loc {
            Some(loc) => loc.error(Some("TransformTimes"), message),
            None => SceneError::new(std::path::Path::new(""), message),
        });
    };
    let Some((entity, _)) = &options.camera else {
        return Ok(camera.with_shutter(-times.start / span, (1.0 - times.start) / span));
    };
    let params = &entity.params;
    let open = params.float_or("shutteropen", 0.0)?;
    let close = params.float_or("shutterclose", 1.0)?;
    let mut camera = camera.with_shutter((open - times.start) / span, (close - times.start) / span);
    if let Some(end) = options.camera_end {
        if options.camera_times.start != times.start || options.camera_times.end != times.end {
            return Err(entity.error(format!(
                "the camera moves between the times {} and {} in force here, and the world's \
                 `TransformTimes` are {} and {}: rayforge moves everything on one clock (give \
                 `TransformTimes` before `Camera`)",
                options.camera_times.start, options.camera_times.end, times.start, times.end
            )));
        }
        let view = Transform::try_new(super::camera::PBRT_TO_BOOK_CAMERA * end)
            .map_err(|_| entity.error("the camera's transform at the end time is singular"))?;
        camera = camera.with_motion(view).ok_or_else(|| {
            entity.error("this camera cannot move (rayforge moves its other cameras)")
        })?;
    }
    Ok(camera)
}

/// `object`, built in its shape's space (its transform the shape's own placement there),
/// placed by `start` and, where the shape moves, moving to `end`: only the motion from
/// `start` to `end` is interpolated, its own placement carried along.
pub fn place(
    object: Object,
    start: &Transform,
    end: Option<&Transform>,
) -> Result<Object, SingularTransform> {
    let Some(end) = end else {
        return object.placed_by(start);
    };
    let motion = Motion::after(start, end, &object.transform)?;
    Ok(Object {
        transform: *motion.start(),
        motion: Some(Box::new(motion)),
        ..object
    })
}

/// The origin of pbrt-v4's render space (`cameraworld`) in the world: the camera's eye at the
/// middle of its times, its world-from-camera transform interpolated there (pbrt-v4's
/// `CameraTransform`).
pub fn render_origin(desc: &Description) -> DVec3 {
    let Some((_, camera_from_world)) = &desc.options.camera else {
        return DVec3::ZERO;
    };
    let world_from = |m: &DMat4| Transform::try_new(m.inverse()).ok();
    let start = world_from(camera_from_world);
    let end = desc.options.camera_end.as_ref().and_then(world_from);
    match (start, end) {
        (Some(start), Some(end)) => Motion::new(start, end).at(0.5).point(DVec3::ZERO),
        (Some(start), None) => start.point(DVec3::ZERO),
        _ => DVec3::ZERO,
    }
}

/// `object` of a named object's definition placed by an `ObjectInstance` whose transform is
/// `start`, moving to `end` where it moves, interpolated in pbrt-v4's render space, whose
/// origin is the world's point `origin` ([`render_origin`]). Returns the placed object, and whether it is only
/// approximately pbrt-v4's: a moving shape in an instance moving otherwise than by a
/// translation, whose two motions pbrt-v4 interpolates one by one and rayforge as their
/// product (the two agree where the instance only translates).
pub fn instance(
    object: &Object,
    start: &Transform,
    end: Option<&Transform>,
    origin: DVec3,
) -> Result<(Object, bool), SingularTransform> {
    match (&object.motion, end) {
        (Some(own), None) => {
            let motion = own.placed_by(start)?;
            let placed = Object {
                transform: *motion.start(),
                motion: Some(Box::new(motion)),
                ..object.clone()
            };
            Ok((placed, false))
        }
        (None, None) => Ok((object.placed_by(start)?, false)),
        (None, Some(end)) => {
            // world(t) = to_world · moving(t) · to_render · own, `moving` between the ends
            // seen in render space.
            let to_render = Transform::try_new(DMat4::from_translation(-origin))?;
            let to_world = Transform::try_new(DMat4::from_translation(origin))?;
            let seen = |t: &Transform| to_render.then_after(&t.then_after(&to_world)?);
            let inner = to_render.then_after(&object.transform)?;
            let motion = Motion::after(&seen(start)?, &seen(end)?, &inner)?.placed_by(&to_world)?;
            let placed = Object {
                transform: *motion.start(),
                motion: Some(Box::new(motion)),
                ..object.clone()
            };
            Ok((placed, false))
        }
        (Some(_), Some(end)) => {
            let turns = DMat3::from_mat4(start.matrix()) != DMat3::from_mat4(end.matrix());
            Ok((object.placed_by_moving(start, end)?, turns))
        }
    }
}
