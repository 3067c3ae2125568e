//! The film: weighted accumulation, pixel filters, exact merging, snapshots of a shared film,
//! the film file, and developing.
use proptest::prelude::*;
use rayforge::color::Color;
use rayforge::film::{
    develop, Exposure, Film, FilmError, PixelFilter, SharedFilm, FILM_MAGIC, MAX_FILM_PIXELS,
};

fn bits(film: &Film) -> (Vec<[u64; 3]>, Vec<u64>, u64) {
    (
        film.sums()
            .iter()
            .map(|c| c.to_array().map(f64::to_bits))
            .collect(),
        film.weights().iter().map(|w| w.to_bits()).collect(),
        film.brightest().to_bits(),
    )
}

fn filter_strategy() -> impl Strategy<Value = PixelFilter> {
    prop_oneof![
        Just(PixelFilter::Box),
        (0.1f64..3.0).prop_map(|radius| PixelFilter::Tent { radius }),
        (0.1f64..3.0).prop_map(|radius| PixelFilter::Gaussian { radius }),
    ]
}

/// A sample: where in the image, its colour and its weight.
type Sample = (f64, f64, [f64; 3], f64);

fn samples(width: usize, height: usize) -> impl Strategy<Value = Vec<Sample>> {
    prop::collection::vec(
        (
            0.0..width as f64,
            0.0..height as f64,
            prop::array::uniform3(-2.0f64..10.0),
            0.0f64..4.0,
        ),
        0..60,
    )
}

fn add_all(film: &mut Film, samples: &[Sample]) {
    for &(x, y, [r, g, b], w) in samples {
        film.add_sample(x, y, Color::new(r, g, b), w);
    }
}

proptest! {
    #[test]
    fn a_film_written_and_read_back_is_the_same_to_the_bit(
        width in 0usize..7,
        height in 0usize..7,
        filter in filter_strategy(),
        raw in prop::collection::vec(any::<u64>(), 0..200),
        brightest in any::<u64>(),
    ) {
        // Any bit patterns in the sums and weights: NaNs, infinities, negative zeros.
        let mut film = Film::with_filter(width, height, filter).unwrap();
        for (i, chunk) in raw.chunks(4).enumerate().take(width * height) {
            let v = |k: usize| f64::from_bits(chunk.get(k).copied().unwrap_or(0));
            film.add_pixel(i % width, i / width, Color::new(v(0), v(1), v(2)), v(3));
        }
        film.note_brightest(f64::from_bits(brightest));
        let bytes = film.to_bytes();
        let back = Film::from_bytes(&bytes).unwrap();
        prop_assert_eq!(bits(&back), bits(&film));
        prop_assert_eq!((back.width(), back.height(), back.filter()), (width, height, filter));
    }

    #[test]
    fn merging_two_halves_of_a_box_filtered_film_equals_the_whole(
        width in 1usize..8,
        height in 1usize..8,
        split in 0usize..8,
        samples in samples(8, 8),
    ) {
        let samples: Vec<Sample> = samples
            .into_iter()
            .map(|(x, y, c, w)| (x % width as f64, y % height as f64, c, w))
            .collect();
        let split = split.min(height) as f64;
        let (top, bottom): (Vec<Sample>, Vec<Sample>) =
            samples.iter().partition(|s| s.1.floor() < split);
        let mut whole = Film::new(width, height);
        add_all(&mut whole, &samples);
        whole.note_brightest(3.0);
        let mut a = Film::new(width, height);
        add_all(&mut a, &top);
        a.note_brightest(3.0);
        let mut b = Film::new(width, height);
        add_all(&mut b, &bottom);
        a.merge(&b).unwrap();
        prop_assert_eq!(bits(&a), bits(&whole));
        // And in the other order.
        let mut a2 = Film::new(width, height);
        add_all(&mut a2, &top);
        a2.note_brightest(3.0);
        b.merge(&a2).unwrap();
        prop_assert_eq!(bits(&b), bits(&whole));
    }

    #[test]
    fn merging_halves_under_a_wide_filter_equals_the_whole_within_rounding(
        filter in filter_strategy(),
        samples in samples(6, 6),
    ) {
        let (top, bottom): (Vec<Sample>, Vec<Sample>) = samples.iter().partition(|s| s.1 < 3.0);
        let mut whole = Film::with_filter(6, 6, filter).unwrap();
        add_all(&mut whole, &samples);
        let mut a = Film::with_filter(6, 6, filter).unwrap();
        add_all(&mut a, &top);
        let mut b = Film::with_filter(6, 6, filter).unwrap();
        add_all(&mut b, &bottom);
        a.merge(&b).unwrap();
        for (m, w) in a.sums().iter().zip(whole.sums()) {
            for (m, w) in m.to_array().into_iter().zip(w.to_array()) {
                prop_assert!((m - w).abs() <= 1e-9 * (1.0 + w.abs()), "{m} vs {w}");
            }
        }
        for (m, w) in a.weights().iter().zip(whole.weights()) {
            prop_assert!((m - w).abs() <= 1e-9 * (1.0 + w.abs()), "{m} vs {w}");
        }
    }
}

