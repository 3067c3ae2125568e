//! OIDN through rayforge's loader, on an image made here: a smooth analytic picture (two
//! soft-edged discs on a gradient, lit unevenly) with its albedo and normal guides, and the
//! same picture with seeded Gaussian noise of a known spread. Run where the library is
//! installed (`tools/oidn/install.sh`); elsewhere each test says on stderr that it skipped,
//! unless `RAYFORGE_REQUIRE_OIDN` is set or `CI` is `true`, where the library's absence fails.

use rayforge_denoise::{DenoiseError, Denoiser, Images, LIBRARY_FILE};
use std::path::PathBuf;

const W: usize = 64;
const H: usize = 48;

/// The denoiser, or `None` (having said so) where it is not installed and not required.
fn denoiser(test: &str) -> Option<Denoiser> {
    match Denoiser::load() {
        Ok(d) => Some(d),
        Err(e) => {
            let required = std::env::var_os("RAYFORGE_REQUIRE_OIDN").is_some()
                || std::env::var("CI").is_ok_and(|v| v == "true");
            assert!(!required, "OIDN is required here: {e}");
            // Straight to stderr, past the harness's capture: a skip is seen, not taken for a
            // pass.
            use std::io::Write;
            let _ = writeln!(
                std::io::stderr(),
                "skipped: {test}: Intel Open Image Denoise is not installed \
                 (tools/oidn/install.sh)"
            );
            None
        }
    }
}

/// SplitMix64, seeded: the noise is the same on every run.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A standard normal draw (Box–Muller).
    fn gaussian(&mut self) -> f64 {
        let (u, v) = (1.0 - self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The clean picture, its albedo and its normals (each W × H × 3 floats, rows from the top).
fn scene() -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let (mut color, mut albedo, mut normal) = (vec![], vec![], vec![]);
    let discs = [
        ((20.0, 20.0), 12.0, [0.8, 0.3, 0.2]),
        ((44.0, 28.0), 14.0, [0.2, 0.5, 0.8]),
    ];
    for y in 0..H {
        for x in 0..W {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let mut a = [0.6, 0.6, 0.55];
            let mut n = [0.0, 1.0, 0.0];
            for ((cx, cy), r, tint) in discs {
                let (dx, dy) = ((px - cx) / r, (py - cy) / r);
                let d2: f64 = dx * dx + dy * dy;
                if d2 < 1.0 {
                    a = tint;
                    n = [dx, (1.0 - d2).sqrt(), -dy];
                }
            }
            // Light from the upper left, falling off across the picture.
            let light = 0.4 + 1.6 * (1.0 - px / W as f64) * (1.0 - 0.5 * py / H as f64);
            let shade = (0.3 + 0.7 * (0.5 * n[0] + 0.8 * n[1]).max(0.0)) * light;
            for c in 0..3 {
                color.push((a[c] * shade) as f32);
                albedo.push(a[c] as f32);
                normal.push(n[c] as f32);
            }
        }
    }
    (color, albedo, normal)
}

/// `image` with Gaussian noise of standard deviation `sigma` times each value (as a path
/// tracer's noise grows with the radiance), seeded.
fn noisy(image: &[f32], sigma: f64, seed: u64) -> Vec<f32> {
    let mut noise = Noise(seed);
    image
        .iter()
        .map(|&v| (f64::from(v) * (1.0 + sigma * noise.gaussian())).max(0.0) as f32)
        .collect()
}

fn mse(a: &[f32], b: &[f32]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (f64::from(*x) - f64::from(*y)).powi(2))
        .sum();
    sum / a.len() as f64
}

#[test]
fn the_filter_brings_a_noisy_image_at_least_ten_times_closer_to_the_clean_one() {
    let Some(denoiser) = denoiser("OIDN's RT filter on a noisy image") else {
        return;
    };
    let (clean, albedo, normal) = scene();
    let input = noisy(&clean, 0.5, 7);
    let images = Images {
        width: W,
        height: H,
        color: &input,
        albedo: Some(&albedo),
        normal: Some(&normal),
    };
    let out = denoiser
        .session(2)
        .denoise(&images, true)
        .expect("denoises");
    let (before, after) = (mse(&input, &clean), mse(&out, &clean));
    // Measured with OIDN 2.5.1: about 37 times less squared error (20 without the guides); 10 is the stated floor.
    assert!(
        after * 10.0 < before,
        "mean squared error {before} before, {after} after"
    );
    // The guides help: without them the error is larger.
    let alone = Images {
        albedo: None,
        normal: None,
        ..images
    };
    let unguided = mse(
        &denoiser.session(2).denoise(&alone, true).expect("denoises"),
        &clean,
    );
    assert!(after < unguided, "guided {after}, unguided {unguided}");
}

