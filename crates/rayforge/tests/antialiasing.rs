//! Anti-aliasing (chapter 17's "next steps"): stratified jittered samples and the adaptive
//! scheme, both deterministic per pixel.
use rayforge::color::color;
use rayforge::render::{render, RenderOptions, Sampling};
use rayforge::{default_world, point, vector, Camera, Color};

#[test]
fn a_sample_count_is_the_rays_per_pixel_a_grid_when_square() {
    assert_eq!(Sampling::with_samples(0), Sampling::Centre);
    assert_eq!(Sampling::with_samples(1), Sampling::Centre);
    assert_eq!(
        Sampling::with_samples(4),
        Sampling::Stratified { per_side: 2 }
    );
    assert_eq!(Sampling::with_samples(5), Sampling::Rooks { samples: 5 });
    assert_eq!(
        Sampling::with_samples(9),
        Sampling::Stratified { per_side: 3 }
    );
    for spp in 1..=100 {
        assert_eq!(Sampling::with_samples(spp).camera_rays(), u64::from(spp));
    }
    assert_eq!(
        Sampling::with_samples(16),
        Sampling::Stratified { per_side: 4 }
    );
}

#[test]
fn stratified_samples_fall_one_in_each_cell_of_the_pixel() {
    let mut points = Vec::new();
    Sampling::Stratified { per_side: 3 }.pixel(7, 2, 99, |s| {
        points.push((s.x, s.y));
        Color::BLACK
    });
    assert_eq!(points.len(), 9);
    let mut cells: Vec<(u32, u32)> = points
        .iter()
        .map(|&(x, y)| {
            assert!(
                (7.0..8.0).contains(&x) && (2.0..3.0).contains(&y),
                "({x}, {y})"
            );
            (((x - 7.0) * 3.0) as u32, ((y - 2.0) * 3.0) as u32)
        })
        .collect();
    cells.sort_unstable();
    cells.dedup();
    assert_eq!(cells.len(), 9, "one sample per cell");
}

#[test]
fn rooks_samples_take_one_column_and_one_row_each() {
    for (samples, seed) in [(5, 99), (7, 3), (50, 12)] {
        let mut points = Vec::new();
        Sampling::Rooks { samples }.pixel(4, 6, seed, |s| {
            points.push((s.x, s.y));
            Color::BLACK
        });
        assert_eq!(points.len(), samples as usize);
        let n = f64::from(samples);
        let strata = |pick: fn(&(f64, f64)) -> f64, base: f64| {
            let mut cells: Vec<u32> = points
                .iter()
                .map(|p| {
                    let v = pick(p) - base;
                    assert!((0.0..1.0).contains(&v), "{p:?}");
                    (v * n) as u32
                })
                .collect();
            cells.sort_unstable();
            cells
        };
        let all: Vec<u32> = (0..samples).collect();
        assert_eq!(strata(|p| p.0, 4.0), all, "one sample per column");
        assert_eq!(strata(|p| p.1, 6.0), all, "one sample per row");
    }
}

#[test]
fn stratified_samples_depend_only_on_the_pixel() {
    let run = |seed| {
        let mut points = Vec::new();
        Sampling::Stratified { per_side: 2 }.pixel(3, 4, seed, |s| {
            points.push((s.x, s.y));
            Color::BLACK
        });
        points
    };
    assert_eq!(run(5), run(5));
    assert_ne!(run(5), run(6));
}

#[test]
fn the_average_of_samples_is_the_pixel_colour() {
    let c = Sampling::Stratified { per_side: 2 }.pixel(0, 0, 1, |s| {
        if s.x < 0.5 {
            color(1.0, 0.0, 0.0)
        } else {
            color(0.0, 0.0, 1.0)
        }
    });
    assert_eq!(c, color(0.5, 0.0, 0.5));
}

#[test]
fn adaptive_sampling_takes_five_rays_where_the_pixel_is_flat() {
    let mut rays = 0;
    let c = Sampling::Adaptive {
        threshold: 0.1,
        depth: 3,
    }
    .pixel(4, 4, 0, |_| {
        rays += 1;
        color(0.2, 0.4, 0.6)
    });
    assert_eq!(rays, 5);
    assert_eq!(c, color(0.2, 0.4, 0.6));
}

#[test]
fn adaptive_sampling_subdivides_across_an_edge() {
    let mut rays = 0;
    // A vertical edge at x = 4.3 inside pixel (4, 0).
    let c = Sampling::Adaptive {
        threshold: 0.1,
        depth: 3,
    }
    .pixel(4, 0, 0, |s| {
        rays += 1;
        if s.x < 4.3 {
            Color::WHITE
        } else {
            Color::BLACK
        }
    });
    assert!(rays > 5, "the edge is refined ({rays} rays)");
    // Close to the 30 % of the pixel left of the edge.
    assert!((c.red - 0.3).abs() < 0.08, "{c:?}");
}

#[test]
fn anti_aliased_renders_keep_flat_areas_and_soften_edges() {
    let w = default_world();
    let camera = Camera::new(16, 16, std::f64::consts::FRAC_PI_2).with_transform(
        rayforge::math::view_transform(
            point(0.0, 0.0, -5.0),
            point(0.0, 0.0, 0.0),
            vector(0.0, 1.0, 0.0),
        ),
    );
    let plain = render(&camera, &w, &RenderOptions::default()).0;
    let aa = render(
        &camera,
        &w,
        &RenderOptions {
            sampling: Sampling::with_samples(16),
            ..RenderOptions::default()
        },
    )
    .0;
    // Far outside the sphere both are the black background.
    assert_eq!(aa.pixel_at(0, 0), Color::BLACK);
    // Along the sphere's silhouette the anti-aliased image blends sphere and background:
    // some pixel is lit but dimmer than the same pixel rendered with one ray.
    let blended = (0..16)
        .flat_map(|y| (0..16).map(move |x| (x, y)))
        .any(|(x, y)| {
            let (p, a) = (plain.pixel_at(x, y), aa.pixel_at(x, y));
            a.red > 0.0 && (a.red < p.red - 1e-3 || p.red == 0.0)
        });
    assert!(blended);
}

#[test]
fn a_pinhole_camera_ignores_the_lens_sample() {
    let c = Camera::new(11, 11, 1.0);
    assert_eq!(
        c.ray_through_lens(3.2, 4.7, 0.1, 0.9),
        c.ray_through(3.2, 4.7)
    );
}

#[test]
fn a_thin_lens_keeps_the_focal_plane_sharp_and_blurs_the_rest() {
    let c = Camera::new(11, 11, 1.0).with_lens(0.5, 4.0);
    let centre = c.ray_through_lens(5.5, 5.5, 0.5, 0.5);
    let edge = c.ray_through_lens(5.5, 5.5, 0.95, 0.2);
    // Rays from different points of the lens meet on the focal plane (z = -4 here)…
    let on_plane = |r: rayforge::Ray| r.position(-4.0 / r.direction.z);
    assert!((on_plane(centre) - on_plane(edge)).length() < 1e-9);
    // …and start from different points of the lens, within its radius.
    assert!(edge.origin.length() > 0.1 && edge.origin.length() <= 0.25 + 1e-12);
    // Away from the focal plane they diverge.
    let near = |r: rayforge::Ray| r.position(-1.0 / r.direction.z);
    assert!((near(centre) - near(edge)).length() > 0.05);
}
