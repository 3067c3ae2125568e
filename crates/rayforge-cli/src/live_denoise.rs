//! Denoising while a render refines: the path tracer's passes shown to a viewer (tev, through
//! `--display-server` with `--denoise`; the live page with its `denoise` box) are denoised on a
//! thread of their own, beside the render.
//!
//! When a pass ends, its accumulated image and guides are offered to that thread. If it is
//! idle, it takes the frame and denoises it; if it is still denoising an earlier one, the offer
//! is skipped, not queued: the frame is not even copied out of the films. So the render never
//! waits for the denoiser (its cost is the CPU time OIDN takes beside the render, measured in
//! `docs/performance.md`), no backlog of stale frames builds up when the passes come faster
//! than the denoiser, and what the viewer sees denoised trails the newest pass by at most one
//! denoise. The frame after the last pass is not offered: it is the image the render writes,
//! denoised with its AOVs by the render's own output code once this thread has finished.
//!
//! The denoiser is behind [`FrameDenoiser`] so that the taking and skipping can be tested
//! without OIDN and without timing: a stand-in that blocks until the test lets it go.

use crate::denoise::Guides;
use crate::failure::Failure;
use crate::finite::blacken_non_finite;
use rayforge::canvas::Canvas;
use rayforge::film::SharedFilm;
use rayforge_denoise::Session;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::{Duration, Instant};

/// A pass's image and its guides, linear and finite, as the denoiser takes them.
pub struct Frame {
    /// The image so far (the film resolved, its non-finite pixels black).
    pub image: Canvas,
    /// The first surfaces' albedo so far.
    pub albedo: Canvas,
    /// Their normals so far.
    pub normal: Canvas,
    /// The pass it ends, from 1.
    pub pass: usize,
    /// Samples per pixel so far.
    pub samples: u64,
}

/// A film's image so far, its non-finite pixels black (as the denoiser takes it).
pub fn resolved(film: &SharedFilm) -> Canvas {
    let mut canvas = film.snapshot().resolve();
    blacken_non_finite(&mut canvas);
    canvas
}

/// What denoises a frame: OIDN ([`Oidn`]), or a stand-in in tests.
pub trait FrameDenoiser: Send {
    /// The frame's image denoised; the error says why not.
    fn denoise(&mut self, frame: &Frame) -> Result<Canvas, String>;
}

/// OIDN as a [`FrameDenoiser`]: the frame denoised as the render's final image is (guided by
/// its albedo and normals), in the render's session: the passes and the final image share
/// one OIDN device, and its filters while the size stays.
pub struct Oidn<'a> {
    /// The render's session, shared with its final denoise (it is `Sync`: one image at a
    /// time).
    pub session: &'a Session,
}

impl FrameDenoiser for Oidn<'_> {
    fn denoise(&mut self, frame: &Frame) -> Result<Canvas, String> {
        let guides = Guides {
            albedo: &frame.albedo,
            normal: Some(&frame.normal),
        };
        let what = format!("pass {}", frame.pass);
        crate::denoise::denoise(self.session, &frame.image, Some(guides), &what).map_err(
            |failure| match failure {
                Failure::Input(m) | Failure::Internal(m) | Failure::Interrupted(m) => m,
                Failure::Scene(report) => report.to_string(),
            },
        )
    }
}

/// Whether an offered frame was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Offer {
    /// The denoiser was idle and took it.
    Taken,
    /// The denoiser was busy (or had failed): the frame was not made.
    Skipped,
}

/// How the denoising beside the render went.
#[derive(Debug, Default)]
pub struct Summary {
    /// Frames denoised and handed on.
    pub denoised: usize,
    /// Frames skipped because the denoiser was busy.
    pub skipped: usize,
    /// The time the denoiser spent on the frames it denoised (reported, never decided on).
    pub time: Duration,
    /// The first failure, after which no frame was taken.
    pub failure: Option<String>,
}

/// What the denoiser's thread reports when it ends: frames denoised, their time, a failure.
type Denoised = (usize, Duration, Option<String>);

