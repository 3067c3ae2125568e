//! A film render workers add to while others look at it.

use super::{Film, FilmError, PixelFilter, EMPTY};
use crate::color::Color;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// A film shared between the workers of a render, which add finished rows or tiles to it, and
/// whoever wants to see the image while it converges ([`snapshot`](Self::snapshot)).
///
/// Each row has its own lock, taken once per row a worker adds (never per sample: a worker
/// accumulates its samples in a small [`Film`] of its own first), so workers on different rows
/// never wait for each other, and a snapshot holds each row's lock only while it copies that
/// row. A snapshot is therefore consistent row by row: each row is as it was between two
/// additions to it, while two rows may be one pass apart in a progressive render.
///
/// A film may hold only some rows of its image ([`with_rows`](Self::with_rows)): a slice of a
/// render cut by rows, on a machine of its own, needs memory for its rows only, not for the
/// whole image (a 16384-pixel-square poster's film is 8 GiB; each of 64 slices holds 1/64 of
/// it). The rows it lacks cost a slot each (a few words, whatever the width) and refuse samples;
/// the film it becomes ([`into_film`](Self::into_film)) is its rows, top to bottom. No margin
/// of rows around the held ones is needed: the renderers that draw into shared films give each
/// sample to one pixel (the path tracer draws a pixel's samples over its filter's support and
/// weighs them there, never splats one onto a neighbour; the ray tracer and the rasterizer add
/// one estimate per pixel), so a pixel's sums are made from its own row's samples alone.
#[derive(Debug)]
pub struct SharedFilm {
    width: usize,
    filter: PixelFilter,
    /// One slot per row of the image, `None` for the rows the film does not hold.
    rows: Vec<Option<Mutex<Row>>>,
    /// [`Film::brightest`] as bits, kept with `fetch_max` (see [`Film::note_brightest`]).
    brightest: AtomicU64,
}

/// One row's sums of weighted colours and sums of weights.
#[derive(Debug)]
struct Row {
    sums: Vec<Color>,
    weights: Vec<f64>,
}

impl From<Film> for SharedFilm {
    fn from(film: Film) -> Self {
        let width = film.width;
        let rows = (0..film.height)
            .map(|y| {
                Some(Mutex::new(Row {
                    sums: film.row_sums(y).to_vec(),
                    weights: film.row_weights(y).to_vec(),
                }))
            })
            .collect();
        Self {
            width,
            filter: film.filter,
            rows,
            brightest: AtomicU64::new(film.brightest.to_bits()),
        }
    }
}

impl SharedFilm {
    /// A `width` × `height` film with no samples that holds only the rows `rows` names (in any
    /// order; a row named twice is held once), splatting through `filter`. Refused when a row
    /// is past the last one or the filter's radius is out of range.
    pub fn with_rows(
        width: usize,
        height: usize,
        filter: PixelFilter,
        rows: impl IntoIterator<Item = usize>,
    ) -> Result<Self, FilmError> {
        let filter = filter.checked()?;
        let mut slots: Vec<Option<Mutex<Row>>> = (0..height).map(|_| None).collect();
        for y in rows {
            let slot = slots.get_mut(y).ok_or(FilmError::RowsOutside {
                first: y,
                rows: 1,
                height,
            })?;
            slot.get_or_insert_with(|| {
                Mutex::new(Row {
                    sums: vec![EMPTY; width],
                    weights: vec![0.0; width],
                })
            });
        }
        Ok(Self {
            width,
            filter,
            rows: slots,
            brightest: AtomicU64::new(0.0f64.to_bits()),
        })
    }