#[test]
fn one_sample_of_weight_one_resolves_to_its_colour_to_the_bit() {
    let mut film = Film::new(2, 1);
    let c = Color::new(-0.0, 0.1 + 0.2, f64::MIN_POSITIVE);
    film.add_pixel(0, 0, c, 1.0);
    let canvas = film.resolve();
    let got = canvas.pixel_at(0, 0).to_array().map(f64::to_bits);
    assert_eq!(got, c.to_array().map(f64::to_bits));
    // A pixel with no weight is black.
    assert_eq!(canvas.pixel_at(1, 0), Color::BLACK);
}

#[test]
fn the_box_filter_gives_a_sample_to_the_pixel_it_lies_in() {
    let mut film = Film::new(3, 2);
    film.add_sample(1.0, 1.999, Color::WHITE, 2.0);
    film.add_sample(1.5, 0.5, Color::new(1.0, 0.0, 0.0), 1.0);
    assert_eq!(film.weight(1, 1), 2.0);
    assert_eq!(
        film.weight(0, 1),
        0.0,
        "a sample on a border counts for one pixel"
    );
    assert_eq!(film.weight(1, 0), 1.0);
    assert_eq!(film.weights().iter().sum::<f64>(), 3.0);
}

#[test]
fn a_tent_splats_a_sample_onto_its_neighbours_by_distance() {
    let mut film = Film::with_filter(3, 3, PixelFilter::Tent { radius: 2.0 }).unwrap();
    film.add_sample(1.5, 1.5, Color::WHITE, 1.0);
    assert_eq!(film.weight(1, 1), 1.0);
    assert_eq!(film.weight(0, 1), 0.5);
    assert_eq!(film.weight(0, 0), 0.25);
    // Every pixel sees the same colour: the weighted average of one sample is that sample.
    assert!(film.resolve().pixels().iter().all(|&c| c == Color::WHITE));
}

#[test]
fn a_gaussian_falls_off_symmetrically_and_reaches_zero_at_its_radius() {
    let g = PixelFilter::Gaussian { radius: 1.5 };
    assert!(g.weight(0.0, 0.0) > g.weight(0.5, 0.0));
    assert_eq!(g.weight(0.7, 0.2), g.weight(-0.7, -0.2));
    assert_eq!(g.weight(0.2, 0.7), g.weight(0.7, 0.2));
    assert_eq!(g.weight(1.5, 0.0), 0.0);
    assert_eq!(g.weight(0.0, 2.0), 0.0);
}

