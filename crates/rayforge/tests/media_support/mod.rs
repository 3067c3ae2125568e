//! What the participating-media tests share: per-channel means of a film and their check,
//! a homogeneous medium, a ball bounding a medium, Henyey–Greenstein's density and the single
//! scattering of a point light by numerical integration. Included by `mod media_support;`.
#![allow(dead_code)]

use rayforge::film::Film;
use rayforge::math::{scaling, translation, Point3};
use rayforge::media::{HenyeyGreenstein, Homogeneous, Medium, MediumId, MediumInterface};
use rayforge::{point, Color, Object, World};

/// Per channel: the mean over the pixels and its standard error.
pub fn channel_means(film: &Film) -> [(f64, f64); 3] {
    let canvas = film.resolve();
    let mut out = [(0.0, 0.0); 3];
    for (c, o) in out.iter_mut().enumerate() {
        let values: Vec<f64> = (0..canvas.height())
            .flat_map(|y| (0..canvas.width()).map(move |x| (x, y)))
            .map(|(x, y)| canvas.pixel_at(x, y).to_array()[c])
            .collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        *o = (mean, (var / n).sqrt());
    }
    out
}

/// Fails unless each channel's mean is within four standard errors of `expected`, and that
/// error small enough to judge by.
pub fn assert_means(film: &Film, expected: [f64; 3], what: &str) {
    for (c, (mean, se)) in channel_means(film).into_iter().enumerate() {
        assert!(
            (mean - expected[c]).abs() <= 4.0 * se,
            "{what}: channel {c} is {mean} ± {se}, expected {}",
            expected[c]
        );
        assert!(
            se < 0.05 * expected[c].max(1e-3),
            "{what}: channel {c} too noisy to judge: {se}"
        );
    }
}

pub fn homogeneous(sigma_a: Color, sigma_s: Color, g: f64) -> Medium {
    Medium::Homogeneous(Homogeneous {
        sigma_a,
        sigma_s,
        emission: Color::BLACK,
        phase: HenyeyGreenstein::new(g),
    })
}

/// A sphere of `radius` about `centre` that only bounds `medium` (inside, vacuum outside).
pub fn medium_ball(world: &mut World, medium: Medium, radius: f64, centre: [f64; 3]) -> MediumId {
    let id = world.media.add(medium).expect("id");
    let [x, y, z] = centre;
    let mut ball =
        Object::sphere().with_transform(translation(x, y, z) * scaling(radius, radius, radius));
    ball.media = Some(MediumInterface {
        inside: Some(id),
        outside: None,
        index_matched: true,
    });
    world.objects.push(ball);
    id
}

/// Henyey–Greenstein's density at the cosine `cos` between travel and scattered directions.
pub fn hg(cos: f64, g: f64) -> f64 {
    let d = 1.0 + g * g - 2.0 * g * cos;
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * d * d.sqrt())
}

/// Single scattering of a point light of intensity 1 at `light`, seen along +z from the origin
/// through a homogeneous medium out to 10 (the ball's radius): per channel
/// L = ∫ σs e^(−σt t) p(θ) π e^(−σt d) ∕ d² dt, by the midpoint rule in `steps` steps.
pub fn single_scattering(
    sigma_a: Color,
    sigma_s: Color,
    g: f64,
    light: Point3,
    steps: usize,
) -> [f64; 3] {
    let mut expected = [0.0; 3];
    for (c, e) in expected.iter_mut().enumerate() {
        let s = sigma_s.to_array()[c];
        let sigma_t = s + sigma_a.to_array()[c];
        let dt = 10.0 / steps as f64;
        for i in 0..steps {
            let t = (i as f64 + 0.5) * dt;
            let to_light = light - point(0.0, 0.0, t);
            let d = to_light.length();
            let cos = to_light.z / d;
            *e +=
                s * (-sigma_t * t).exp() * hg(cos, g) * std::f64::consts::PI * (-sigma_t * d).exp()
                    / (d * d)
                    * dt;
        }
    }
    expected
}
