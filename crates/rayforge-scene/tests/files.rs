//! The files a scene names (issue 21, findings 4 and 9): read only from inside the scene's
//! folder unless allowed, never taken for an empty model when they are not one, and images
//! costed against the memory limit from their headers, before they are decoded.

use rayforge_scene::{load_file_with, LoadOptions, SceneError};
use std::path::{Path, PathBuf};

const CAMERA: &str = "- add: camera
  width: 4
  height: 4
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

const MODEL: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fn image_item(file: &str) -> String {
    format!(
        "- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern: {{type: image, file: {file}}}\n"
    )
}

fn environment_item(file: &str) -> String {
    format!("- world:\n    renderer: path\n    environment:\n      file: {file}\n")
}

/// Writes `scene` (after the camera) as `scene.yml` in `dir` and loads it with `options`.
fn load_in(dir: &Path, body: &str, options: &LoadOptions) -> Result<(), SceneError> {
    let path = dir.join("scene.yml");
    std::fs::write(&path, format!("{CAMERA}{body}")).unwrap();
    load_file_with(&path, options).map(|_| ())
}

fn write(path: &Path, bytes: &[u8]) -> PathBuf {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, bytes).unwrap();
    path.to_path_buf()
}

fn allowing_outside() -> LoadOptions {
    LoadOptions {
        allow_outside: true,
        ..LoadOptions::default()
    }
}

/// Finding 9: `file:` took absolute and `../` paths, so a scene could read any file. Now each
/// way out of the scene's folder (an absolute path, `..`, a symbolic link, and the same from
/// inside a model's material library) is an error at the key that names it, which names
/// `--allow-outside`; with it, the same scenes load.
#[test]
fn reading_outside_the_scenes_folder_needs_allow_outside() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("scene");
    let secret = write(&root.path().join("secret.obj"), MODEL);
    write(&root.path().join("secret.mtl"), b"newmtl m\nKd 1 0 0\n");
    write(&root.path().join("secret.ppm"), b"P3\n1 1\n255\n1 2 3\n");
    write(
        &root.path().join("sky.pfm"),
        b"PF\n1 2\n-1\n\0\0\x80\x3f\0\0\x80\x3f\0\0\x80\x3f\0\0\x80\x3f\0\0\x80\x3f\0\0\x80\x3f",
    );
    write(&dir.join("models/inside.obj"), MODEL);
    write(
        &dir.join("models/lib.obj"),
        b"mtllib ../../secret.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    write(
        &dir.join("models/map.mtl"),
        b"newmtl m\nmap_Kd ../../secret.ppm\n",
    );
    write(
        &dir.join("models/map.obj"),
        b"mtllib map.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    std::os::unix::fs::symlink(&secret, dir.join("link.obj")).unwrap();
    std::os::unix::fs::symlink(root.path(), dir.join("up")).unwrap();
    let obj = |file: &str| format!("- add: obj\n  file: {file}\n");
    let cases = [
        (obj("../secret.obj"), "file", 9),
        (obj(&secret.display().to_string()), "file", 9),
        (obj("models/../../secret.obj"), "file", 9),
        (obj("link.obj"), "file", 9),
        (obj("up/secret.obj"), "file", 9),
        (image_item("../secret.ppm"), "file", 13),
        (environment_item("../sky.pfm"), "file", 11),
        (obj("models/lib.obj"), "mtllib", 1),
        (obj("models/map.obj"), "map_Kd", 2),
    ];
    for (body, key, line) in &cases {
        let e = load_in(&dir, body, &LoadOptions::default()).unwrap_err();
        assert!(e.message.contains("outside the scene's folder"), "{e}");
        assert!(e.message.contains("--allow-outside"), "{e}");
        assert_eq!(e.key.as_deref(), Some(*key), "{e}");
        assert_eq!(e.span.map(|s| s.line), Some(*line), "{e}");
        load_in(&dir, body, &allowing_outside()).unwrap_or_else(|e| panic!("{body}: {e}"));
    }
    // Inside the folder, through `..` that stays in it, all is as before.
    load_in(
        &dir,
        &obj("models/../models/inside.obj"),
        &LoadOptions::default(),
    )
    .unwrap();
}

/// Finding 9: a file that is not a model (here `/etc/passwd`-like text, binary bytes, bytes
/// that are not UTF-8, a missing file) was read as an empty model with success. Each is now an
/// error at the scene's `file:`, with no position in the file, so no line of it is shown.
#[test]
fn a_file_that_is_not_a_model_is_an_error_not_an_empty_model() {
    let dir = tempfile::tempdir().unwrap();
    write(
        &dir.path().join("passwd"),
        b"root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1::/:\n",
    );
    write(&dir.path().join("binary.obj"), b"v 0 0 0\0\x01\x02");
    write(&dir.path().join("latin1.obj"), b"v 0 0 0\n# caf\xe9\n");
    write(&dir.path().join("empty.obj"), b"");
    for (file, reason) in [
        ("passwd", "not an OBJ model"),
        ("binary.obj", "binary"),
        ("latin1.obj", "not a UTF-8 text file"),
        ("empty.obj", "not an OBJ model"),
        ("missing.obj", "No such file"),
    ] {
        let e = load_in(
            dir.path(),
            &format!("- add: obj\n  file: {file}\n"),
            &LoadOptions::default(),
        )
        .unwrap_err();
        assert!(e.message.contains(reason), "{file}: {e}");
        // Located at the scene's `file:`, never inside the file named.
        assert_eq!(e.path, dir.path().join("scene.yml"), "{e}");
        assert_eq!(e.key.as_deref(), Some("file"), "{e}");
        assert!(!e.message.contains("root:x"), "{e}");
    }
}

