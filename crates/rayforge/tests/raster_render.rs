//! The rasterizer end to end: it draws rayforge worlds through rayforge cameras, lined up with
//! the ray tracer, with hidden surfaces removed, back faces culled, and the same bytes for any
//! number of threads.

use rayforge::geometry::{Mesh, MeshFace};
use rayforge::math::{scaling, translation, view_transform};
use rayforge::raster::{self, RasterOptions, Shading, TextureFilter};
use rayforge::shading::{Filter, Texture, UvPattern};
use rayforge::{point, vector, Camera, Color, Light, Material, Object, World};
use std::sync::Arc;

fn camera(size: usize) -> Camera {
    Camera::new(size, size, std::f64::consts::FRAC_PI_3).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ))
}

fn matte(color: Color) -> Material {
    Material {
        color,
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        ..Material::DEFAULT
    }
}

fn world(objects: Vec<Object>) -> World {
    World {
        objects,
        lights: vec![Light::point(point(-10.0, 10.0, -10.0), Color::WHITE)],
        background: Color::new(0.0, 0.0, 0.25),
        ..World::default()
    }
}

fn close(a: Color, b: Color, tolerance: f64) -> bool {
    (a.red - b.red).abs() < tolerance
        && (a.green - b.green).abs() < tolerance
        && (a.blue - b.blue).abs() < tolerance
}

#[test]
fn the_default_world_lines_up_with_the_ray_tracer() {
    let w = rayforge::default_world();
    let c = camera(41);
    let traced = c.render(&w);
    let options = RasterOptions {
        sphere_divisions: 64,
        ..RasterOptions::default()
    };
    let drawn = raster::render(&c, &w, &options).expect("within the triangle budget");
    let mut differ = 0;
    for y in 0..41 {
        for x in 0..41 {
            let (a, b) = (traced.pixel_at(x, y), drawn.pixel_at(x, y));
            // Inside the silhouette the Phong terms are the ray tracer's (no shadows fall in
            // the default world's view); the tessellated edge may differ by a pixel.
            if !close(a, b, 0.02) {
                differ += 1;
            }
        }
    }
    assert!(differ <= 12, "{differ} pixels differ");
    assert!(close(traced.pixel_at(20, 20), drawn.pixel_at(20, 20), 0.01));
}

/// A square of side 2 facing the camera at depth `z` (two triangles, one mesh).
fn square(z: f64, color: Color) -> Object {
    let positions = vec![
        point(-1.0, -1.0, z),
        point(1.0, -1.0, z),
        point(1.0, 1.0, z),
        point(-1.0, 1.0, z),
    ];
    let faces = [[0, 1, 2], [0, 2, 3]]
        .map(|vertices| MeshFace {
            vertices,
            normals: None,
            texcoords: None,
        })
        .to_vec();
    Object::mesh(Arc::new(Mesh::new(positions, vec![], faces).unwrap())).with_material(matte(color))
}

#[test]
fn the_nearer_surface_hides_the_farther_in_either_order() {
    let red = Color::new(1.0, 0.0, 0.0);
    let green = Color::new(0.0, 1.0, 0.0);
    let near = square(-1.0, red).with_transform(scaling(0.5, 0.5, 1.0));
    let far = square(1.0, green).with_transform(scaling(3.0, 3.0, 1.0));
    for objects in [vec![near.clone(), far.clone()], vec![far, near]] {
        let image = raster::render(&camera(21), &world(objects), &RasterOptions::default())
            .expect("within the triangle budget");
        assert_eq!(image.pixel_at(10, 10), red, "the near square in front");
        assert_eq!(image.pixel_at(3, 10), green, "the far one around it");
        assert_eq!(
            image.pixel_at(0, 0),
            Color::new(0.0, 0.0, 0.25),
            "background"
        );
    }
}

