//! Writes a tessellated sphere of about N triangles as an OBJ file on standard output, to test
//! and measure large meshes: `cargo run --release -p rayforge --example sphere_obj -- 1000000`.

use rayforge::geometry::sphere_mesh;
use std::io::{BufWriter, Write};

fn main() -> std::io::Result<()> {
    let triangles: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let rings = ((triangles / 4) as f64).sqrt().max(2.0) as u32;
    let mesh = sphere_mesh(rings, rings * 2);
    let mut out = BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "# a tessellated unit sphere, {} triangles",
        mesh.faces().len()
    )?;
    for p in mesh.positions() {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for n in mesh.normals() {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    for f in mesh.faces() {
        let [a, b, c] = f.vertices.map(|i| i + 1);
        writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    out.flush()
}