/// Errors about an image or environment map are located at the `file:` of the scene (or the
/// `map_Kd` of a material library), never inside the image, so no display can quote it.
#[test]
fn errors_about_images_carry_no_position_in_the_image() {
    let dir = tempfile::tempdir().unwrap();
    write(
        &dir.path().join("bad.png"),
        b"\x89PNG\r\n\x1a\nsecret\nsecret\n",
    );
    write(&dir.path().join("bad.pfm"), b"PF\nsecret\n");
    for body in [image_item("bad.png"), environment_item("bad.pfm")] {
        let e = load_in(dir.path(), &body, &LoadOptions::default()).unwrap_err();
        assert_eq!(e.path, dir.path().join("scene.yml"), "{e}");
        assert!(e.span.is_some(), "{e}");
    }
    let e = rayforge_scene::texture_from_bytes(b"\x89PNG\r\n\x1a\nsecret", Path::new("a.png"))
        .unwrap_err();
    assert_eq!(e.span, None, "{e}");
}

/// A PNG of `width × height` with the given bit depth and colour type (6: RGBA, 2: RGB), whose
/// IDAT holds `data` (already zlib-compressed).
fn png(width: u32, height: u32, depth: u8, color: u8, interlaced: bool, data: &[u8]) -> Vec<u8> {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[depth, color, 0, 0, u8::from(interlaced)]);
    let mut idat = b"IDAT".to_vec();
    idat.extend_from_slice(data);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for chunk in [&ihdr[..], &idat[..], b"IEND"] {
        png.extend_from_slice(&(chunk.len() as u32 - 4).to_be_bytes());
        png.extend_from_slice(chunk);
        png.extend_from_slice(&crc32(chunk).to_be_bytes());
    }
    png
}

/// An empty zlib stream: a tiny IDAT for an image that claims to be huge.
const TINY_IDAT: &[u8] = b"\x78\x01\x03\x00\x00\x00\x00\x01";

/// `data` as a zlib stream of stored (uncompressed) blocks: enough to build real test PNGs
/// without a compressor.
fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = data.chunks(65_535).collect();
    for (k, block) in blocks.iter().enumerate() {
        out.push(u8::from(k + 1 == blocks.len()));
        let len = block.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &byte in data {
        a = (a + u32::from(byte)) % 65_521;
        b = (b + a) % 65_521;
    }
    out.extend_from_slice(&((b << 16) | a).to_be_bytes());
    out
}

/// The filtered scanlines of an all-black image of `bytes_per_pixel`, in Adam7's seven passes
/// when `interlaced`.
fn black_scanlines(
    width: usize,
    height: usize,
    bytes_per_pixel: usize,
    interlaced: bool,
) -> Vec<u8> {
    let passes: &[(usize, usize, usize, usize)] = if interlaced {
        &[
            (0, 0, 8, 8),
            (4, 0, 8, 8),
            (0, 4, 4, 8),
            (2, 0, 4, 4),
            (0, 2, 2, 4),
            (1, 0, 2, 2),
            (0, 1, 1, 2),
        ]
    } else {
        &[(0, 0, 1, 1)]
    };
    let mut data = Vec::new();
    for &(x0, y0, dx, dy) in passes {
        let w = (width + dx - 1 - x0.min(width)) / dx;
        let h = (height + dy - 1 - y0.min(height)) / dy;
        if w > 0 {
            data.extend(std::iter::repeat_n(0u8, h * (1 + w * bytes_per_pixel)));
        }
    }
    data
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// Finding 4: the memory an image takes is counted exactly, from its header: the file, the
/// decoder's output in the image's own format (16-bit channels and alpha included, interlaced
/// or not) and the 24-byte colours kept; the image that would go over the limit is refused
/// before it is decoded, and one that fits is read.
#[test]
fn image_memory_counts_16_bit_alpha_and_interlaced_images_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (37, 23);
    for (depth, color, bytes_per_pixel) in [(16, 6, 8), (8, 2, 3), (16, 2, 6)] {
        for interlaced in [false, true] {
            let data = zlib_stored(&black_scanlines(w, h, bytes_per_pixel, interlaced));
            let file = png(w as u32, h as u32, depth, color, interlaced, &data);
            write(&dir.path().join("a.png"), &file);
            let cost = file.len() as u64 + (w * h) as u64 * (bytes_per_pixel as u64 + 24);
            let within = |max| LoadOptions {
                max_image_memory: max,
                ..LoadOptions::default()
            };
            load_in(dir.path(), &image_item("a.png"), &within(cost))
                .unwrap_or_else(|e| panic!("depth {depth}, colour {color}: {e}"));
            let e = load_in(dir.path(), &image_item("a.png"), &within(cost - 1)).unwrap_err();
            assert!(e.message.contains(&format!("takes {cost} bytes")), "{e}");
        }
    }
}