#[test]
fn intersecting_surfaces_meet_where_their_depths_cross() {
    // A square tilted through the one facing the camera: the depth test decides per pixel.
    let red = Color::new(1.0, 0.0, 0.0);
    let green = Color::new(0.0, 1.0, 0.0);
    let tilted = square(0.0, green).with_transform(rayforge::math::rotation_y(0.7));
    let flat = square(0.0, red);
    let image = raster::render(
        &camera(41),
        &world(vec![flat, tilted]),
        &RasterOptions::default(),
    )
    .expect("within the triangle budget");
    // rotation_y turns +x towards -z (nearer the camera at z = -5) on one side only.
    let (left, right) = (image.pixel_at(14, 20), image.pixel_at(26, 20));
    assert_ne!(left, right);
    assert!([left, right].contains(&red) && [left, right].contains(&green));
}

#[test]
fn back_face_culling_skips_hidden_faces_only() {
    let objects = vec![
        Object::sphere(),
        Object::cube().with_transform(translation(2.5, 0.0, 1.0) * scaling(0.7, 0.7, 0.7)),
        // A mirrored cube: its winding turns over, culling must still keep the front.
        Object::cube().with_transform(translation(-2.5, 0.0, 1.0) * scaling(-0.7, 0.7, 0.7)),
    ];
    let w = world(objects);
    let on = RasterOptions::default();
    let off = RasterOptions {
        backface_culling: false,
        ..on
    };
    let (a, stats_on) =
        raster::render_with_stats(&camera(48), &w, &on).expect("within the triangle budget");
    let (b, stats_off) =
        raster::render_with_stats(&camera(48), &w, &off).expect("within the triangle budget");
    assert_eq!(a, b, "culling changes no pixel of closed shapes");
    assert_eq!(stats_off.culled, 0);
    // About half of each closed shape faces away.
    let facing_away = stats_on.culled as f64 / stats_on.triangles as f64;
    // From 5 units away less than a hemisphere of a unit sphere is visible.
    assert!((0.45..0.75).contains(&facing_away), "{facing_away}");
    // Without culling the back faces go on to the tiles (at least those covering a pixel).
    let kept = stats_on.drawn as f64 / stats_off.drawn as f64;
    assert!((0.3..0.7).contains(&kept), "{kept}");
}

#[test]
fn from_inside_a_closed_shape_its_faces_are_drawn() {
    // A room: the camera inside a large cube sees its walls (none is culled).
    let room = Object::cube()
        .with_transform(scaling(10.0, 10.0, 10.0))
        .with_material(matte(Color::new(0.5, 0.5, 0.5)));
    let image = raster::render(&camera(9), &world(vec![room]), &RasterOptions::default())
        .expect("within the triangle budget");
    assert!(image
        .pixels()
        .iter()
        .all(|&p| p == Color::new(0.5, 0.5, 0.5)));
}