#[test]
fn filters_of_no_or_huge_or_undefined_radius_are_refused() {
    for radius in [0.0, -1.0, f64::NAN, f64::INFINITY, 8.5] {
        assert!(matches!(
            Film::with_filter(2, 2, PixelFilter::Tent { radius }),
            Err(FilmError::BadFilter(_))
        ));
        assert!(PixelFilter::Gaussian { radius }.checked().is_err());
    }
    assert!(PixelFilter::Gaussian { radius: 8.0 }.checked().is_ok());
}

#[test]
fn films_of_other_sizes_or_filters_do_not_merge() {
    let mut a = Film::new(3, 2);
    a.add_pixel(0, 0, Color::WHITE, 1.0);
    let before = a.clone();
    let e = a.merge(&Film::new(2, 3)).unwrap_err();
    assert!(matches!(e, FilmError::SizeMismatch(2, 3, 3, 2)), "{e}");
    assert!(e.to_string().contains("sizes differ"), "{e}");
    let tent = Film::with_filter(3, 2, PixelFilter::Tent { radius: 1.0 }).unwrap();
    let e = a.merge(&tent).unwrap_err();
    assert!(matches!(e, FilmError::FilterMismatch(..)), "{e}");
    assert_eq!(a, before, "a refused merge changes nothing");
}

fn sample_film() -> Film {
    let mut film = Film::with_filter(4, 3, PixelFilter::Gaussian { radius: 1.25 }).unwrap();
    film.add_sample(1.2, 2.3, Color::new(0.5, 0.25, 2.0), 1.0);
    film.note_brightest(2.0);
    film
}

#[test]
fn reading_refuses_what_is_not_a_whole_undamaged_film() {
    let bytes = sample_film().to_bytes();
    assert_eq!(&bytes[..8], FILM_MAGIC);
    assert_eq!(bytes.len(), 45 + 12 * 32 + 4);
    // Every prefix is truncated.
    for len in 0..bytes.len() {
        let e = Film::from_bytes(&bytes[..len]).unwrap_err();
        assert!(matches!(e, FilmError::Truncated), "{len}: {e}");
    }
    let mut wrong = bytes.clone();
    wrong[0] = b'X';
    assert!(matches!(Film::from_bytes(&wrong), Err(FilmError::BadMagic)));
    let mut version = bytes.clone();
    version[8] = 2;
    assert!(matches!(
        Film::from_bytes(&version),
        Err(FilmError::UnsupportedVersion(2))
    ));
    let mut filter = bytes.clone();
    filter[28] = 9;
    assert!(matches!(
        Film::from_bytes(&filter),
        Err(FilmError::UnknownFilter(9))
    ));
    // A flipped bit in the pixels fails the checksum.
    let mut damaged = bytes.clone();
    damaged[100] ^= 0x10;
    let e = Film::from_bytes(&damaged).unwrap_err();
    assert!(matches!(e, FilmError::BadChecksum { .. }), "{e}");
    assert!(e.to_string().contains("damaged"), "{e}");
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(
        Film::from_bytes(&longer),
        Err(FilmError::TrailingBytes(1))
    ));
    // What follows a film in a stream is left there.
    let mut input = &longer[..];
    assert!(Film::read_from(&mut input).is_ok());
    assert_eq!(input, &[0]);
}

#[test]
fn a_header_asking_for_unbounded_memory_is_refused_before_allocating() {
    let bytes = sample_film().to_bytes();
    for (width, height) in [
        (u64::MAX, 2u64),
        (1 << 20, 1 << 20),
        (MAX_FILM_PIXELS + 1, 1),
    ] {
        let mut huge = bytes[..45].to_vec();
        huge[12..20].copy_from_slice(&width.to_le_bytes());
        huge[20..28].copy_from_slice(&height.to_le_bytes());
        let e = Film::from_bytes(&huge).unwrap_err();
        assert!(matches!(e, FilmError::TooLarge(..)), "{e}");
        assert!(e.to_string().contains("limit"), "{e}");
    }
    // Within the limit but truncated: refused as truncated, without reserving the whole.
    let mut big = bytes[..45].to_vec();
    big[12..20].copy_from_slice(&(1u64 << 14).to_le_bytes());
    big[20..28].copy_from_slice(&(1u64 << 14).to_le_bytes());
    assert!(matches!(Film::from_bytes(&big), Err(FilmError::Truncated)));
}