/// The thread that denoises frames beside the render, and the render's side of it.
pub struct LiveDenoiser<'scope> {
    /// Where a taken frame goes: one slot, never full when a frame is sent (see `offer`).
    frames: mpsc::SyncSender<Frame>,
    /// Set from the moment a frame is taken until it is denoised (and for good after a
    /// failure).
    busy: Arc<AtomicBool>,
    skipped: AtomicUsize,
    thread: ScopedJoinHandle<'scope, Denoised>,
}

impl<'scope> LiveDenoiser<'scope> {
    /// Starts the denoiser's thread in `scope`: each frame it takes is denoised by `denoiser`
    /// and handed to `deliver` with the denoised image (on that thread, which is idle again by
    /// then: a slow viewer delays the next denoise, never the render).
    pub fn start<'env, D, F>(
        scope: &'scope Scope<'scope, 'env>,
        mut denoiser: D,
        mut deliver: F,
    ) -> Self
    where
        D: FrameDenoiser + 'scope,
        F: FnMut(&Frame, Canvas) + Send + 'scope,
    {
        let (frames, taken) = mpsc::sync_channel::<Frame>(1);
        let busy = Arc::new(AtomicBool::new(false));
        let idle = busy.clone();
        let thread = scope.spawn(move || {
            let (mut denoised, mut time) = (0, Duration::ZERO);
            for frame in taken {
                let started = Instant::now();
                match denoiser.denoise(&frame) {
                    Ok(image) => {
                        time += started.elapsed();
                        idle.store(false, Ordering::Release);
                        denoised += 1;
                        deliver(&frame, image);
                    }
                    // Busy for good: no more frames are taken, and the render's own denoise
                    // of its last image reports what is wrong.
                    Err(failure) => return (denoised, time, Some(failure)),
                }
            }
            (denoised, time, None)
        });
        Self {
            frames,
            busy,
            skipped: AtomicUsize::new(0),
            thread,
        }
    }

    /// Offers the frame `make` makes: made and taken when the denoiser is idle, else skipped
    /// (and not made).
    pub fn offer(&self, make: impl FnOnce() -> Frame) -> Offer {
        if self.busy.swap(true, Ordering::AcqRel) {
            self.skipped.fetch_add(1, Ordering::Relaxed);
            return Offer::Skipped;
        }
        // The denoiser was idle: it has taken every frame sent before (it clears `busy` only
        // after taking one), so the slot is empty and this never waits. It fails only when the
        // thread has ended, which it does only after a failure, and then `busy` stays set.
        let _ = self.frames.send(make());
        Offer::Taken
    }

    /// Waits for the frame being denoised (and handed on), and says how it went.
    pub fn finish(self) -> Summary {
        drop(self.frames);
        let (denoised, time, failure) = self.thread.join().unwrap_or_else(|_| {
            let failure = "the denoising thread failed".to_string();
            (0, Duration::ZERO, Some(failure))
        });
        Summary {
            denoised,
            skipped: self.skipped.into_inner(),
            time,
            failure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::color::Color;
    use std::sync::mpsc::{channel, Receiver, Sender};

    /// A frame of 2 × 1 pixels whose image is all `value`.
    fn frame(pass: usize, value: f64) -> Frame {
        let image = Canvas::from_pixels(2, 1, vec![Color::WHITE * value; 2]);
        Frame {
            image: image.clone(),
            albedo: image.clone(),
            normal: image,
            pass,
            samples: 1 << pass,
        }
    }

    /// A stand-in that says when it starts each frame, then waits to be let go; its result
    /// is the image halved, or a failure when told so.
    struct Blocking {
        started: Sender<usize>,
        go: Receiver<bool>,
    }

    impl FrameDenoiser for Blocking {
        fn denoise(&mut self, frame: &Frame) -> Result<Canvas, String> {
            let _ = self.started.send(frame.pass);
            let ok = self.go.recv().unwrap_or(false);
            if !ok {
                return Err("told to fail".into());
            }
            let pixels = frame.image.pixels().iter().map(|&c| c * 0.5).collect();
            Ok(Canvas::from_pixels(2, 1, pixels))
        }
    }

    /// A stand-in and the ends that drive it: its starts, its go-aheads, its deliveries.
    type Rig = (Blocking, Receiver<usize>, Sender<bool>);

    fn rig() -> Rig {
        let (started, starts) = channel();
        let (go_ahead, go) = channel();
        (Blocking { started, go }, starts, go_ahead)
    }

    #[test]
    fn a_frame_offered_while_one_is_denoised_is_skipped_not_queued() {
        let (stand_in, starts, go) = rig();
        let (delivered, deliveries) = channel();
        let summary = std::thread::scope(|scope| {
            let live = LiveDenoiser::start(scope, stand_in, move |f: &Frame, image| {
                let _ = delivered.send((f.pass, image));
            });
            assert_eq!(live.offer(|| frame(1, 1.0)), Offer::Taken);
            // The denoiser holds pass 1 until it is let go: passes 2 and 3 are skipped, and
            // not even made.
            assert_eq!(starts.recv().unwrap(), 1);
            assert_eq!(live.offer(|| frame(2, 2.0)), Offer::Skipped);
            let mut made = false;
            assert_eq!(
                live.offer(|| {
                    made = true;
                    frame(3, 3.0)
                }),
                Offer::Skipped
            );
            assert!(!made, "a skipped frame is not made");
            go.send(true).unwrap();
            let (pass, image) = deliveries.recv().unwrap();
            assert_eq!(pass, 1);
            assert_eq!(image.pixels()[0], Color::WHITE * 0.5);
            // Idle again once its frame is handed on: pass 4 is taken.
            assert_eq!(live.offer(|| frame(4, 4.0)), Offer::Taken);
            assert_eq!(starts.recv().unwrap(), 4);
            go.send(true).unwrap();
            live.finish()
        });
        // Pass 4 was handed on before `finish` returned; 2 and 3 never reached the denoiser.
        let passes: Vec<usize> = deliveries.try_iter().map(|(p, _)| p).collect();
        assert_eq!(passes, [4]);
        assert!(starts.try_recv().is_err(), "only passes 1 and 4 started");
        assert_eq!((summary.denoised, summary.skipped), (2, 2));
        assert_eq!(summary.failure, None);
    }

    #[test]
    fn finish_waits_for_the_frame_in_hand_and_a_failure_stops_the_taking() {
        let (stand_in, starts, go) = rig();
        let summary = std::thread::scope(|scope| {
            let live = LiveDenoiser::start(scope, stand_in, |_: &Frame, _| {
                panic!("nothing is delivered")
            });
            assert_eq!(live.offer(|| frame(1, 1.0)), Offer::Taken);
            assert_eq!(starts.recv().unwrap(), 1);
            go.send(false).unwrap();
            // After the failure the denoiser counts as busy for good (whether or not its
            // thread has ended yet).
            assert_eq!(live.offer(|| frame(2, 1.0)), Offer::Skipped);
            live.finish()
        });
        assert_eq!(summary.denoised, 0);
        assert!(summary.failure.unwrap().contains("told to fail"));
    }

    #[test]
    fn frames_offered_to_an_idle_denoiser_are_all_taken() {
        let (stand_in, starts, go) = rig();
        let (delivered, deliveries) = channel();
        std::thread::scope(|scope| {
            let live = LiveDenoiser::start(scope, stand_in, move |f: &Frame, _| {
                let _ = delivered.send(f.pass);
            });
            for pass in 1..=3 {
                assert_eq!(live.offer(|| frame(pass, 1.0)), Offer::Taken);
                assert_eq!(starts.recv().unwrap(), pass);
                go.send(true).unwrap();
                assert_eq!(deliveries.recv().unwrap(), pass);
            }
            assert_eq!(live.finish().skipped, 0);
        });
    }
}
