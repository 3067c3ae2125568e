//! A film render workers add to while others look at it.

use super::{Film, FilmError, PixelFilter};
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
#[derive(Debug)]
pub struct SharedFilm {
    width: usize,
    filter: PixelFilter,
    rows: Vec<Mutex<Row>>,
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
                Mutex::new(Row {
                    sums: film.row_sums(y).to_vec(),
                    weights: film.row_weights(y).to_vec(),
                })
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
    /// How samples are spread over the pixels (every part added must have the same).
    pub fn filter(&self) -> PixelFilter {
        self.filter
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.rows.len()
    }

    /// Adds `part`, a film as wide as this one whose row 0 is this film's row `first` (a
    /// worker's finished row or band of tiles), and notes its brightest sample. Refused (and
    /// nothing changes) when the widths or filters differ or the rows run past the last one.
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
        for (y, row) in self.rows[first..first + part.height].iter().enumerate() {
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
    ///
    /// [`set_row`]: Self::set_row
    pub fn row(&self, y: usize) -> Result<Film, FilmError> {
        let height = self.height();
        let row = self.rows.get(y).ok_or(FilmError::RowsOutside {
            first: y,
            rows: 1,
            height,
        })?;
        let row = lock(row);
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = 1;
        film.sums.extend_from_slice(&row.sums);
        film.weights.extend_from_slice(&row.weights);
        Ok(film)
    }

    /// Replaces row `y` with `part`'s one row (see [`SharedFilm::row`]). Refused (and nothing
    /// changes) when `part` is not one row of this film's width and filter, or `y` is past
    /// the last row.
    pub fn set_row(&self, y: usize, part: &Film) -> Result<(), FilmError> {
        let height = self.height();
        let Some(row) = self.rows.get(y) else {
            return Err(FilmError::RowsOutside {
                first: y,
                rows: part.height,
                height,
            });
        };
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

    /// An owned copy of the film as it is now, row by row (see the type's documentation), to
    /// develop or save while the render goes on.
    pub fn snapshot(&self) -> Film {
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = self.height();
        film.sums.reserve(self.width * self.height());
        film.weights.reserve(self.width * self.height());
        for row in &self.rows {
            let row = lock(row);
            film.sums.extend_from_slice(&row.sums);
            film.weights.extend_from_slice(&row.weights);
        }
        film.brightest = f64::from_bits(self.brightest.load(Ordering::Relaxed));
        film
    }

    /// The film, once no one adds to it any more.
    pub fn into_film(self) -> Film {
        let mut film = Film::new(self.width, 0);
        film.filter = self.filter;
        film.height = self.rows.len();
        for row in self.rows {
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