#[test]
fn a_shared_film_takes_rows_from_many_threads_and_snapshots_whole_rows() {
    let (width, height) = (16, 24);
    let shared = SharedFilm::from(Film::new(width, height));
    let row = |y: usize, pass: usize| {
        let mut part = Film::new(width, 1);
        for x in 0..width {
            part.add_pixel(x, 0, Color::new(x as f64, y as f64, pass as f64), 1.0);
        }
        part.note_brightest(y as f64);
        part
    };
    std::thread::scope(|scope| {
        for t in 0..4 {
            let shared = &shared;
            scope.spawn(move || {
                for pass in 0..3 {
                    for y in (t..height).step_by(4) {
                        shared.add(y, &row(y, pass)).unwrap();
                    }
                }
            });
        }
        for _ in 0..20 {
            let snapshot = shared.snapshot();
            assert_eq!((snapshot.width(), snapshot.height()), (width, height));
            // Each row is whole: every pixel of it has seen the same number of passes.
            for y in 0..height {
                let w = snapshot.row_weights(y);
                assert!(w.iter().all(|&v| v == w[0]), "row {y}: {w:?}");
            }
        }
    });
    let film = shared.into_film();
    let mut expected = Film::new(width, height);
    for pass in 0..3 {
        for y in 0..height {
            let part = row(y, pass);
            for x in 0..width {
                expected.add_pixel(x, y, part.sum(x, 0), 1.0);
            }
        }
    }
    expected.note_brightest((height - 1) as f64);
    assert_eq!(bits(&film), bits(&expected));
    assert!(matches!(
        SharedFilm::from(Film::new(width, 2)).add(2, &row(0, 0)),
        Err(FilmError::RowsOutside { .. })
    ));
}

#[test]
fn developing_with_automatic_exposure_repairs_empty_pixels_and_exposes() {
    let mut film = Film::new(3, 1);
    film.add_pixel(0, 0, Color::new(0.5, 0.25, 0.0), 1.0);
    film.add_pixel(2, 0, Color::new(1.0, 0.0, 0.0), 1.0);
    film.note_brightest(2.0);
    let fixed = develop(&film, Exposure::Fixed);
    assert_eq!(fixed.pixel_at(1, 0), Color::BLACK);
    assert_eq!(fixed.pixel_at(2, 0), Color::new(1.0, 0.0, 0.0));
    let exposed = develop(&film, Exposure::Automatic);
    // The empty pixel is its neighbours' average, (0.75, 0.125, 0); everything is divided by
    // the brightest sample (2) and truncated to 255 steps.
    let step = |v: f64| ((255.0 * v / 2.0) as i64) as f64 / 255.0;
    assert_eq!(
        exposed.pixel_at(1, 0),
        Color::new(step(0.75), step(0.125), 0.0)
    );
    assert_eq!(exposed.pixel_at(2, 0), Color::new(step(1.0), 0.0, 0.0));
}