#[test]
fn the_same_image_gives_the_same_bytes_for_any_thread_count() {
    let Some(denoiser) = denoiser("OIDN's determinism") else {
        return;
    };
    let (clean, albedo, normal) = scene();
    let input = noisy(&clean, 0.5, 11);
    let images = Images {
        width: W,
        height: H,
        color: &input,
        albedo: Some(&albedo),
        normal: Some(&normal),
    };
    let denoised = |threads| -> Vec<u32> {
        bits(
            &denoiser
                .session(threads)
                .denoise(&images, true)
                .expect("denoises"),
        )
    };
    let one = denoised(1);
    assert_eq!(one, denoised(1), "twice with one thread");
    assert_eq!(one, denoised(2), "one thread and two");
    assert_eq!(one, denoised(3), "one thread and three");
}

/// The image's bytes, to compare exactly.
fn bits(image: &[f32]) -> Vec<u32> {
    image.iter().map(|v| v.to_bits()).collect()
}

/// The top-left `w × h` pixels of a `W`-wide image.
fn crop(image: &[f32], w: usize, h: usize) -> Vec<f32> {
    (0..h)
        .flat_map(|y| image[y * W * 3..(y * W + w) * 3].iter().copied())
        .collect()
}

#[test]
fn a_session_keeps_its_device_and_remakes_its_filters_only_for_a_new_size_with_the_same_bytes() {
    let Some(denoiser) = denoiser("OIDN's device and filters kept across frames") else {
        return;
    };
    let (clean, albedo, normal) = scene();
    let frames: Vec<Vec<f32>> = (0..3).map(|seed| noisy(&clean, 0.5, 20 + seed)).collect();
    let guided = |color: &[f32]| -> Vec<f32> {
        let images = Images {
            width: W,
            height: H,
            color,
            albedo: Some(&albedo),
            normal: Some(&normal),
        };
        // A fresh session each time: a device and filters made for this image alone.
        denoiser
            .session(2)
            .denoise(&images, true)
            .expect("denoises")
    };
    let session = denoiser.session(2);
    let stats = |devices, setups, denoised| rayforge_denoise::SessionStats {
        devices,
        setups,
        denoised,
    };
    assert_eq!(
        session.stats(),
        stats(0, 0, 0),
        "nothing made before an image"
    );
    for (i, frame) in frames.iter().enumerate() {
        let images = Images {
            width: W,
            height: H,
            color: frame,
            albedo: Some(&albedo),
            normal: Some(&normal),
        };
        let out = session.denoise(&images, true).expect("denoises");
        assert_eq!(
            bits(&out),
            bits(&guided(frame)),
            "frame {i}: a fresh device's bytes"
        );
        assert_eq!(session.stats(), stats(1, 1, i + 1), "after frame {i}");
    }
    // Another size: the filters made again on the same device; the bytes a fresh one's.
    let (w, h) = (W / 2, H / 2);
    let (small, small_albedo, small_normal) = (
        crop(&frames[0], w, h),
        crop(&albedo, w, h),
        crop(&normal, w, h),
    );
    let images = Images {
        width: w,
        height: h,
        color: &small,
        albedo: Some(&small_albedo),
        normal: Some(&small_normal),
    };
    let out = session.denoise(&images, true).expect("denoises");
    let fresh = denoiser
        .session(2)
        .denoise(&images, true)
        .expect("denoises");
    assert_eq!(bits(&out), bits(&fresh), "the smaller image");
    assert_eq!(session.stats(), stats(1, 2, 4));
    // Without guides, another set of filters; back to the first size, another again.
    let alone = Images {
        albedo: None,
        normal: None,
        ..images
    };
    let out = session.denoise(&alone, true).expect("denoises");
    let fresh = denoiser.session(2).denoise(&alone, true).expect("denoises");
    assert_eq!(bits(&out), bits(&fresh), "without guides");
    assert_eq!(session.stats(), stats(1, 3, 5));
    let out = session
        .denoise(
            &Images {
                width: W,
                height: H,
                color: &frames[2],
                albedo: Some(&albedo),
                normal: Some(&normal),
            },
            true,
        )
        .expect("denoises");
    assert_eq!(
        bits(&out),
        bits(&guided(&frames[2])),
        "the first size again"
    );
    assert_eq!(session.stats(), stats(1, 4, 6));
    // A refused image reaches no OIDN call and changes nothing.
    let short = &frames[0][3..];
    let refused = Images {
        width: W,
        height: H,
        color: short,
        albedo: None,
        normal: None,
    };
    assert!(session.denoise(&refused, true).is_err());
    assert_eq!(session.stats(), stats(1, 4, 6));
}

