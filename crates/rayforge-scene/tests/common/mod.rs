//! What the streaming tests share.

/// The camera item the scenes start with.
pub const CAMERA: &str = "- add: camera
  width: 40
  height: 20
  field-of-view: 1.2
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
";

/// `n` spheres, each its own item with its own transform and colour, the way a generated
/// scene places many objects, after a camera and a material every tenth one names.
pub fn many_items(n: usize) -> String {
    let mut text = String::from(CAMERA);
    text += "- define: shiny\n  value:\n    specular: 0.9\n    shininess: 200\n";
    for i in 0..n {
        let (x, z) = ((i % 100) as f64 * 0.3, (i / 100) as f64 * 0.3);
        let material = if i % 10 == 0 {
            "shiny".to_string()
        } else {
            format!(
                "\n    color: [{:.3}, 0.5, {:.3}]\n    diffuse: 0.7",
                (i % 7) as f64 / 7.0,
                (i % 11) as f64 / 11.0
            )
        };
        text += &format!(
            "- add: sphere\n  transform:\n    - [scale, 0.1, 0.1, 0.1]\n    - [rotate-y, {:.4}]\n    \
             - [translate, {x:.3}, 0, {z:.3}]\n  material: {material}\n",
            (i % 13) as f64 / 2.0,
        );
    }
    text
}