/// The film a render fills can be looked at while it runs: each snapshot, taken as a row is
/// finished, holds that row whole, and the film at the end is the one `render_rows` makes.
#[test]
fn a_render_can_be_watched_through_snapshots_of_its_film() {
    use rayforge::math::{point, vector, view_transform};
    use rayforge::render::{render_rows, render_rows_into, RenderOptions};
    use rayforge::Camera;
    use std::sync::Mutex;

    let world = rayforge::default_world();
    let camera = Camera::new(9, 7, std::f64::consts::FRAC_PI_2).with_transform(view_transform(
        point(0.0, 0.0, -5.0),
        point(0.0, 0.0, 0.0),
        vector(0.0, 1.0, 0.0),
    ));
    let film = SharedFilm::from(Film::new(9, 7));
    let mut done = vec![false; 7];
    let seen = Mutex::new(Vec::new());
    let on_row = |y: usize, _: &[Color]| {
        let snapshot = film.snapshot();
        let whole = (0..9).all(|x| snapshot.weight(x, y) == 1.0);
        seen.lock().unwrap().push((y, whole));
    };
    let options = RenderOptions {
        on_row: Some(&on_row),
        ..RenderOptions::default()
    };
    render_rows_into(&camera, &world, &options, &film, &mut done).expect("the camera's size");
    let mut seen = seen.into_inner().unwrap();
    seen.sort_unstable();
    assert_eq!(seen, (0..7).map(|y| (y, true)).collect::<Vec<_>>());
    assert!(done.iter().all(|&d| d));
    let (image, _) = render_rows(&camera, &world, &RenderOptions::default());
    assert_eq!(bits(&film.snapshot()), bits(image.film()));

    // A film or a row list of another size is refused before anything is traced.
    let small = SharedFilm::from(Film::new(3, 7));
    let plain = RenderOptions::default();
    assert!(render_rows_into(&camera, &world, &plain, &small, &mut [false; 7]).is_err());
    assert!(render_rows_into(&camera, &world, &plain, &film, &mut [false; 2]).is_err());
}

#[test]
fn a_film_of_some_rows_takes_samples_on_those_rows_only() {
    let film = SharedFilm::with_rows(4, 9, PixelFilter::Box, [7, 1, 4, 1]).unwrap();
    assert_eq!((film.width(), film.height(), film.held_rows()), (4, 9, 3));
    assert!((0..10).all(|y| film.holds_row(y) == [1, 4, 7].contains(&y)));
    let row = |v: f64| {
        let mut part = Film::new(4, 1);
        (0..4).for_each(|x| part.add_pixel(x, 0, Color::new(v, x as f64, -0.0), 1.0));
        part.note_brightest(v);
        part
    };
    film.add(4, &row(2.0)).unwrap();
    film.set_row(7, &row(3.0)).unwrap();
    assert!(matches!(
        film.add(2, &row(9.0)),
        Err(FilmError::RowNotHeld(2))
    ));
    assert!(matches!(
        film.set_row(0, &row(9.0)),
        Err(FilmError::RowNotHeld(0))
    ));
    assert!(matches!(film.row(8), Err(FilmError::RowNotHeld(8))));
    assert!(matches!(film.row(9), Err(FilmError::RowsOutside { .. })));
    // A band running over a row not held is refused whole: row 4 keeps its one sample.
    let mut band = Film::new(4, 2);
    band.add_pixel(0, 0, Color::WHITE, 1.0);
    assert!(matches!(film.add(4, &band), Err(FilmError::RowNotHeld(5))));
    assert_eq!(film.row(4).unwrap().weight(0, 0), 1.0);
    assert!(film
        .check_holds_undone(&[true, false, true, true, false, true, true, false, true])
        .is_ok());
    assert!(matches!(
        film.check_holds_undone(&[true, false, false, true, false, true, true, false, true]),
        Err(FilmError::RowNotHeld(2))
    ));
    // Its film is its rows, top to bottom: an empty row, row 4's sample, row 7's.
    let mut expected = Film::new(4, 3);
    for x in 0..4 {
        expected.add_pixel(x, 1, Color::new(2.0, x as f64, -0.0), 1.0);
        expected.add_pixel(x, 2, Color::new(3.0, x as f64, -0.0), 1.0);
    }
    expected.note_brightest(3.0);
    assert_eq!(bits(&film.snapshot()), bits(&expected));
    assert_eq!(bits(&film.into_film()), bits(&expected));
    assert!(matches!(
        SharedFilm::with_rows(4, 9, PixelFilter::Box, [9]),
        Err(FilmError::RowsOutside { first: 9, .. })
    ));
    assert!(matches!(
        SharedFilm::with_rows(4, 9, PixelFilter::Tent { radius: 0.0 }, [1]),
        Err(FilmError::BadFilter(_))
    ));
}

