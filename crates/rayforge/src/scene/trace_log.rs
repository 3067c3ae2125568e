//! `--trace-pixel`: a readable record of every ray one pixel casts, under any lighting model:
//! where each ray starts and goes, what it hits (the object, the point, the normal, the media
//! on either side), what light arrives, and the colour it brings back, indented by depth.
//!
//! Only a tracer with a log started writes anything; every other tracer pays one branch per
//! ray.

use super::tracer::Tracer;
use crate::math::Vec3;
use crate::{Color, Object, Shape};

/// The lines written so far and the current depth.
#[derive(Debug, Default, Clone)]
pub struct TraceLog {
    lines: Vec<String>,
    depth: usize,
}

/// A vector or point, briefly.
pub(super) fn v(p: Vec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}

/// A colour, briefly.
pub(super) fn c(c: Color) -> String {
    format!("[{:.4}, {:.4}, {:.4}]", c.red, c.green, c.blue)
}

/// The name of a shape's kind.
fn kind(shape: &Shape) -> &'static str {
    match shape {
        Shape::Sphere => "sphere",
        Shape::Plane => "plane",
        Shape::Cube => "cube",
        Shape::Cylinder { .. } => "cylinder",
        Shape::Cone { .. } => "cone",
        Shape::Torus { .. } => "torus",
        Shape::Ring { .. } => "ring",
        Shape::Triangle(_) => "triangle",
        Shape::Mesh(_) => "mesh",
        Shape::Csg(_) => "csg",
    }
}

impl<'w> Tracer<'w> {
    /// Starts recording every ray this tracer casts (until [`Tracer::take_log`]).
    pub fn start_log(&mut self) {
        self.log = Some(Box::default());
    }

    /// The lines recorded since [`Tracer::start_log`], and stops recording.
    pub fn take_log(&mut self) -> Vec<String> {
        self.log.take().map(|l| l.lines).unwrap_or_default()
    }

    /// Writes a line, if recording (the text is only built then).
    #[inline]
    pub(super) fn note(&mut self, text: impl FnOnce(&Self) -> String) {
        if self.log.is_some() {
            let text = text(self);
            if let Some(log) = self.log.as_mut() {
                let line = format!("{}{}", "  ".repeat(log.depth), text);
                log.lines.push(line);
            }
        }
    }

    /// Indents the lines that follow (a ray spawned by the current hit).
    #[inline]
    pub(super) fn deeper(&mut self) {
        if let Some(log) = self.log.as_mut() {
            log.depth += 1;
        }
    }

    /// Undoes [`Tracer::deeper`].
    #[inline]
    pub(super) fn shallower(&mut self) {
        if let Some(log) = self.log.as_mut() {
            log.depth = log.depth.saturating_sub(1);
        }
    }

    /// Names an object: its place in the scene's list and its kind (a CSG primitive by the
    /// solid it belongs to).
    pub(super) fn describe(&self, object: &Object) -> String {
        let world = self.world;
        if let Some(i) = world.objects.iter().position(|o| std::ptr::eq(o, object)) {
            return format!("object #{i} ({})", kind(&object.shape));
        }
        for (i, o) in world.objects.iter().enumerate() {
            if let Shape::Csg(csg) = &o.shape {
                if let Some(j) = csg.leaves().iter().position(|l| std::ptr::eq(l, object)) {
                    return format!("object #{i} (csg), primitive {j} ({})", kind(&object.shape));
                }
            }
        }
        format!("a {}", kind(&object.shape))
    }
}
