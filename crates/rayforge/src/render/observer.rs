//! Watching a ray being traced: the events an integrator reports as it works (a ray cast, a
//! hit or a miss, the light arriving at a point, a secondary ray spawned or left out, the
//! colour returned), and two observers of them.
//!
//! Normal renders pass [`NoTrace`], whose every method is empty, so the calls compile away and
//! the integrators carry no logging branches. `--trace-pixel` ([`super::trace_pixel`]) passes a
//! [`TraceLog`], which writes each event as a readable line, indented by depth.

use crate::color::Color;
use crate::math::{Point3, Vec3};
use crate::scene::{Computations, Object, Shape, World};
use std::fmt;

/// What an integrator says about the ray it is tracing. Every method does nothing by default.
pub trait TraceObserver {
    /// A ray is cast from `origin` along `direction` (camera, reflected or refracted).
    #[inline(always)]
    fn ray_cast(&mut self, origin: Point3, direction: Vec3, detail: RayDetail) {
        let _ = (origin, direction, detail);
    }

    /// The ray met nothing and brings back the background.
    #[inline(always)]
    fn missed(&mut self, background: Color) {
        let _ = background;
    }

    /// The ray met two surfaces at the same distance and is abandoned (the optics model).
    #[inline(always)]
    fn ambiguous(&mut self) {}

    /// The ray hit `surface` at `point`, where the normal is `normal`.
    #[inline(always)]
    fn hit(&mut self, surface: &Object, point: Point3, normal: Vec3) {
        let _ = (surface, point, normal);
    }

    /// The ray hit the surface that `comps` describes (The Ray Tracer Challenge's prepared
    /// computations: the distance, the side and the media on either side too).
    #[inline(always)]
    fn prepared_hit(&mut self, comps: &Computations<'_>) {
        let _ = comps;
    }

    /// How much of the light at `position` reaches the point being shaded.
    #[inline(always)]
    fn light(&mut self, position: Point3, reach: LightReach) {
        let _ = (position, reach);
    }

    /// Computer Graphics from Scratch's summed light `intensity` at the point and the local
    /// colour it gives (both on the book's 0–255 scale).
    #[inline(always)]
    fn light_sum(&mut self, intensity: [f64; 3], local: [f64; 3]) {
        let _ = (intensity, local);
    }

    /// The optics model's matte term: the light arriving and the surface's opacity.
    #[inline(always)]
    fn matte(&mut self, arriving: Color, opacity: f64) {
        let _ = (arriving, opacity);
    }

    /// A ray passes from a medium of index `from` into one of index `into`.
    #[inline(always)]
    fn refraction(&mut self, from: f64, into: f64) {
        let _ = (from, into);
    }

    /// A secondary ray of `kind` is spawned, carrying `weight` of its parent's light.
    #[inline(always)]
    fn secondary(&mut self, kind: Secondary, weight: f64) {
        let _ = (kind, weight);
    }

    /// A secondary ray of `kind` is left out: its `weight` is below the bailout.
    #[inline(always)]
    fn skipped(&mut self, kind: Secondary, weight: f64) {
        let _ = (kind, weight);
    }

    /// The ray brings back `color`.
    #[inline(always)]
    fn color(&mut self, color: Color) {
        let _ = color;
    }

    /// The events that follow belong to a ray spawned by the current one.
    #[inline(always)]
    fn enter(&mut self) {}

    /// Undoes [`TraceObserver::enter`].
    #[inline(always)]
    fn leave(&mut self) {}
}

/// What an integrator says about a ray it casts besides where it goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RayDetail {
    /// Nothing more (The Ray Tracer Challenge).
    Plain,
    /// The hits that count lie strictly between `t_min` and `t_max` (Computer Graphics from
    /// Scratch).
    Between {
        /// The nearest distance that counts (excluded).
        t_min: f64,
        /// The farthest distance that counts (excluded).
        t_max: f64,
    },
    /// The ray travels in a medium of refractive index `index` carrying `intensity` (the
    /// optics model).
    Medium {
        /// The medium's refractive index.
        index: f64,
        /// The light the ray carries.
        intensity: Color,
    },
}

/// How much of a light reaches a point (The Ray Tracer Challenge's shadow test).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightReach {
    /// The light is behind the surface: no shadow ray.
    Behind,
    /// The light could add too little at the ray's `weight` to show: no shadow ray.
    TooFaint {
        /// The weight of the ray being shaded.
        weight: f64,
    },
    /// This fraction of the light reaches the point.
    Fraction(f64),
}

/// The kind of a secondary ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Secondary {
    /// A mirror reflection.
    Reflected,
    /// A ray through the surface.
    Refracted,
}

impl fmt::Display for Secondary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Secondary::Reflected => "reflected",
            Secondary::Refracted => "refracted",
        })
    }
}

/// The observer of normal renders: hears nothing, costs nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoTrace;

impl TraceObserver for NoTrace {}