#[test]
fn a_session_is_shared_between_threads_one_image_at_a_time() {
    let Some(denoiser) = denoiser("a session used from two threads") else {
        return;
    };
    let (clean, albedo, normal) = scene();
    let frames: Vec<Vec<f32>> = (0..4).map(|seed| noisy(&clean, 0.5, 40 + seed)).collect();
    let images = |color| Images {
        width: W,
        height: H,
        color,
        albedo: Some(&albedo),
        normal: Some(&normal),
    };
    let session = denoiser.session(1);
    // Frames 0 and 1 on one thread, 2 and 3 on another, at once: each as alone.
    let outs: Vec<Vec<f32>> = std::thread::scope(|scope| {
        let halves: Vec<_> = frames
            .chunks(2)
            .map(|pair| {
                let (session, images) = (&session, &images);
                scope.spawn(move || {
                    pair.iter()
                        .map(|f| session.denoise(&images(f), true).expect("denoises"))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        halves
            .into_iter()
            .flat_map(|h| h.join().expect("the thread"))
            .collect()
    });
    for (frame, out) in frames.iter().zip(&outs) {
        let fresh = denoiser.session(1).denoise(&images(frame), true).unwrap();
        assert_eq!(bits(out), bits(&fresh));
    }
    let stats = session.stats();
    assert_eq!((stats.devices, stats.setups, stats.denoised), (1, 1, 4));
}

#[test]
fn guides_of_another_size_and_values_that_are_not_finite_are_refused() {
    let Some(denoiser) = denoiser("OIDN's refusals") else {
        return;
    };
    let (clean, albedo, normal) = scene();
    let short = &albedo[..albedo.len() - 3];
    let images = Images {
        width: W,
        height: H,
        color: &clean,
        albedo: Some(short),
        normal: None,
    };
    let e = denoiser.session(1).denoise(&images, true).unwrap_err();
    assert!(
        matches!(
            e,
            DenoiseError::SizeMismatch {
                guide: "albedo",
                ..
            }
        ),
        "{e}"
    );
    let e = denoiser
        .session(1)
        .denoise(
            &Images {
                albedo: None,
                normal: Some(&normal),
                ..images
            },
            true,
        )
        .unwrap_err();
    assert_eq!(e, DenoiseError::NormalWithoutAlbedo);
    let mut bad = clean.clone();
    bad[(5 * W + 3) * 3 + 1] = f32::NAN;
    let e = denoiser
        .session(1)
        .denoise(
            &Images {
                color: &bad,
                albedo: Some(&albedo),
                ..images
            },
            true,
        )
        .unwrap_err();
    assert!(
        matches!(
            e,
            DenoiseError::NonFinite {
                image: "color",
                x: 3,
                y: 5,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("column 3, row 5"), "{e}");
}

#[test]
fn a_folder_without_the_library_is_an_error_that_says_how_to_install_it() {
    let empty = std::env::temp_dir().join(format!("rayforge-no-oidn-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let path: PathBuf = empty.join("lib").join(LIBRARY_FILE);
    let e = Denoiser::load_from(std::slice::from_ref(&path)).unwrap_err();
    let message = e.to_string();
    assert_eq!(e.tried.len(), 1);
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains("tools/oidn/install.sh"), "{message}");
    assert!(message.contains("RAYFORGE_OIDN_DIR"), "{message}");
    let _ = std::fs::remove_dir_all(&empty);
}

/// The checks made before OIDN is given the images need no OIDN, and a size whose values no
/// memory could hold is refused rather than overflowing the count (a panic in a debug build).
#[test]
fn images_are_checked_without_oidn_and_a_size_past_memory_is_refused() {
    let color = [0.5f32; 6];
    let images = |width, height, albedo, normal| Images {
        width,
        height,
        color: &color,
        albedo,
        normal,
    };
    assert!(images(2, 1, None, None).check().is_ok());
    assert!(images(2, 1, Some(&color[..]), Some(&color[..]))
        .check()
        .is_ok());
    let huge = images(usize::MAX, 2, None, None).check().unwrap_err();
    assert!(
        huge.to_string().contains("past what memory can address"),
        "{huge}"
    );
    assert!(matches!(
        images(2, 1, None, Some(&color[..])).check(),
        Err(DenoiseError::NormalWithoutAlbedo)
    ));
    assert!(matches!(
        images(2, 1, Some(&color[..3]), None).check(),
        Err(DenoiseError::SizeMismatch { .. })
    ));
    let nan = [f32::NAN; 6];
    assert!(matches!(
        images(2, 1, Some(&nan[..]), None).check(),
        Err(DenoiseError::NonFinite { .. })
    ));
}
