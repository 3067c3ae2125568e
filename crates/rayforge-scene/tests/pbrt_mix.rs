//! pbrt-v4's `mix` material read and rendered: inside a closed glowing sphere whose surface
//! mixes two diffuse materials, every pixel converges to `Le / (1 − ρ̄)`, ρ̄ the mix's mean
//! albedo (each bounce picks one material, independently of the last); errors at the
//! parameter.

mod support;

use rayforge_scene::{LoadOptions, Scene, SceneError};

fn load_text(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

/// The closed room, its surface the mix `amount` (a parameter as written) of reflectances 0.8
/// and 0.2, glowing with 0.35 inwards.
fn room(amount: &str) -> String {
    format!(
        "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4\n\
         Integrator \"path\" \"integer maxdepth\" 200\n\
         Camera \"perspective\" \"float fov\" 60\n\
         WorldBegin\n\
         Texture \"quarter\" \"float\" \"constant\" \"float value\" 0.25\n\
         MakeNamedMaterial \"bright\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.8 0.8]\n\
         MakeNamedMaterial \"dark\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.2 0.2 0.2]\n\
         MakeNamedMaterial \"both\" \"string type\" \"mix\" \"string materials\" [\"bright\" \"dark\"] {amount}\n\
         AttributeBegin\n\
         ReverseOrientation\n\
         AreaLightSource \"diffuse\" \"rgb L\" [0.35 0.35 0.35]\n\
         NamedMaterial \"both\"\n\
         Shape \"sphere\" \"float radius\" 10\n\
         AttributeEnd\n"
    )
}

/// The mean of the image's channels.
fn mean(scene: &Scene) -> f64 {
    let film = support::render(scene, 4, 4, 512);
    let canvas = film.resolve();
    let mut sum = 0.0;
    for y in 0..4 {
        for x in 0..4 {
            let c = canvas.pixel_at(x, y);
            sum += c.red + c.green + c.blue;
        }
    }
    sum / 48.0
}

#[test]
fn inside_a_glowing_mixed_room_every_pixel_is_le_over_one_less_the_mean_albedo() {
    // ρ̄ = 0.75 · 0.8 + 0.25 · 0.2 = 0.65: L = 0.35 / 0.35 = 1. (The first material alone
    // gives 1.75, the second 0.44.)
    for amount in ["\"float amount\" 0.25", "\"texture amount\" \"quarter\""] {
        let scene = load_text(&room(amount)).unwrap_or_else(|e| panic!("{e}"));
        let m = mean(&scene);
        assert!((m - 1.0).abs() < 0.02, "{amount}: {m}");
    }
}

#[test]
fn a_mix_names_two_materials_made_before_it_renders() {
    let e = load_text(&room("").replace("[\"bright\" \"dark\"]", "[\"bright\"]")).unwrap_err();
    assert!(e.message.contains("two material names"), "{e}");
    assert_eq!(e.key.as_deref(), Some("string materials"), "{e}");
    let e = load_text(&room("").replace("\"dark\"]", "\"nowhere\"]")).unwrap_err();
    assert!(e.message.contains("nowhere"), "{e}");
    assert_eq!(e.span.map(|s| s.line), Some(8), "{e}");
    // A mix that names itself is refused at its depth limit, not followed for ever.
    let e =
        load_text(&room("").replace("[\"bright\" \"dark\"]", "[\"bright\" \"both\"]")).unwrap_err();
    assert!(e.message.contains("deep"), "{e}");
}