#[test]
fn a_floor_through_the_near_plane_is_clipped_not_dropped() {
    // A plane under the camera reaches behind the eye: its triangles are split at the near
    // plane and at the image's sides, and the visible part matches the ray tracer.
    let floor = Object::plane()
        .with_transform(translation(0.0, -1.0, 0.0))
        .with_material(matte(Color::new(0.2, 0.7, 0.2)));
    let w = world(vec![floor]);
    // A wide view from just in front of a grid line: the nearest visible cells have corners
    // behind the eye.
    let c = Camera::new(40, 40, 2.8).with_transform(view_transform(
        point(0.0, 0.0, -4.75),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let traced = c.render(&w);
    // Every shading mode: Gouraud must light the pieces whose corners lie behind the eye too.
    for shading in [Shading::Phong, Shading::Gouraud, Shading::Flat] {
        let options = RasterOptions {
            shading,
            ..RasterOptions::default()
        };
        let (image, stats) =
            raster::render_with_stats(&c, &w, &options).expect("within the triangle budget");
        assert!(stats.clipped > 0);
        let differ = (0..40 * 40)
            .filter(|i| !close(image.pixels()[*i], traced.pixels()[*i], 1e-9))
            .count();
        // Only along the horizon can a pixel centre fall on the other side of the far grid edge.
        assert!(differ <= 40, "{shading:?}: {differ} pixels differ");
        assert!(close(
            image.pixel_at(20, 39),
            Color::new(0.2, 0.7, 0.2),
            1e-9
        ));
    }
}

#[test]
fn the_book_sphere_generator_makes_divs_plus_one_rings_of_divs_vertices() {
    for divs in [3u32, 8, 15, 48] {
        let sphere = raster::generate_sphere(divs);
        let d = divs as usize;
        assert_eq!(sphere.positions.len(), (d + 1) * d);
        assert_eq!(sphere.faces.len(), 2 * d * d);
        assert!(sphere.closed);
        for p in sphere.positions.iter() {
            assert!((p.length() - 1.0).abs() < 1e-12);
        }
        // Every face with an area is wound outwards: (p3 - p1) × (p2 - p1) points away.
        for face in sphere.faces.iter() {
            let [p1, p2, p3] = sphere.corners(&face);
            let n = (p3 - p1).cross(p2 - p1);
            if n.length() > 1e-12 {
                assert!(n.dot(p1 + p2 + p3) > 0.0);
            }
        }
    }
}

#[test]
fn every_shape_tessellates_with_outward_faces() {
    use rayforge::raster::tessellate;
    use rayforge::Shape;
    let shapes = [
        Shape::Cube,
        Shape::Cylinder {
            minimum: -1.0,
            maximum: 2.0,
            closed: true,
        },
        Shape::Cone {
            minimum: -1.0,
            maximum: 1.0,
            closed: true,
        },
        Shape::CYLINDER,
        Shape::Plane,
    ];
    let counts: Vec<usize> = shapes
        .iter()
        .map(|s| {
            let t = tessellate(s, 16);
            for face in t.faces.iter() {
                let [p1, p2, p3] = t.corners(&face);
                let n = (p3 - p1).cross(p2 - p1);
                let centre = (p1 + p2 + p3) / 3.0;
                let outward = match s {
                    Shape::Plane => rayforge::vector(0.0, 1.0, 0.0),
                    Shape::Cube => centre,
                    // Caps point along y, sides away from the axis.
                    _ if (p1.y == p2.y && p2.y == p3.y) => rayforge::vector(0.0, centre.y, 0.0),
                    _ => rayforge::vector(centre.x, 0.0, centre.z),
                };
                if n.length() > 1e-12 {
                    assert!(n.dot(outward) > 0.0, "{s:?}: {face:?}");
                }
            }
            t.faces.len()
        })
        .collect();
    assert_eq!(counts[0], 12, "the cube has twelve triangles");
    assert!(counts[4] > 1000, "planes are grids");
}

#[test]
fn the_image_is_the_same_for_any_thread_count() {
    let mut objects = vec![Object::plane().with_transform(translation(0.0, -1.0, 0.0))];
    for i in 0..5 {
        objects.push(Object::sphere().with_transform(
            translation(i as f64 - 2.0, 0.0, i as f64 * 0.5) * scaling(0.6, 0.6, 0.6),
        ));
    }
    let w = world(objects);
    let c = camera(67);
    // 140 divisions: 39 200 triangles per sphere, so the triangles span several chunks.
    for (shading, sphere_divisions) in [
        (Shading::Flat, 20),
        (Shading::Gouraud, 48),
        (Shading::Phong, 140),
    ] {
        let options = RasterOptions {
            shading,
            sphere_divisions,
            ..RasterOptions::default()
        };
        let render = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| raster::render(&c, &w, &options).expect("within the triangle budget"))
        };
        let one = render(1);
        assert_eq!(one.to_rgb8(), render(3).to_rgb8());
        assert_eq!(one, render(2));
    }
}

