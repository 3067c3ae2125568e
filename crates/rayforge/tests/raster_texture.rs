//! Texture filtering for the rasterizer (MIP maps, the book's "TO DO") and the CSG rule that
//! keeps or drops the primitives' triangles.

use rayforge::math::{scaling, translation};
use rayforge::raster::{MipChain, TextureFilter};
use rayforge::shading::{Filter, Texture};
use rayforge::{point, Color, CsgOperation, Object};

fn checkerboard(width: usize, height: usize) -> Texture {
    let pixels = (0..width * height)
        .map(|i| {
            if (i % width + i / width) % 2 == 0 {
                Color::WHITE
            } else {
                Color::BLACK
            }
        })
        .collect();
    Texture::new(width, height, pixels, Filter::Bilinear).unwrap()
}

#[test]
fn a_mip_chain_halves_down_to_one_texel_that_is_the_average() {
    let mip = MipChain::new(&checkerboard(8, 4));
    assert_eq!(mip.levels(), 4);
    assert_eq!(mip.level_size(0), (8, 4));
    assert_eq!(mip.level_size(1), (4, 2));
    assert_eq!(mip.level_size(2), (2, 1));
    assert_eq!(mip.level_size(3), (1, 1));
    let last = mip.sample(0.3, 0.7, 10.0, TextureFilter::Trilinear);
    assert!((last.red - 0.5).abs() < 1e-12 && (last.blue - 0.5).abs() < 1e-12);
    // Odd sizes keep their last column.
    let odd = MipChain::new(&checkerboard(5, 5));
    assert_eq!(odd.level_size(1), (3, 3));
    assert_eq!(odd.levels(), 4);
}

#[test]
fn level_zero_bilinear_is_the_ray_tracers_sampling() {
    let pixels = (0..12)
        .map(|i| Color::new(i as f64 / 11.0, (i * i) as f64 / 121.0, 0.5))
        .collect();
    let texture = Texture::new(4, 3, pixels, Filter::Bilinear).unwrap();
    let mip = MipChain::new(&texture);
    for (u, v) in [
        (0.0, 0.0),
        (0.31, 0.77),
        (0.5, 0.5),
        (1.0, 1.0),
        (0.9, 0.05),
    ] {
        assert_eq!(
            mip.sample(u, v, 0.0, TextureFilter::Bilinear),
            texture.sample(u, v)
        );
        assert_eq!(
            mip.sample(u, v, 0.0, TextureFilter::Trilinear),
            texture.sample(u, v)
        );
    }
    let nearest = Texture::new(4, 3, texture.pixels().to_vec(), Filter::Nearest).unwrap();
    assert_eq!(
        mip.sample(0.31, 0.77, 0.0, TextureFilter::Nearest),
        nearest.sample(0.31, 0.77)
    );
}

#[test]
fn the_level_of_detail_follows_the_footprint_in_texels() {
    let mip = MipChain::new(&checkerboard(257, 257));
    // One pixel spans 1/256 of the texture: one texel, level 0.
    assert!(
        mip.level_of_detail(1.0 / 256.0, 0.0, 0.0, 1.0 / 256.0)
            .abs()
            < 1e-9
    );
    // Four texels across (the longer side counts): level 2.
    assert!((mip.level_of_detail(4.0 / 256.0, 0.0, 0.0, 1.0 / 256.0) - 2.0).abs() < 1e-9);
    // Magnified: level 0.
    assert_eq!(mip.level_of_detail(1e-5, 0.0, 0.0, 1e-5), 0.0);
    // Trilinear between levels blends them.
    let a = mip.sample(0.5, 0.5, 1.0, TextureFilter::Trilinear);
    let b = mip.sample(0.5, 0.5, 2.0, TextureFilter::Trilinear);
    let mid = mip.sample(0.5, 0.5, 1.5, TextureFilter::Trilinear);
    assert!((mid.red - (a.red + b.red) / 2.0).abs() < 1e-12);
}

