//! The path tracer's light samplers (`light-sampler: uniform | power | bvh`) render the same
//! image: each is unbiased, so the mean of a small many-light scene agrees between them
//! within its noise.

mod support;

use rayforge::options::{LightSamplerKind, SampleAllocation};
use rayforge_scene::Scene;
use std::path::Path;
use support::render;

/// Twenty-four small lamps of differing brightness over a floor, one-sided squares facing
/// down, two-sided sheets and balls, a wall between some of them and the rest (light the tree
/// cannot foresee) and a grey box under them: light found by next-event estimation, by the
/// BSDF's sampling (weighed by MIS with the pick's probability from the vertex before) and
/// by later bounces.
fn many_lamps() -> Scene {
    let mut text = String::from(
        "- world:\n    renderer: path\n    background: [0, 0, 0]\n    sample-allocation: uniform\n\
         - add: camera\n  width: 20\n  height: 15\n  field-of-view-degrees: 70\n\
         \x20 from: [0, 4, 5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n\
         - add: rectangle\n  material: { type: diffuse, color: [0.6, 0.6, 0.6] }\n\
         \x20 transform: [[scale, 4, 1, 4]]\n\
         - add: cube\n  material: { type: diffuse, color: [0.7, 0.7, 0.7] }\n\
         \x20 transform: [[scale, 0.05, 0.8, 2], [translate, 0.5, 0.8, 0]]\n\
         - add: cube\n  material: { type: diffuse, color: [0.5, 0.5, 0.5] }\n\
         \x20 transform: [[scale, 0.4, 0.4, 0.4], [translate, -1.5, 0.4, 1]]\n",
    );
    for i in 0..24 {
        let (x, z) = ((i % 6) as f64 - 2.5, (i / 6) as f64 - 1.5);
        let y = 1.0 + 0.2 * (i % 3) as f64;
        let bright = [1.0, 4.0, 16.0][i % 3] * (1.0 + (i % 5) as f64);
        let (shape, side, size) = match i % 4 {
            3 => ("sphere", "front", 0.08),
            1 => ("rectangle", "both", 0.12),
            _ => ("rectangle", "front", 0.12),
        };
        text += &format!(
            "- add: {shape}\n  material: {{ type: diffuse, color: [0, 0, 0], \
             emission: [{bright}, {g}, {b}], emission-side: {side} }}\n  \
             transform: [[scale, {size}, {size}, {size}], [rotate-x, 3.1415926536], \
             [translate, {x}, {y}, {z}]]\n",
            g = bright * 0.8,
            b = bright * 0.5,
        );
    }
    rayforge_scene::load_str(&text, Path::new("many-lamps.yml")).unwrap()
}

/// The mean over the image of each of `batches` renders of `spp` samples per pixel, each
/// with its own seed, picking lights by `kind`.
fn batch_means(scene: &Scene, kind: LightSamplerKind, batches: u64, spp: u64) -> Vec<f64> {
    (0..batches)
        .map(|seed| {
            let mut scene = scene.clone();
            let options = scene.path.as_mut().unwrap();
            options.light_sampler = kind;
            options.seed = seed;
            let film = render(&scene, 20, 15, spp).resolve();
            let pixels = film.pixels();
            let sum: f64 = pixels.iter().map(|c| c.red + c.green + c.blue).sum();
            sum / (3 * pixels.len()) as f64
        })
        .collect()
}

/// The mean of `values` and its standard error.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn the_three_light_samplers_give_one_image_mean_within_noise() {
    let scene = many_lamps();
    assert_eq!(scene.path.unwrap().allocation, SampleAllocation::Uniform);
    let estimates: Vec<(LightSamplerKind, (f64, f64))> = [
        LightSamplerKind::Uniform,
        LightSamplerKind::Power,
        LightSamplerKind::Bvh,
    ]
    .into_iter()
    .map(|kind| (kind, mean_and_error(&batch_means(&scene, kind, 10, 32))))
    .collect();
    for (i, (a, (mean_a, se_a))) in estimates.iter().enumerate() {
        assert!(*mean_a > 0.0 && *se_a > 0.0, "{a:?}: {mean_a} ± {se_a}");
        for (b, (mean_b, se_b)) in &estimates[i + 1..] {
            // Ten batches each: a difference of more than 4.5 standard errors (of Student's t
            // with about 18 degrees of freedom, a chance below 1 in 3,000) is a bias.
            let z = (mean_a - mean_b).abs() / (se_a * se_a + se_b * se_b).sqrt();
            assert!(
                z < 4.5,
                "{a:?} {mean_a} ± {se_a} against {b:?} {mean_b} ± {se_b}: {z:.1} errors apart"
            );
        }
    }
    // Each mean is known to 2 % at worst: a sampler off by an eighth (4.5 combined errors)
    // could not pass.
    for (kind, (mean, se)) in &estimates {
        assert!(se / mean < 0.02, "{kind:?}: {mean} ± {se}");
    }
}