#[test]
fn flat_gouraud_and_phong_agree_at_a_vertex_and_differ_between() {
    let w = rayforge::default_world();
    let c = camera(51);
    let render = |shading| {
        raster::render(
            &c,
            &w,
            &RasterOptions {
                shading,
                sphere_divisions: 12,
                ..RasterOptions::default()
            },
        )
        .expect("within the triangle budget")
    };
    let (flat, gouraud, phong) = (
        render(Shading::Flat),
        render(Shading::Gouraud),
        render(Shading::Phong),
    );
    assert_ne!(flat, gouraud);
    assert_ne!(gouraud, phong);
    // Flat shading is one colour per triangle: far fewer distinct colours.
    let distinct = |c: &rayforge::Canvas| {
        let mut v: Vec<[u8; 3]> = c.to_rgb8().chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
        v.sort();
        v.dedup();
        v.len()
    };
    assert!(
        distinct(&flat) * 3 < distinct(&phong),
        "{} {}",
        distinct(&flat),
        distinct(&phong)
    );
}

#[test]
fn wireframe_draws_edges_only() {
    let red = Color::new(1.0, 0.0, 0.0);
    let options = RasterOptions {
        wireframe: true,
        ..RasterOptions::default()
    };
    let image = raster::render(&camera(41), &world(vec![square(0.0, red)]), &options)
        .expect("within the triangle budget");
    let inked = image.pixels().iter().filter(|&&p| p == red).count();
    // The outline and one diagonal of a square about 14 pixels across.
    assert!((55..=90).contains(&inked), "{inked}");
    assert_eq!(
        image.pixel_at(14, 20),
        Color::new(0.0, 0.0, 0.25),
        "inside is empty"
    );
}

/// A floor quad from z = 0 to z = 20 whose texture's red channel is v (bilinear: exactly v).
fn textured_floor(filter: Filter) -> Object {
    let height = 256;
    let pixels = (0..height)
        .flat_map(|y| {
            let v = 1.0 - y as f64 / (height - 1) as f64;
            [Color::new(v, 0.0, 0.0); 2]
        })
        .collect();
    let texture = Texture::new(2, height, pixels, filter).unwrap();
    let positions = vec![
        point(-3.0, -1.0, 0.0),
        point(3.0, -1.0, 0.0),
        point(3.0, -1.0, 20.0),
        point(-3.0, -1.0, 20.0),
    ];
    let texcoords = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let faces = [[0, 1, 2], [0, 2, 3]]
        .map(|v| MeshFace {
            vertices: v,
            normals: None,
            texcoords: Some(v),
        })
        .to_vec();
    let mesh = Mesh::with_texcoords(positions, vec![], texcoords, faces).unwrap();
    Object::mesh(Arc::new(mesh)).with_material(Material {
        texture: Some(Box::new(UvPattern::Image(Arc::new(texture)))),
        ..matte(Color::WHITE)
    })
}

