//! Generates the textures of `scenes/trtc/next-steps/textures/` (an earth-like map, a tiled
//! normal map and the six faces of a sky box) and those of `scenes/cgfs/textures/` (a wooden
//! crate, a floor tile). Every pixel is computed here (procedural noise
//! and closed-form shapes), so the images are ours to commit and can be remade exactly:
//!
//! ```text
//! cargo run -p rayforge-scene --example make_textures -- scenes/trtc/next-steps/textures scenes/cgfs/textures
//! ```

use rayforge::shading::{perlin_noise, CubeFace};
use rayforge::Point3;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "scenes/trtc/next-steps/textures".into()),
    );
    std::fs::create_dir_all(&dir)?;
    save(&dir, "earth.png", 512, 256, earth)?;
    save(&dir, "tiles-normal.png", 256, 256, tiles_normal)?;
    for face in CubeFace::ALL {
        let name = format!("sky-{}.png", face_name(face));
        save(&dir, &name, 128, 128, |u, v| {
            sky(cube_direction(face, u, v))
        })?;
    }
    let crate_dir = PathBuf::from(
        std::env::args()
            .nth(2)
            .unwrap_or_else(|| "scenes/cgfs/textures".into()),
    );
    std::fs::create_dir_all(&crate_dir)?;
    save(&crate_dir, "crate.png", 256, 256, wooden_crate)?;
    save(&crate_dir, "floor-tile.png", 64, 64, floor_tile)?;
    Ok(())
}

/// A floor tile for the texture-filtering stage: a cream tile with a slate diamond inlay,
/// framed by dark grout. Coarse on purpose (64 texels), so that close up a texel covers many
/// pixels and nearest filtering shows its steps along the diamond's diagonal edges, which
/// bilinear filtering smooths; towards the horizon, where a pixel spans many tiles, the grout
/// lines and diamonds alias into moiré unless a MIP map averages them. The edge texels are all
/// grout, so tiles repeated side by side meet without a seam.
fn floor_tile(u: f64, v: f64) -> [f64; 3] {
    let (x, y) = ((u * 63.0).round(), (v * 63.0).round());
    let inside = |t: f64| (3.0..=60.0).contains(&t);
    let grout = !inside(x) || !inside(y);
    if grout {
        return [0.16, 0.13, 0.11];
    }
    if (u - 0.5).abs() + (v - 0.5).abs() < 0.3 {
        [0.18, 0.24, 0.36]
    } else {
        [0.93, 0.89, 0.78]
    }
}

/// A wooden crate's face: a frame of boards around five horizontal planks and a diagonal
/// brace, with grain from stretched noise and dark gaps between boards.
fn wooden_crate(u: f64, v: f64) -> [f64; 3] {
    let frame = 0.12;
    let on_frame = u < frame || u > 1.0 - frame || v < frame || v > 1.0 - frame;
    let brace = (u - v).abs() < 0.07 && !on_frame;
    let (along, across) = if on_frame {
        if u < frame || u > 1.0 - frame {
            (v, u)
        } else {
            (u, v)
        }
    } else if brace {
        ((u + v) * 0.5, u - v)
    } else {
        (u, v)
    };
    let grain = fbm(Point3::new(along * 3.0, across * 40.0, 7.0)) * 0.5 + 0.5;
    let mut c = mix([0.52, 0.34, 0.17], [0.78, 0.58, 0.34], grain);
    if on_frame || brace {
        c = c.map(|x| x * 0.85);
    }
    // Gaps: between the planks of the middle, and at the frame's inner edge.
    let plank = (v - frame) / (1.0 - 2.0 * frame) * 5.0;
    let plank_gap = !on_frame && !brace && plank.fract() < 0.03;
    let edge = |t: f64| (t - frame).abs() < 0.006 || (t - (1.0 - frame)).abs() < 0.006;
    if plank_gap || edge(u) || edge(v) {
        c = [0.2, 0.12, 0.06];
    }
    c
}

/// Writes a `width × height` PNG whose pixel at (u, v) (the book's texture convention: u to the
/// right, v up, both in [0, 1] from edge pixel centre to edge pixel centre) is `shade(u, v)`.
fn save(
    dir: &Path,
    name: &str,
    width: u32,
    height: u32,
    shade: impl Fn(f64, f64) -> [f64; 3],
) -> Result<(), image::ImageError> {
    let image = image::RgbImage::from_fn(width, height, |x, y| {
        let u = x as f64 / (width - 1) as f64;
        let v = 1.0 - y as f64 / (height - 1) as f64;
        let c = shade(u, v);
        image::Rgb(c.map(|channel| (channel.clamp(0.0, 1.0) * 255.0).round() as u8))
    });
    image.save(dir.join(name))?;
    println!("wrote {}", dir.join(name).display());
    Ok(())
}

