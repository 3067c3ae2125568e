//! The primary rays both sides trace: a pinhole camera (rayforge's own, the book's) framing a
//! mesh, its rays listed in 8×8 screen tiles so that consecutive rays are coherent, as a
//! renderer that traces tiles would cast them.

use super::shapes::Soup;
use rayforge::math::view_transform;
use rayforge::{point, vector, Camera, Ray};

/// Pixels per side of a tile of rays.
const TILE: usize = 8;

/// One ray as the rays file stores it: origin xyz, direction xyz.
pub type StoredRay = [f32; 6];

/// The camera's rays through every pixel centre of a `width`×`height` image, tile by tile,
/// framing `soup` from the front, a little above: 60° across the image, far enough that its
/// bounding sphere just fills the image's height.
pub fn framing_rays(soup: &Soup, width: usize, height: usize) -> Vec<StoredRay> {
    let (centre, radius) = soup.bounding_sphere();
    let fov = std::f64::consts::FRAC_PI_3;
    let camera = Camera::new(width, height, fov);
    // The half-angle the image spans vertically (the field of view spans the longer side).
    let half_view = (fov / 2.0).tan();
    let aspect = width as f64 / height as f64;
    let half_vertical = if aspect >= 1.0 {
        (half_view / aspect).atan()
    } else {
        half_view.atan()
    };
    let distance = radius / half_vertical.sin();
    let from = centre + vector(0.0, 0.35, -1.0).normalize() * distance;
    let camera = camera.with_transform(view_transform(from, centre, vector(0.0, 1.0, 0.0)));
    tiled(width, height, |x, y| camera.ray_for_pixel(x, y))
}

/// Rays for every pixel, 8×8 tiles in rows of tiles, pixels in rows within a tile.
fn tiled(width: usize, height: usize, ray: impl Fn(usize, usize) -> Ray) -> Vec<StoredRay> {
    let mut rays = Vec::with_capacity(width * height);
    for ty in (0..height).step_by(TILE) {
        for tx in (0..width).step_by(TILE) {
            for y in ty..(ty + TILE).min(height) {
                for x in tx..(tx + TILE).min(width) {
                    let r = ray(x, y);
                    rays.push([
                        r.origin.x as f32,
                        r.origin.y as f32,
                        r.origin.z as f32,
                        r.direction.x as f32,
                        r.direction.y as f32,
                        r.direction.z as f32,
                    ]);
                }
            }
        }
    }
    rays
}

/// A stored ray as rayforge traces it: the same `f32` values, widened.
#[inline]
pub fn to_ray(r: &StoredRay) -> Ray {
    Ray::new(
        point(r[0] as f64, r[1] as f64, r[2] as f64),
        vector(r[3] as f64, r[4] as f64, r[5] as f64),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pixel_gets_one_ray_tile_by_tile() {
        let rays = tiled(10, 9, |x, y| {
            Ray::new(point(x as f64, y as f64, 0.0), vector(0.0, 0.0, 1.0))
        });
        assert_eq!(rays.len(), 90);
        // The first tile is 8×8, then the 2-pixel-wide tile beside it.
        assert_eq!(rays[7][..2], [7.0, 0.0]);
        assert_eq!(rays[8][..2], [0.0, 1.0]);
        assert_eq!(rays[64][..2], [8.0, 0.0]);
        let mut seen: Vec<(u32, u32)> = rays.iter().map(|r| (r[0] as u32, r[1] as u32)).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 90);
    }

    #[test]
    fn the_framing_camera_sees_the_mesh_in_the_middle() {
        let soup = super::super::shapes::bumpy_sphere(500);
        let mesh = soup.to_mesh().unwrap();
        let rays = framing_rays(&soup, 32, 18);
        let hits = rays
            .iter()
            .filter(|r| mesh.closest_hit(&to_ray(r), 0.0, f64::INFINITY).is_some())
            .count();
        // The sphere fills the height of a 16:9 image: about a third of the rays hit it.
        assert!(hits > rays.len() / 5 && hits < rays.len() / 2, "{hits}");
    }
}