/// The rows `keep` of `film`, top to bottom, as a film of their own.
fn rows_of(film: &Film, keep: &[usize]) -> Film {
    let mut rows = Film::with_filter(film.width(), keep.len(), film.filter()).unwrap();
    for (j, &y) in keep.iter().enumerate() {
        for x in 0..film.width() {
            rows.add_pixel_sum(x, j, film.sum(x, y), film.weight(x, y));
        }
    }
    rows.note_brightest(film.brightest());
    rows
}

/// Every renderer renders into a film of some rows exactly those rows of its whole render, and
/// refuses to render a row the film does not hold.
#[test]
fn renders_into_a_film_of_some_rows_are_those_rows_of_the_whole_render() {
    use rayforge::math::{point, vector, view_transform};
    use rayforge::options::{PathOptions, RasterOptions};
    use rayforge::raster::{render_film, RasterError};
    use rayforge::render::path::{render_path, PathJob};
    use rayforge::render::{render_rows, render_rows_into, RenderOptions};
    use rayforge::Camera;

    // Rows in three bands of the rasterizer's tiles (32 rows each), one band skipped.
    let (width, height) = (9, 100);
    let keep = [0, 5, 31, 70, 99];
    let done: Vec<bool> = (0..height).map(|y| !keep.contains(&y)).collect();
    let world = rayforge::default_world();
    let camera =
        Camera::new(width, height, std::f64::consts::FRAC_PI_3).with_transform(view_transform(
            point(0.0, 1.5, -5.0),
            point(0.0, 1.0, 0.0),
            vector(0.0, 1.0, 0.0),
        ));
    let film = |filter| SharedFilm::with_rows(width, height, filter, keep).unwrap();

    let ray = film(PixelFilter::Box);
    let options = RenderOptions::default();
    render_rows_into(&camera, &world, &options, &ray, &mut done.clone()).unwrap();
    let (whole, _) = render_rows(&camera, &world, &options);
    assert_eq!(bits(&ray.into_film()), bits(&rows_of(whole.film(), &keep)));
    let refused = render_rows_into(
        &camera,
        &world,
        &options,
        &film(PixelFilter::Box),
        &mut [false; 100],
    );
    assert!(matches!(refused, Err(FilmError::RowNotHeld(1))));

    let tent = PixelFilter::Tent { radius: 1.5 };
    let job = PathJob::new(
        PathOptions {
            filter: tent,
            ..PathOptions::default()
        },
        0..3,
    );
    let path = film(tent);
    render_path(&camera, &world, &job, &path, None, &mut done.clone()).unwrap();
    let whole = SharedFilm::with_rows(width, height, tent, 0..height).unwrap();
    render_path(
        &camera,
        &world,
        &job,
        &whole,
        None,
        &mut vec![false; height],
    )
    .unwrap();
    assert_eq!(
        bits(&path.into_film()),
        bits(&rows_of(&whole.into_film(), &keep))
    );
    let refused = render_path(
        &camera,
        &world,
        &job,
        &film(tent),
        None,
        &mut vec![false; height],
    );
    assert!(matches!(refused, Err(FilmError::RowNotHeld(1))));

    let options = RasterOptions::default();
    let raster = film(PixelFilter::Box);
    let stats =
        rayforge::raster::render_rows_into(&camera, &world, &options, &raster, None).unwrap();
    let (whole, whole_stats) = render_film(&camera, &world, &options, None).unwrap();
    assert_eq!(stats, whole_stats);
    assert_eq!(bits(&raster.into_film()), bits(&rows_of(&whole, &keep)));
    let refused = rayforge::raster::render_rows_into(&camera, &world, &options, &film(tent), None);
    assert!(matches!(
        refused,
        Err(RasterError::FilmMismatch {
            box_filter: false,
            ..
        })
    ));
}