#[test]
fn csg_keeps_the_surface_points_each_operation_allows() {
    let left = Object::sphere();
    let right = Object::sphere().with_transform(translation(1.0, 0.0, 0.0));
    let solid = |op| match Object::csg(op, left.clone(), right.clone()).unwrap().shape {
        rayforge::Shape::Csg(csg) => csg,
        _ => unreachable!(),
    };
    // A point of the left sphere inside the right one, and one outside it.
    let (inner, outer) = (point(0.8, 0.6, 0.0), point(-1.0, 0.0, 0.0));
    let union = solid(CsgOperation::Union);
    assert!(!union.keeps_surface_point(0, inner));
    assert!(union.keeps_surface_point(0, outer));
    let intersection = solid(CsgOperation::Intersection);
    assert!(intersection.keeps_surface_point(0, inner));
    assert!(!intersection.keeps_surface_point(0, outer));
    let difference = solid(CsgOperation::Difference);
    assert!(!difference.keeps_surface_point(0, inner));
    assert!(difference.keeps_surface_point(0, outer));
    // The right sphere's surface inside the left one is the wall of the hole.
    assert!(difference.keeps_surface_point(1, point(0.0, 0.0, 0.0) + point(0.05, 0.0, 0.0)));
    assert!(!difference.keeps_surface_point(1, point(2.0, 0.0, 0.0)));
    assert!(difference.contains_point(point(-0.5, 0.0, 0.0)));
    assert!(!difference.contains_point(point(0.5, 0.0, 0.0)));
}

#[test]
fn nested_csg_and_groups_count_as_their_combined_solid() {
    // (big sphere ∩ cube) − small sphere at the centre: a point on the cube's face inside the
    // big sphere is kept; one at the cube's corner (outside the big sphere) is not.
    let inner = Object::csg(
        CsgOperation::Intersection,
        Object::cube(),
        Object::sphere().with_transform(scaling(1.35, 1.35, 1.35)),
    )
    .unwrap();
    let die = Object::csg(
        CsgOperation::Difference,
        inner,
        Object::sphere().with_transform(scaling(0.5, 0.5, 0.5)),
    )
    .unwrap();
    let rayforge::Shape::Csg(csg) = &die.shape else {
        unreachable!()
    };
    assert_eq!(csg.leaves().len(), 3);
    assert!(csg.keeps_surface_point(0, point(1.0, 0.2, 0.3)));
    assert!(!csg.keeps_surface_point(0, point(1.0, 0.99, 0.99)));
    assert!(csg.contains_point(point(0.7, 0.0, 0.0)));
    assert!(
        !csg.contains_point(point(0.1, 0.0, 0.0)),
        "inside the removed sphere"
    );
}

/// The cube map of `texture` on every face of a cube 1.2 units across at the origin, unlit
/// (its colour is the texture's), seen face on from 5 units away on a 48-pixel image, so that
/// each pixel covers about six texels of a 64-texel face.
fn render_cube_map(texture: Texture, filter: TextureFilter) -> Vec<Color> {
    use rayforge::math::view_transform;
    use rayforge::raster::RasterOptions;
    use rayforge::shading::UvPattern;
    use rayforge::{vector, Camera, Light, Material, Pattern, PatternKind, World};
    use std::sync::Arc;
    let image = UvPattern::Image(Arc::new(texture));
    let faces = Box::new(std::array::from_fn(|_| image.clone()));
    let cube = Object::cube()
        .with_transform(scaling(0.6, 0.6, 0.6))
        .with_material(Material {
            pattern: Some(Box::new(Pattern::new(PatternKind::CubeMap(faces)))),
            ambient: 1.0,
            diffuse: 0.0,
            specular: 0.0,
            ..Material::DEFAULT
        });
    let world = World {
        objects: vec![cube],
        lights: vec![Light::point(point(0.0, 0.0, -10.0), Color::WHITE)],
        background: Color::new(0.0, 0.0, 1.0),
        ..World::default()
    };
    let camera = Camera::new(48, 48, std::f64::consts::FRAC_PI_3).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let options = RasterOptions {
        filter,
        ..RasterOptions::default()
    };
    let canvas =
        rayforge::raster::render(&camera, &world, &options).expect("within the triangle budget");
    canvas
        .pixels()
        .iter()
        .copied()
        .filter(|c| c.blue == c.red)
        .collect()
}

#[test]
fn cube_maps_are_filtered_like_every_other_image() {
    // Nearest filtering picks a black or a white texel for each pixel; trilinear reads the MIP
    // level whose texels are pixel-sized, where the checkerboard has averaged to grey.
    let grey = |pixels: &[Color]| pixels.iter().filter(|c| (c.red - 0.5).abs() < 0.15).count();
    let nearest = render_cube_map(checkerboard(64, 64), TextureFilter::Nearest);
    let trilinear = render_cube_map(checkerboard(64, 64), TextureFilter::Trilinear);
    assert_eq!(
        nearest.len(),
        trilinear.len(),
        "the same pixels show the cube"
    );
    assert!(nearest.len() > 40, "{} pixels", nearest.len());
    assert_eq!(grey(&nearest), 0);
    assert!(
        grey(&trilinear) * 10 >= trilinear.len() * 9,
        "{} of {} grey",
        grey(&trilinear),
        trilinear.len()
    );
}