/// Fractal noise: four octaves of Perlin noise.
fn fbm(p: Point3) -> f64 {
    (0..4)
        .map(|octave| {
            let scale = f64::from(1u32 << octave);
            perlin_noise(p * scale) / scale
        })
        .sum()
}

fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
}

/// An equirectangular map of an invented planet: noise on the sphere itself (so the map has
/// no seam), oceans shading to deep blue, land from green lowlands to brown highlands, ice
/// towards the poles. Laid out for the book's spherical mapping.
fn earth(u: f64, v: f64) -> [f64; 3] {
    let longitude = (u - 0.5) * 2.0 * PI;
    let latitude = (v - 0.5) * PI;
    let p = Point3::new(
        latitude.cos() * longitude.sin(),
        latitude.sin(),
        latitude.cos() * longitude.cos(),
    );
    let height = fbm(p * 2.2 + Point3::new(3.1, 0.7, -1.9));
    let ice = latitude.abs() > 1.2 + 0.15 * fbm(p * 6.0);
    if ice {
        return [0.93, 0.95, 0.97];
    }
    if height < -0.02 {
        mix([0.02, 0.09, 0.32], [0.1, 0.35, 0.6], (height + 0.5) / 0.48)
    } else {
        let land = mix([0.2, 0.5, 0.15], [0.45, 0.35, 0.2], (height + 0.02) / 0.4);
        mix(land, [0.85, 0.85, 0.82], (height - 0.55) / 0.1)
    }
}

/// A normal map of 4 × 4 square tiles with bevelled edges and a faint dimple in each, in the
/// OpenGL convention (red along u, green along v, blue out of the surface).
fn tiles_normal(u: f64, v: f64) -> [f64; 3] {
    let height = |u: f64, v: f64| {
        let (fu, fv) = ((u * 4.0).rem_euclid(1.0), (v * 4.0).rem_euclid(1.0));
        let edge = fu.min(1.0 - fu).min(fv.min(1.0 - fv));
        let bevel = (edge / 0.08).min(1.0);
        let (du, dv) = (fu - 0.5, fv - 0.5);
        bevel - 0.15 * (-(du * du + dv * dv) * 20.0).exp()
    };
    let h = 1.0 / 1024.0;
    let slope_u = (height(u + h, v) - height(u - h, v)) / (2.0 * h);
    let slope_v = (height(u, v + h) - height(u, v - h)) / (2.0 * h);
    let (x, y, z) = (-slope_u * 0.02, -slope_v * 0.02, 1.0);
    let length = (x * x + y * y + z * z).sqrt();
    [x / length, y / length, z / length].map(|c| 0.5 + 0.5 * c)
}

fn face_name(face: CubeFace) -> &'static str {
    match face {
        CubeFace::Left => "left",
        CubeFace::Front => "front",
        CubeFace::Right => "right",
        CubeFace::Back => "back",
        CubeFace::Up => "up",
        CubeFace::Down => "down",
    }
}

/// The direction from the cube's centre through (u, v) of a face: the inverse of the book's
/// `cube_uv_*` functions.
fn cube_direction(face: CubeFace, u: f64, v: f64) -> Point3 {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    match face {
        CubeFace::Front => Point3::new(a, b, 1.0),
        CubeFace::Back => Point3::new(-a, b, -1.0),
        CubeFace::Left => Point3::new(-1.0, b, a),
        CubeFace::Right => Point3::new(1.0, b, -a),
        CubeFace::Up => Point3::new(a, 1.0, -b),
        CubeFace::Down => Point3::new(a, -1.0, b),
    }
    .normalize()
}

/// A clear sky seen along `d`: deep blue overhead, pale at the horizon, a sun, wisps of cloud,
/// and dark ground below.
fn sky(d: Point3) -> [f64; 3] {
    let sun = Point3::new(0.5, 0.45, 0.74).normalize();
    if d.y < 0.0 {
        let ground = mix([0.36, 0.32, 0.26], [0.16, 0.14, 0.12], (-d.y * 3.0).sqrt());
        return mix([0.75, 0.8, 0.85], ground, -d.y * 12.0);
    }
    let mut c = mix([0.78, 0.86, 0.95], [0.16, 0.36, 0.75], d.y.sqrt());
    let cloud = (fbm(d / (d.y + 0.15) * 0.6) - 0.05).max(0.0) * 2.5 * (d.y * 4.0).min(1.0);
    c = mix(c, [1.0, 1.0, 1.0], cloud);
    let glow = d.dot(sun).max(0.0).powf(256.0);
    let disc = if d.dot(sun) > 0.9992 { 1.0 } else { 0.0 };
    mix(c, [1.0, 0.97, 0.85], glow + disc)
}