/// `--trace-pixel`'s record of the rays one sample casts: one line per event, indented by
/// depth, naming objects by their place in `world`.
#[derive(Debug, Clone)]
pub struct TraceLog<'w> {
    world: &'w World,
    lines: Vec<String>,
    /// How many lines the record keeps at most.
    capacity: usize,
    /// Events past the capacity, counted but not written.
    left_out: u64,
    depth: usize,
}

impl<'w> TraceLog<'w> {
    /// An empty record for rays traced through `world`, keeping at most `capacity` lines: a
    /// ray tree may hold millions of rays, and a record of them all would fill memory long
    /// before anyone could read it.
    pub fn new(world: &'w World, capacity: usize) -> Self {
        Self {
            world,
            lines: Vec::new(),
            capacity,
            left_out: 0,
            depth: 0,
        }
    }

    /// The lines written, and a last one saying how many events were left out, if any.
    pub fn into_lines(mut self) -> Vec<String> {
        if self.left_out > 0 {
            self.lines.push(format!(
                "… and {} more events, not shown (the record keeps {} lines)",
                self.left_out, self.capacity
            ));
        }
        self.lines
    }

    /// Writes a line at the current depth.
    fn note(&mut self, text: String) {
        if self.lines.len() >= self.capacity {
            self.left_out += 1;
            return;
        }
        let line = format!("{}{}", "  ".repeat(self.depth), text);
        self.lines.push(line);
    }

    /// Names an object: its place in the scene's list and its kind (a CSG primitive by the
    /// solid it belongs to).
    fn describe(&self, object: &Object) -> String {
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

impl TraceObserver for TraceLog<'_> {
    fn ray_cast(&mut self, origin: Point3, direction: Vec3, detail: RayDetail) {
        let text = match detail {
            RayDetail::Plain => format!("ray from {} along {}", v(origin), v(direction)),
            RayDetail::Between { t_min, t_max } => format!(
                "ray from {} along {}, {t_min} < t < {t_max}",
                v(origin),
                v(direction)
            ),
            RayDetail::Medium { index, intensity } => format!(
                "ray from {} along {}, in a medium of index {index}, carrying {}",
                v(origin),
                v(direction),
                c(intensity)
            ),
        };
        self.note(text);
    }

    fn missed(&mut self, background: Color) {
        self.note(format!("miss: background {}", c(background)));
    }

    fn ambiguous(&mut self) {
        self.note("ambiguous: two surfaces at the same distance".to_string());
    }

    fn hit(&mut self, surface: &Object, point: Point3, normal: Vec3) {
        let text = format!(
            "hit {}: point {}, normal {}",
            self.describe(surface),
            v(point),
            v(normal)
        );
        self.note(text);
    }

    fn prepared_hit(&mut self, comps: &Computations<'_>) {
        let text = format!(
            "hit {} at t = {:.5}: point {}, normal {}{}, media n1 = {} → n2 = {}",
            self.describe(comps.surface),
            comps.t,
            v(comps.point),
            v(comps.normalv),
            if comps.inside { " (from inside)" } else { "" },
            comps.n1,
            comps.n2
        );
        self.note(text);
    }

    fn light(&mut self, position: Point3, reach: LightReach) {
        self.note(match reach {
            LightReach::Behind => format!("light at {}: behind the surface", v(position)),
            LightReach::TooFaint { weight } => format!(
                "light at {}: too faint to show at weight {:.2e}, left out",
                v(position),
                weight
            ),
            LightReach::Fraction(fraction) => format!(
                "light at {}: {:.3} of it reaches the point",
                v(position),
                fraction
            ),
        });
    }

    fn light_sum(&mut self, intensity: [f64; 3], local: [f64; 3]) {
        self.note(format!(
            "light intensity {intensity:.4?}, local colour (0-255) {local:.3?}"
        ));
    }

    fn matte(&mut self, arriving: Color, opacity: f64) {
        self.note(format!(
            "matte: light arriving {}, opacity {opacity}",
            c(arriving)
        ));
    }

    fn refraction(&mut self, from: f64, into: f64) {
        self.note(format!("refraction from index {from} into {into}"));
    }

    fn secondary(&mut self, kind: Secondary, weight: f64) {
        self.note(format!("{kind} ray, weight {weight}:"));
    }

    fn skipped(&mut self, kind: Secondary, weight: f64) {
        self.note(format!(
            "{kind} ray not traced: weight {weight:.2e} is below the bailout"
        ));
    }

    fn color(&mut self, color: Color) {
        self.note(format!("colour {}", c(color)));
    }

    fn enter(&mut self) {
        self.depth += 1;
    }

    fn leave(&mut self) {
        self.depth = self.depth.saturating_sub(1);
    }
}

/// A vector or point, briefly.
fn v(p: Vec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}

/// A colour, briefly.
fn c(c: Color) -> String {
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
        Shape::Rectangle => "rectangle",
        Shape::Triangle(_) => "triangle",
        Shape::Mesh(_) => "mesh",
        Shape::Curves(_) => "curves",
        Shape::Csg(_) => "csg",
        Shape::Partial(_) => "cut quadric",
    }
}
