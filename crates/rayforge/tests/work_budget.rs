//! Bounds on the work one pixel or one frame may take, whatever the scene: a ray tree that
//! doubles at every bounce stops at the ray budget (in every lighting model) and names its
//! pixel, a stop flag is heeded inside a pixel's work, and a frame the rasterizer could not
//! hold is refused before its triangles are made.
use rayforge::color::color;
use rayforge::math::{scaling, view_transform};
use rayforge::raster::{self, face_count, tessellate, RasterError, RasterOptions};
use rayforge::render::{render_rows, RenderOptions, Stopped, TraceState};
use rayforge::scene::{LightingModel, WorldIndex};
use rayforge::{point, vector, Camera, Light, Object, Shape, World};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// A glass cube inside a mirror cube, the camera inside both: every ray that reaches the glass
/// splits in two and none ever leaves, so the ray tree of one camera ray is 2^depth rays.
fn mirror_box(lighting: LightingModel) -> (Camera, World) {
    let mut w = World::new();
    w.lighting = lighting;
    let mut mirror = Object::cube().with_transform(scaling(5.0, 5.0, 5.0));
    mirror.material.color = color(0.2, 0.2, 0.2);
    mirror.material.reflective = 1.0;
    mirror.material.gloss = color(1.0, 1.0, 1.0);
    mirror.material.opacity = 1.0;
    let mut glass = Object::cube().with_transform(scaling(3.0, 3.0, 3.0));
    glass.material.reflective = 0.5;
    glass.material.transparency = 0.5;
    glass.material.refractive_index = 1.5;
    glass.material.opacity = 0.0;
    w.objects = vec![mirror, glass];
    w.lights
        .push(Light::point(point(0.0, 2.0, 0.0), color(1.0, 1.0, 1.0)));
    let camera = Camera::new(4, 3, 1.0).with_transform(view_transform(
        point(0.0, 0.0, 0.0),
        point(0.0, 0.0, 1.0),
        vector(0.0, 1.0, 0.0),
    ));
    (camera, w)
}

#[test]
fn a_ray_tree_past_the_budget_stops_the_render_and_names_its_pixel_in_every_model() {
    // The optics model prunes its own tree (its intensities fall at every split, and its
    // depth is fixed), so its budget here is small; the others' trees are 2^64 rays.
    for (lighting, budget) in [
        (LightingModel::Phong, 20_000),
        (LightingModel::Cgfs, 20_000),
        (LightingModel::Optics, 10),
    ] {
        let (camera, world) = mirror_box(lighting);
        let options = RenderOptions {
            max_depth: 64,
            max_rays_per_sample: budget,
            ..RenderOptions::default()
        };
        let (image, stats) = render_rows(&camera, &world, &options);
        let (x, y) = stats
            .over_budget
            .unwrap_or_else(|| panic!("{lighting:?}: {} rays and no stop", stats.rays));
        assert!(x < 4 && y < 3, "{lighting:?}: pixel ({x}, {y})");
        assert!(!image.is_complete(), "{lighting:?}");
        // Each thread stops within a sample's budget of the first failure: a handful of
        // budgets in all, not the 2^64 rays the tree would take.
        assert!(
            stats.rays < budget * 16,
            "{lighting:?}: {} rays after the stop",
            stats.rays
        );
    }
}

#[test]
fn a_budget_the_scene_stays_within_changes_no_pixel() {
    let (camera, world) = mirror_box(LightingModel::Phong);
    let shallow = |budget| RenderOptions {
        max_depth: 3,
        max_rays_per_sample: budget,
        ..RenderOptions::default()
    };
    let (a, sa) = render_rows(&camera, &world, &shallow(1 << 20));
    let (b, sb) = render_rows(&camera, &world, &shallow(1_000));
    assert!(a.is_complete() && b.is_complete());
    assert_eq!((sa.over_budget, sb.over_budget), (None, None));
    assert_eq!(a, b);
}

#[test]
fn a_stop_flag_is_heeded_inside_one_camera_ray() {
    let (camera, world) = mirror_box(LightingModel::Cgfs);
    let index = WorldIndex::build(&world);
    let stop = AtomicBool::new(true);
    let mut state = TraceState::new(&world, &index);
    state.set_stop_flags([Some(&stop), None]);
    state.begin_sample();
    let ray = camera.ray_for_pixel(1, 1);
    let _ = rayforge::render::render_one_ray(&mut state, &ray, 64);
    // The flag is looked at every few thousand rays: the 2^64-ray tree stops there.
    assert_eq!(state.stopped(), Some(Stopped::Cancelled));
    assert!(state.rays_cast() < 4096, "{} rays", state.rays_cast());
}

#[test]
fn face_counts_match_the_tessellations() {
    let shapes = [
        Shape::Sphere,
        Shape::Cube,
        Shape::Plane,
        Shape::Rectangle,
        Shape::Torus {
            major: 1.0,
            minor: 0.25,
        },
        Shape::Ring {
            inner: 0.5,
            outer: 1.0,
        },
        Shape::Cylinder {
            minimum: -1.0,
            maximum: 2.0,
            closed: true,
        },
        Shape::Cylinder {
            minimum: f64::NEG_INFINITY,
            maximum: f64::INFINITY,
            closed: false,
        },
        Shape::Cone {
            minimum: -1.0,
            maximum: 0.0,
            closed: true,
        },
    ];
    for shape in &shapes {
        for divisions in [3, 16, 48] {
            assert_eq!(
                face_count(shape, divisions),
                tessellate(shape, divisions).faces.len() as u64,
                "{shape:?} at {divisions}"
            );
        }
    }
}

#[test]
fn a_frame_over_the_triangle_budget_is_refused_before_its_triangles_are_made() {
    // 64 spheres at 4096 divisions: 2.1 billion triangles, 51 GB had they been made.
    let mut world = World::new();
    world.objects = (0..64)
        .map(|i| Object::sphere().with_transform(rayforge::math::translation(i as f64, 0.0, 0.0)))
        .collect();
    let camera = Camera::new(16, 16, 1.0).with_transform(view_transform(
        point(0.0, 0.0, -50.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let options = RasterOptions {
        sphere_divisions: 4096,
        ..RasterOptions::default()
    };
    let started = Instant::now();
    let refused = raster::render(&camera, &world, &options);
    assert_eq!(
        refused.err(),
        Some(RasterError::TooManyTriangles {
            limit: RasterOptions::DEFAULT_MAX_TRIANGLES
        })
    );
    // Refused before any sphere is built: 64 meshes of 33 million triangles would take far
    // longer than this guard on any machine.
    assert!(started.elapsed().as_secs() < 60);
    // At the default resolution the same frame is drawn.
    assert!(raster::render(&camera, &world, &RasterOptions::default()).is_ok());
    // And a budget below one model's size refuses it too.
    let tight = RasterOptions {
        max_triangles: 1_000,
        ..RasterOptions::default()
    };
    assert!(raster::render(&camera, &world, &tight).is_err());
}
