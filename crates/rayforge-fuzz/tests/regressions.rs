//! Inputs the fuzzer found that crashed, hung or crawled, minimised, each with what it gets
//! now. They run through the same targets as the fuzzer (reader, then a tiny render).

use rayforge_fuzz::corpus::palette_png_with;
use rayforge_fuzz::targets;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::Path;

/// The system allocator, counting the bytes each thread asks for: a deterministic measure of
/// the work a reader does, whatever the machine's speed (a timing bound would be one).
struct Counting;

thread_local! {
    /// Bytes allocated by this thread so far.
    static ALLOCATED: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: every call is passed to `System` unchanged; only a thread-local count is added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATED.with(|a| a.set(a.get() + layout.size() as u64));
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATED.with(|a| a.set(a.get() + new_size as u64));
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// The bytes `work` allocates on this thread.
fn bytes_allocated<T>(work: impl FnOnce() -> T) -> (T, u64) {
    let before = ALLOCATED.with(Cell::get);
    let out = work();
    (out, ALLOCATED.with(Cell::get) - before)
}

/// Found by the fuzzer of the time (a seeded mutator, before bolero) in its first second: a palette whose
/// length is not a multiple of three panics inside the png crate (0.18.1, palette.rs:74,
/// "range end index 3 out of range for slice of length 2"). The texture reader catches the
/// decoder's panic and reports a damaged image.
#[test]
fn a_png_palette_of_a_length_not_a_multiple_of_three_is_a_damaged_image() {
    for palette in [&[255u8, 0, 0, 0, 255][..], &[1, 2, 3, 4]] {
        let png = palette_png_with(palette);
        let e = rayforge_scene::texture_from_bytes(&png, Path::new("bad.png"))
            .expect_err("a damaged palette is refused");
        assert!(e.message.contains("damaged"), "{e}");
        assert!(!targets::image(&png));
    }
    // Shorter than one colour, the png crate itself finds the chunk too short.
    let png = palette_png_with(&[9, 9]);
    assert!(!targets::image(&png));
    // The same file with a whole palette decodes.
    let fine = palette_png_with(&[255, 0, 0, 0, 255, 0]);
    assert!(targets::image(&fine));
}

#[test]
fn a_png_with_a_damaged_palette_in_a_scene_is_a_located_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.png"), palette_png_with(&[1, 2, 3, 4])).unwrap();
    let scene = "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: sphere\n  material:\n    pattern:\n      type: map\n      mapping: spherical\n      uv_pattern:\n        type: image\n        file: bad.png\n";
    let e = rayforge_scene::load_str(scene, &dir.path().join("s.yml")).unwrap_err();
    let span = e.span.expect("located");
    assert_eq!((span.line, e.key.as_deref()), (15, Some("file")), "{e}");
    assert!(e.message.contains("damaged"), "{e}");
}

/// Found while writing the OBJ target: a model naming many groups and materials took
/// quadratic time (a linear search per name, and a vertex table as long as the whole file's
/// per group and material: 50,000 groups were 50,000 × 150,000 entries). It now takes work
/// in proportion to the file: twice the groups allocate at most about twice the bytes
/// (a table per mesh would make it four times). The count is the reader's own and the
/// meshes' (one triangle each, built on this thread), so it does not depend on the machine,
/// the build or the other tests.
#[test]
fn many_groups_and_materials_take_linear_time() {
    let model = |groups: usize| {
        let mut obj = String::new();
        for i in 0..groups {
            obj += &format!("v {i} 0 0\nv {i} 1 0\nv {i} 0 1\ng g{i}\nusemtl m{i}\nf -3 -2 -1\n");
        }
        obj
    };
    let read = |groups: usize| {
        let obj = model(groups);
        let ((parsed, meshes), bytes) = bytes_allocated(|| {
            let parsed = rayforge_scene::obj::parse_obj(&obj, Path::new("many.obj")).unwrap();
            let meshes = rayforge_scene::obj::to_meshes(&parsed);
            (parsed, meshes)
        });
        assert_eq!((parsed.groups.len(), meshes.len()), (groups + 1, groups));
        bytes
    };
    let (small, large) = (read(10_000), read(20_000));
    let growth = large as f64 / small as f64;
    assert!(
        growth < 2.5,
        "twice the groups allocated {growth:.2} times the bytes ({small} → {large})"
    );
}