#[test]
fn texture_coordinates_are_perspective_correct() {
    let w = world(vec![textured_floor(Filter::Bilinear)]);
    let c = Camera::new(40, 40, 1.0).with_transform(view_transform(
        point(0.0, 0.5, -2.0),
        point(0.0, -1.0, 6.0),
        vector(0.0, 1.0, 0.0),
    ));
    let traced = c.render(&w);
    let options = RasterOptions {
        filter: TextureFilter::Bilinear,
        ..RasterOptions::default()
    };
    let drawn = raster::render(&c, &w, &options).expect("within the triangle budget");
    let mut compared = 0;
    for y in 0..40 {
        for x in 0..40 {
            let (a, b) = (traced.pixel_at(x, y), drawn.pixel_at(x, y));
            if a.blue == 0.0 && b.blue == 0.0 {
                // Both see the floor: v (the red channel) agrees to well under a percent, where
                // interpolating u and v linearly on the screen would be off by up to ~0.2.
                assert!(
                    (a.red - b.red).abs() < 2e-3,
                    "({x}, {y}): {} vs {}",
                    a.red,
                    b.red
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 400, "{compared}");
}

#[test]
fn trilinear_filtering_averages_a_minified_checkerboard() {
    // A 64×64 checkerboard of single texels on a floor seen edge-on: far away each pixel
    // covers many texels; nearest filtering aliases to black or white, trilinear averages.
    let n = 64;
    let pixels = (0..n * n)
        .map(|i| {
            if (i % n + i / n) % 2 == 0 {
                Color::WHITE
            } else {
                Color::BLACK
            }
        })
        .collect();
    let texture = Arc::new(Texture::new(n, n, pixels, Filter::Bilinear).unwrap());
    let mut floor = textured_floor(Filter::Bilinear);
    floor.material.texture = Some(Box::new(UvPattern::Image(texture)));
    let w = world(vec![floor]);
    let c = Camera::new(32, 32, 0.6).with_transform(view_transform(
        point(0.0, -0.6, -2.0),
        point(0.0, -1.0, 20.0),
        vector(0.0, 1.0, 0.0),
    ));
    let render = |filter| {
        raster::render(
            &c,
            &w,
            &RasterOptions {
                filter,
                ..RasterOptions::default()
            },
        )
        .expect("within the triangle budget")
    };
    let (nearest, trilinear) = (
        render(TextureFilter::Nearest),
        render(TextureFilter::Trilinear),
    );
    // The far rows of the floor (just under the horizon, but above the near rows).
    let row = (0..32)
        .find(|&y| trilinear.pixel_at(16, y) != Color::new(0.0, 0.0, 0.25))
        .expect("the floor is visible");
    let grey = |c: Color| (c.red - 0.5).abs() < 0.2;
    let far = |img: &rayforge::Canvas| (0..32).filter(|&x| grey(img.pixel_at(x, row + 1))).count();
    assert!(
        far(&trilinear) >= 28,
        "trilinear is grey far away: {}",
        far(&trilinear)
    );
    assert!(
        far(&nearest) <= 4,
        "nearest picks black or white: {}",
        far(&nearest)
    );
}

#[test]
fn a_csg_difference_shows_the_hole() {
    use rayforge::CsgOperation;
    let solid = Object::csg(
        CsgOperation::Difference,
        Object::cube().with_material(matte(Color::new(1.0, 0.0, 0.0))),
        Object::sphere()
            .with_transform(translation(0.0, 0.0, -1.0) * scaling(0.8, 0.8, 0.8))
            .with_material(matte(Color::new(0.0, 1.0, 0.0))),
    )
    .unwrap();
    let w = world(vec![solid]);
    let c = camera(41);
    let traced = c.render(&w);
    let drawn =
        raster::render(&c, &w, &RasterOptions::default()).expect("within the triangle budget");
    // In the middle, the hole's wall (the sphere's inside, green); at the corners, the cube.
    assert_eq!(drawn.pixel_at(20, 20), Color::new(0.0, 1.0, 0.0));
    assert_eq!(drawn.pixel_at(13, 13), Color::new(1.0, 0.0, 0.0));
    let differ = (0..41 * 41)
        .filter(|&i| traced.pixels()[i] != drawn.pixels()[i])
        .count();
    assert!(differ < 41 * 41 / 20, "{differ} pixels differ");
}

#[test]
fn refining_cuts_faces_into_k_squared_pieces_of_the_same_surface() {
    use rayforge::raster::{refine, tessellate};
    let cube = tessellate(&rayforge::Shape::Cube, 8);
    // Cube faces' triangles have legs of 2 and a hypotenuse of 2√2: k = ⌈2√2 / 0.75⌉ = 4.
    let fine = refine(&cube, 0.75);
    assert_eq!(fine.faces.len(), 12 * 16);
    let area = |t: &rayforge::raster::Tessellation<'_>| -> f64 {
        t.faces
            .iter()
            .map(|f| {
                let [a, b, c] = t.corners(&f);
                (b - a).cross(c - a).length() / 2.0
            })
            .sum()
    };
    assert!((area(&fine) - 24.0).abs() < 1e-9);
    for face in fine.faces.iter() {
        let [p1, p2, p3] = fine.corners(&face);
        let n = (p3 - p1).cross(p2 - p1);
        assert!(n.dot(p1 + p2 + p3) > 0.0, "still wound outwards");
    }
}

#[test]
fn a_resized_viewport_camera_rasterizes_the_same_view_at_the_new_size() {
    // `--width` on a Computer Graphics from Scratch scene resizes its viewport camera: the
    // rasterizer must see the smaller canvas's pixels, not a corner of the old one.
    use rayforge::camera::Viewport;
    let w = world(vec![Object::sphere()
        .with_transform(translation(0.5, 0.0, 5.0))
        .with_material(matte(Color::WHITE))]);
    let resized = Camera::viewport(600, 600, Viewport::BOOK)
        .unwrap()
        .resized(60, 60);
    let native = Camera::viewport(60, 60, Viewport::BOOK).unwrap();
    let options = RasterOptions::default();
    assert_eq!(
        raster::render(&resized, &w, &options).expect("within the triangle budget"),
        raster::render(&native, &w, &options).expect("within the triangle budget")
    );
    assert_eq!(resized.pixel_size(), native.pixel_size());
}

/// The stop flag is looked at before each stage and each tile: set before the frame, nothing
/// is drawn (0 tiles, of the 2 × 3 of a 100 × 90 image in 64 × 32 tiles) and the frame is
/// refused as interrupted; left clear, the frame is the bytes of one drawn without a flag.
#[test]
fn a_stop_flag_set_before_a_frame_draws_no_tile() {
    use rayforge::raster::{RasterError, Rasterizer};
    use std::sync::atomic::AtomicBool;
    let w = rayforge::default_world();
    let c = Camera::new(100, 90, std::f64::consts::FRAC_PI_3).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let options = RasterOptions::default();
    let stop = AtomicBool::new(true);
    let cancelled = RasterError::Cancelled {
        tiles_drawn: 0,
        tiles: 6,
    };
    assert_eq!(
        raster::render_film(&c, &w, &options, Some(&stop)).err(),
        Some(cancelled)
    );
    let mut rasterizer = Rasterizer::new();
    assert_eq!(
        rasterizer.render(&c, &w, &options, Some(&stop)).err(),
        Some(cancelled)
    );
    let clear = AtomicBool::new(false);
    let drawn = rasterizer
        .render(&c, &w, &options, Some(&clear))
        .expect("drawn whole")
        .0
        .clone();
    assert_eq!(drawn, raster::render(&c, &w, &options).unwrap());
}

/// The rasterizer projects onto a plane through a pinhole centred on its axis: it refuses,
/// before drawing anything, a spherical camera (no plane holds its image), a screen window
/// (off the axis or stretched pixels) and an orthographic camera, each naming what it is;
/// the same camera without them draws.
#[test]
fn cameras_the_rasterizer_cannot_project_are_refused_by_name() {
    use rayforge::camera::{ScreenWindow, SphericalMapping};
    use rayforge::raster::RasterError;
    let scene = world(vec![Object::sphere().with_material(matte(Color::WHITE))]);
    let place = |c: Camera| c.with_transform_of(*camera(8).transform());
    let options = RasterOptions::default();
    for mapping in [
        SphericalMapping::Equirectangular,
        SphericalMapping::EqualArea,
    ] {
        let spherical = place(Camera::spherical(16, 8, mapping));
        match raster::render(&spherical, &scene, &options) {
            Err(e @ RasterError::Unprojected(_)) => {
                assert!(e.to_string().contains("spherical"), "{e}")
            }
            other => panic!("{mapping:?}: {other:?}"),
        }
    }
    let windowed = camera(8)
        .with_screen_window(ScreenWindow {
            x_min: 0.0,
            x_max: 0.5,
            y_min: -0.25,
            y_max: 0.25,
        })
        .unwrap();
    match raster::render(&windowed, &scene, &options) {
        Err(e @ RasterError::Unprojected(_)) => {
            assert!(e.to_string().contains("screen window"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    let orthographic = place(Camera::orthographic(8, 8, 1.5));
    assert!(matches!(
        raster::render(&orthographic, &scene, &options),
        Err(RasterError::Orthographic)
    ));
    assert!(raster::render(&camera(8), &scene, &options).is_ok());
}
