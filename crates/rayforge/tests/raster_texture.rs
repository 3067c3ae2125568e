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