/// A pbrt-v4 scene of one medium `medium` (parameters after its type), the camera in it.
fn pbrt_medium(medium: &str) -> String {
    format!(
        "LookAt 0 0 -2  0 0 0  0 1 0\nMediumInterface \"\" \"m\"\nCamera \"perspective\"\n\
         WorldBegin\nMakeNamedMedium \"m\" \"string type\" {medium}\n"
    )
}

/// The error reading `text` as the file `name` of a folder of its own gives.
fn refusal(name: &str, text: &str) -> rayforge_scene::SceneError {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    match rayforge_scene::load_file(&path) {
        Ok(_) => panic!("`{text}` was read"),
        Err(e) => e,
    }
}

/// Found by writing the media target: an `rgbgrid` whose `nx × ny × nz` passes 2⁶⁴ (three
/// sizes of 2³¹ − 1, the largest integers pbrt-v4 writes) overflowed the product of the sizes
/// (a panic in a debug build, "attempt to multiply with overflow", media.rs; a wrapped count
/// in a release build) before any check. It is refused at the medium, naming the limit's flag.
#[test]
fn an_rgbgrid_whose_samples_overflow_is_refused_at_its_sizes() {
    let scene = pbrt_medium(
        "\"rgbgrid\" \"integer nx\" 2147483647 \"integer ny\" 2147483647 \"integer nz\" 2147483647 \"rgb sigma_a\" [1 1 1]",
    );
    assert!(!targets::media(scene.as_bytes()));
    let e = refusal("m.pbrt", &scene);
    assert!(
        e.message
            .contains("2147483647 × 2147483647 × 2147483647 samples")
            && e.message.contains("--max-grid-samples"),
        "{e}"
    );
}

/// The same for a `uniformgrid` past the limit without overflowing: refused from its sizes,
/// before its density is looked at.
#[test]
fn a_uniformgrid_past_the_sample_limit_is_refused_from_its_sizes() {
    let scene = pbrt_medium(
        "\"uniformgrid\" \"integer nx\" 1024 \"integer ny\" 1024 \"integer nz\" 1024 \"float density\" [1]",
    );
    let e = refusal("m.pbrt", &scene);
    assert!(e.message.contains("past the limit of 134217728"), "{e}");
}

/// Found by writing the media target: a `.vol` file whose header gives three sizes of
/// 2³¹ − 1 overflowed the product of the sizes (a panic in a debug build) before its limit
/// was asked. It is refused at the `file:` that names it.
#[test]
fn a_vol_file_whose_samples_overflow_is_refused_at_its_file_key() {
    let vol = rayforge_fuzz::targets::media::vol([i32::MAX; 3], &[1.0; 4]);
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("huge.vol"), vol).unwrap();
    let scene = "- medium: m\n  type: grid\n  file: huge.vol\n";
    let path = dir.path().join("m.yml");
    std::fs::write(&path, scene).unwrap();
    let e = rayforge_scene::load_file(&path).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("file"), "{e}");
    assert!(e.message.contains("--max-grid-samples"), "{e}");
    // And through the target, whose folder always holds such a file.
    let scene = "- medium: m\n  type: grid\n  file: huge.vol\n- add: camera\n  width: 3\n  height: 2\n  field-of-view: 1\n  from: [0, 0, -2]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n";
    assert!(!targets::media(scene.as_bytes()));
}

/// Found by the media target in its first 30 seconds (`BOLERO_RANDOM_SEED=
/// 156354180388458201715630867705602668789`): a pbrt-v4 sphere of radius 1e300 (and a
/// cylinder's, a disk's sizes likewise) was placed by a scale whose determinant is infinite,
/// and `Transform::new` panicked ("the transform is too large"); one of radius 1e-300, whose
/// determinant is 0, the same. Each is refused at its shape.
#[test]
fn a_pbrt_shape_too_large_or_small_to_place_is_refused_at_the_shape() {
    for shape in [
        "\"sphere\" \"float radius\" 1e300",
        "\"sphere\" \"float radius\" 1e-300",
        "\"cylinder\" \"float radius\" 1e300",
    ] {
        let scene = format!("Camera \"perspective\"\nWorldBegin\nShape {shape}\n");
        assert!(!targets::media(scene.as_bytes()), "{shape}");
        let e = refusal("s.pbrt", &scene);
        assert!(e.message.contains("size cannot be used"), "{shape}: {e}");
        assert_eq!(e.span.map(|s| s.line), Some(3), "{shape}: {e}");
    }
}
