//! Fundamentals of Ray Tracing (Don Cross): `rayforge render scenes/fundamentals/NAME.yml` at
//! the original program's size, zoom and anti-aliasing.
//!
//! Each render is pinned by a hash of its pixels. The hashes were taken from renders compared
//! pixel by pixel with the images the author's own program writes (built from its public
//! source; `docs/fidelity.md` gives the measured differences: none for seven of these scenes).

mod support;
use support::{fnv1a, render_scene};

/// Renders `scenes/fundamentals/<name>.yml` at its own size.
fn render(name: &str) -> image::RgbImage {
    render_scene(&format!("fundamentals/{name}"))
}

#[test]
fn the_test_commands_scenes_render_as_pinned() {
    let expected: [(&str, (u32, u32), u64); 16] = [
        ("sphere", (400, 400), 0xb348_eeec_6cba_4604),
        ("cuboid", (300, 300), 0x7e87_a204_c11a_1c68),
        ("spheroid", (300, 300), 0x7917_771d_a871_039d),
        ("cylinder", (300, 300), 0x6f76_08f3_ac2d_641e),
        ("torus1", (420, 300), 0xe56a_6175_5084_d100),
        ("torus2", (420, 300), 0xe8c9_7334_7f09_b67a),
        ("intersection", (300, 300), 0x8e36_bf97_7109_2b52),
        ("difference", (300, 300), 0xc3e1_8f9e_2440_7f7c),
        ("donutbite", (300, 300), 0xde09_fe87_1858_c3b7),
        ("multisphere", (400, 300), 0x662f_c71c_7d0e_9f7d),
        ("polyhedra", (600, 300), 0x04a7_9efd_fe7f_e06b),
        ("overlap", (400, 300), 0xbedc_cfef_1c72_1bcd),
        ("saturn", (500, 250), 0x2a68_6228_945f_dfce),
        ("block", (320, 400), 0xb300_15a5_f025_a944),
        ("kaleid", (600, 600), 0xedf4_7e11_6597_2c69),
        ("chessboard", (600, 360), 0x5662_1a29_46bb_717d),
    ];
    let mut wrong = Vec::new();
    for (name, size, hash) in expected {
        let image = render(name);
        assert_eq!(image.dimensions(), size, "{name}");
        let got = fnv1a(image.as_raw());
        if got != hash {
            wrong.push(format!("(\"{name}\", {size:?}, {got:#018x})"));
        }
    }
    assert!(wrong.is_empty(), "changed renders: {}", wrong.join(", "));
}

#[test]
fn automatic_exposure_makes_the_brightest_channel_full() {
    // The matte sphere (0.6, 0.2, 0.2) under the light (0.5, 1.0, 0.3) reflects (0.3, 0.2,
    // 0.06) of it: red is the brightest channel, and its brightest point becomes 255.
    let image = render("sphere");
    let brightest = image.pixels().map(|p| p.0[0]).max().unwrap();
    assert_eq!(brightest, 255);
    // The background stays black.
    assert_eq!(image.get_pixel(0, 0).0, [0, 0, 0]);
}