    /// How samples are spread over the pixels (every part added must have the same).
    pub fn filter(&self) -> PixelFilter {
        self.filter
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels: the image's, whichever of its rows the film holds.
    pub fn height(&self) -> usize {
        self.rows.len()
    }

    /// Whether the film holds row `y` (false past the last row).
    pub fn holds_row(&self, y: usize) -> bool {
        self.rows.get(y).is_some_and(Option::is_some)
    }

    /// How many rows the film holds: its height, unless made [`with_rows`](Self::with_rows).
    pub fn held_rows(&self) -> usize {
        self.rows.iter().filter(|row| row.is_some()).count()
    }

    /// Checks that the film holds every row a render is to add, those not marked in `done`
    /// (one entry per row), naming the first that it does not.
    pub fn check_holds_undone(&self, done: &[bool]) -> Result<(), FilmError> {
        match done
            .iter()
            .enumerate()
            .find(|&(y, &done)| !done && !self.holds_row(y))
        {
            Some((row, _)) => Err(FilmError::RowNotHeld(row)),
            None => Ok(()),
        }
    }

    /// Row `y`'s slot, or why there is none.
    fn held(&self, y: usize, rows: usize) -> Result<&Mutex<Row>, FilmError> {
        match self.rows.get(y) {
            Some(Some(row)) => Ok(row),
            Some(None) => Err(FilmError::RowNotHeld(y)),
            None => Err(FilmError::RowsOutside {
                first: y,
                rows,
                height: self.height(),
            }),
        }
    }

    /// Adds `part`, a film as wide as this one whose row 0 is this film's row `first` (a
    /// worker's finished row or band of tiles), and notes its brightest sample. Refused (and
    /// nothing changes) when the widths or filters differ or the rows run past the last one or
    /// are not all held.
    pub fn add(&self, first: usize, part: &Film) -> Result<(), FilmError> {
        if first
            .checked_add(part.height)
            .is_none_or(|end| end > self.height())
        {
            return Err(FilmError::RowsOutside {
                first,
                rows: part.height,
                height: self.height(),
            });
        }
        if part.width != self.width {
            return Err(FilmError::SizeMismatch(
                part.width,
                part.height,
                self.width,
                part.height,
            ));
        }
        if part.filter != self.filter {
            return Err(FilmError::FilterMismatch(part.filter, self.filter));
        }
        let rows = (first..first + part.height)
            .map(|y| self.held(y, part.height))
            .collect::<Result<Vec<_>, _>>()?;
        for (y, row) in rows.into_iter().enumerate() {
            let mut row = lock(row);
            for (sum, s) in row.sums.iter_mut().zip(part.row_sums(y)) {
                *sum += *s;
            }
            for (weight, w) in row.weights.iter_mut().zip(part.row_weights(y)) {
                *weight += w;
            }
        }
        self.brightest
            .fetch_max(part.brightest.to_bits(), Ordering::Relaxed);
        Ok(())
    }

    /// Row `y` as it is now, as a film one row high: a worker that goes on sampling the row
    /// (the path tracer's next pass) continues from its sums and then [`set_row`]s it, so that
    /// every pixel's samples are summed in the same order however many passes they came in.
    /// Refused for a row past the last or not held.
    ///
    /// [`set_row`]: Self::set_row
    pub fn row(&self, y: usize) -> Result<Film, FilmError> {
        let row = lock(self.held(y, 1)?);
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = 1;
        film.sums.extend_from_slice(&row.sums);
        film.weights.extend_from_slice(&row.weights);
        Ok(film)
    }

    /// Replaces row `y` with `part`'s one row (see [`SharedFilm::row`]). Refused (and nothing
    /// changes) when `part` is not one row of this film's width and filter, or `y` is past
    /// the last row or not held.
    pub fn set_row(&self, y: usize, part: &Film) -> Result<(), FilmError> {
        let row = self.held(y, part.height)?;
        if part.width != self.width || part.height != 1 {
            return Err(FilmError::SizeMismatch(
                part.width,
                part.height,
                self.width,
                1,
            ));
        }
        if part.filter != self.filter {
            return Err(FilmError::FilterMismatch(part.filter, self.filter));
        }
        let mut row = lock(row);
        row.sums.copy_from_slice(part.row_sums(0));
        row.weights.copy_from_slice(part.row_weights(0));
        drop(row);
        self.brightest
            .fetch_max(part.brightest.to_bits(), Ordering::Relaxed);
        Ok(())
    }

    /// An owned copy of the rows the film holds as they are now, top to bottom, row by row
    /// (see the type's documentation), to develop or save while the render goes on: the whole
    /// image unless the film was made [`with_rows`](Self::with_rows).
    pub fn snapshot(&self) -> Film {
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = self.held_rows();
        film.sums.reserve(self.width * film.height);
        film.weights.reserve(self.width * film.height);
        for row in self.rows.iter().flatten() {
            let row = lock(row);
            film.sums.extend_from_slice(&row.sums);
            film.weights.extend_from_slice(&row.weights);
        }
        film.brightest = f64::from_bits(self.brightest.load(Ordering::Relaxed));
        film
    }

    /// The rows the film holds, top to bottom, once no one adds to them any more: the whole
    /// image unless the film was made [`with_rows`](Self::with_rows), else a film as high as
    /// the rows it holds (what a slice's part file stores).
    pub fn into_film(self) -> Film {
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = self.held_rows();
        film.sums.reserve_exact(self.width * film.height);
        film.weights.reserve_exact(self.width * film.height);
        for row in self.rows.into_iter().flatten() {
            let row = row.into_inner().unwrap_or_else(|e| e.into_inner());
            film.sums.extend(row.sums);
            film.weights.extend(row.weights);
        }
        film.brightest = f64::from_bits(self.brightest.into_inner());
        film
    }
}

/// A row's lock. Nothing done under it can panic (it only adds numbers), so a poisoned lock
/// still guards whole rows and is used as it is.
fn lock(row: &Mutex<Row>) -> MutexGuard<'_, Row> {
    row.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bytes a film's rows hold in sums and weights, by their capacities.
    fn row_bytes(film: &SharedFilm) -> usize {
        film.rows
            .iter()
            .flatten()
            .map(|row| {
                let row = lock(row);
                row.sums.capacity() * std::mem::size_of::<Color>()
                    + row.weights.capacity() * std::mem::size_of::<f64>()
            })
            .sum()
    }

    #[test]
    fn a_film_of_some_rows_allocates_those_rows_only() {
        // Slice 3 of 64 of a 4096 × 4096 image: 64 rows, 8 MiB of the whole film's 512 MiB.
        let (width, height) = (4096, 4096);
        let rows = (3..height).step_by(64);
        let film = SharedFilm::with_rows(width, height, PixelFilter::Box, rows).unwrap();
        assert_eq!(
            (film.width(), film.height(), film.held_rows()),
            (4096, 4096, 64)
        );
        assert_eq!(row_bytes(&film), 64 * width * 32);
        // A slot per row of the image, held or not: a few words each, whatever the width.
        assert_eq!(film.rows.capacity(), height);
        assert!(std::mem::size_of::<Option<Mutex<Row>>>() <= 64);
        let film = film.into_film();
        assert_eq!((film.width(), film.height()), (4096, 64));
        assert_eq!(film.sums().len(), 64 * width);
        // The whole image, for comparison.
        let whole = SharedFilm::from(Film::new(16, 8));
        assert_eq!(row_bytes(&whole), 16 * 8 * 32);
    }
}