/// The bombs of finding 4, each a few hundred bytes whose header claims a huge image.
fn bombs() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new(&mut jpeg)
        .encode(&[0u8; 16 * 16 * 3], 16, 16, image::ExtendedColorType::Rgb8)
        .unwrap();
    // The frame header's height and width, after its marker, length and precision.
    let sof = jpeg.windows(2).position(|w| w == [0xFF, 0xC0]).unwrap();
    let with_size = |w: u16, h: u16| {
        let mut j = jpeg.clone();
        j[sof + 5..sof + 7].copy_from_slice(&h.to_be_bytes());
        j[sof + 7..sof + 9].copy_from_slice(&w.to_be_bytes());
        j
    };
    vec![
        (
            "side.png",
            png(65_535, 65_535, 8, 2, false, TINY_IDAT),
            "pixels on a side",
        ),
        (
            "interlaced.png",
            png(65_535, 65_535, 16, 6, true, TINY_IDAT),
            "pixels on a side",
        ),
        (
            "pixels.png",
            png(16_384, 16_384, 16, 6, false, TINY_IDAT),
            "67108864 pixels",
        ),
        (
            "rgba16.png",
            png(8_192, 8_192, 16, 6, false, TINY_IDAT),
            "takes",
        ),
        (
            "rgba16-interlaced.png",
            png(8_192, 8_192, 16, 6, true, TINY_IDAT),
            "takes",
        ),
        ("side.jpg", with_size(65_535, 65_535), "pixels on a side"),
        ("big.jpg", with_size(8_192, 8_192), "takes"),
        ("big.ppm", b"P6\n8192 8192\n65535\n\0\0\0".to_vec(), "takes"),
        (
            "pixels.ppm",
            b"P6\n16384 16384\n255\n\0\0\0".to_vec(),
            "67108864 pixels",
        ),
    ]
}

/// Finding 4: a 65 KB PNG took 2.4 GB and a 141 KB one 3.9 GB, past the documented limit, and
/// the scene's total was checked only after decoding. Each bomb is now refused from its header
/// with a located error; run in a child process, whose peak memory (VmHWM) stays far below
/// any of the sizes the headers claim.
#[test]
fn image_bombs_are_refused_before_decoding_in_bounded_memory() {
    const CHILD: &str = "RAYFORGE_IMAGE_BOMB_CHILD";
    let dir = tempfile::tempdir().unwrap();
    let bombs = bombs();
    for (name, bytes, _) in &bombs {
        write(&dir.path().join(name), bytes);
    }
    // A limit of 256 MiB: the bombs within the side and pixel limits still ask for more.
    let options = LoadOptions {
        max_image_memory: 256 << 20,
        ..LoadOptions::default()
    };
    if std::env::var_os(CHILD).is_some() {
        for (name, _, reason) in &bombs {
            let e = load_in(dir.path(), &image_item(name), &options).unwrap_err();
            assert!(e.message.contains(reason), "{name}: {e}");
            assert_eq!(e.key.as_deref(), Some("file"), "{name}: {e}");
            assert!(e.span.is_some(), "{name}: {e}");
        }
        // Environment maps too, under the default limit: a PFM and an RGBE file claiming
        // 8192 × 8192 texels (3.5 GiB as a map).
        std::fs::write(dir.path().join("sky.pfm"), b"PF\n8192 8192\n-1\n\0\0\0\0").unwrap();
        std::fs::write(
            dir.path().join("sky.hdr"),
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 8192\n\0\0\0\0",
        )
        .unwrap();
        for sky in ["sky.pfm", "sky.hdr"] {
            let e =
                load_in(dir.path(), &environment_item(sky), &LoadOptions::default()).unwrap_err();
            assert!(e.message.contains("takes"), "{sky}: {e}");
            assert!(e.message.contains("max_image_memory"), "{sky}: {e}");
        }
        let status = std::fs::read_to_string("/proc/self/status").unwrap();
        let peak = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap();
        println!("peak {peak}");
        return;
    }
    let output = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "image_bombs_are_refused_before_decoding_in_bounded_memory",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let kib: u64 = stdout
        .lines()
        .find_map(|l| l.split("VmHWM:").nth(1))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or_else(|| panic!("no peak in {stdout}"));
    // The smallest claim above is 192 MiB of decoder output; the child stays well under it.
    assert!(kib < 128 * 1024, "peak memory {kib} KiB");
    eprintln!("peak memory of the child: {kib} KiB");
}
