//! The evaluator and the back end on two threads, batches handed from one
//! to the other, the order of everything the one thread's order.

use super::backend::Backend;
use crate::ir;
use crate::lower::{self, Pipeline};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Run `front` (the evaluator) with a sink that hands each batch to
/// `backend` on a thread of its own, so lowering and printing one batch
/// overlap making the next; `backend` is given back when both are done.
/// Memory stays bounded: at most [`BATCHES_IN_FLIGHT`] batches wait between
/// the two ([`Throttle`]). The order of everything is the one thread's
/// order. Where no thread can be started, both run on this one.
pub(super) fn on_two_threads<'s, R>(
    mut backend: Backend<'s>,
    front: impl FnOnce(&mut dyn ir::Sink) -> R,
) -> (R, Backend<'s>) {
    // The first passes run on the evaluator's thread, if there are two.
    let (ahead, lower_options) = backend.ahead();
    backend.ahead = ahead;
    let backend = Mutex::new(backend);
    let slot = &backend;
    let throttle = &Throttle::new();
    let result = std::thread::scope(|scope| {
        // The start and every batch the throttle lets through: never full.
        let (to_back, from_front) = mpsc::sync_channel(BATCHES_IN_FLIGHT + 1);
        let (to_front, spare) = mpsc::sync_channel(BATCHES_IN_FLIGHT + 1);
        let back = std::thread::Builder::new()
            .name("ger back end".into())
            .spawn_scoped(scope, move || {
                let _gone = throttle.gone_on_drop();
                let mut apart = Apart::new();
                let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
                for handed in from_front {
                    match handed {
                        Handed::Start(start) => ir::Sink::start(&mut *backend, &start),
                        Handed::Batch(mut batch, front_cpu) => {
                            apart.keep_off(front_cpu);
                            ir::Sink::batch(&mut *backend, &mut batch);
                            // Full: the front allocates another.
                            let _ = to_front.try_send(batch);
                            throttle.lowered();
                        }
                    }
                }
            });
        let Ok(back) = back else {
            // One thread: it runs the back end, every pass, too.
            let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
            backend.ahead = 0;
            return front(&mut *backend);
        };
        let mut handoff = Handoff {
            throttle,
            to_back,
            spare,
            ahead,
            lower_options,
            lowering: None,
            lower_time: Duration::ZERO,
        };
        let result = front(&mut handoff);
        let (lowering, lower_time) = handoff.finish();
        // The hand-off is gone: the back end has seen the last batch.
        if let Err(panic) = back.join() {
            std::panic::resume_unwind(panic);
        }
        let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
        backend.lowered_ahead = lowering;
        backend.lower_time += lower_time;
        backend.lower_time_ahead = lower_time;
        result
    });
    (
        result,
        backend.into_inner().unwrap_or_else(PoisonError::into_inner),
    )
}

/// Batches made but not yet lowered, at most. Eight (about 1.4 MB of
/// statements at most): the evaluator runs on while the back end is held
/// up a moment (the kernel's work on its core: the output's writeback is
/// started there), and a batch comes back to be filled after the back
/// end's core has moved on from its lines. With two, a 200k compile took
/// 1–2 ms longer (ARCHITECTURE, "The ninth stop"; two and four measured
/// again in the tenth: no faster).
const BATCHES_IN_FLIGHT: usize = 8;

/// Where the evaluator, held up by [`BATCHES_IN_FLIGHT`] batches not yet
/// lowered, goes on: when the back end has lowered half of them. Woken
/// as each one is lowered, it made one batch and waited again, a hundred
/// times in a `ger stats` of the 200k program on grbl with its steps
/// (the back end the slower thread): each wait and wake some microseconds
/// of both threads' time; with half, ten times (docs/performance.md,
/// "The evaluator held back by halves").
const RESUME_AT: usize = BATCHES_IN_FLIGHT / 2;

/// The batches handed to the back end and not yet lowered, and the
/// evaluator, parked while there are [`BATCHES_IN_FLIGHT`] of them until
/// there are [`RESUME_AT`].
struct Throttle {
    in_flight: AtomicUsize,
    /// The evaluator is parked, or about to be.
    waiting: AtomicBool,
    /// The back end's thread has ended (a panic too): nothing will lower
    /// the batches left.
    gone: AtomicBool,
    evaluator: std::thread::Thread,
}

impl Throttle {
    /// Made on the evaluator's thread.
    fn new() -> Throttle {
        Throttle {
            in_flight: AtomicUsize::new(0),
            waiting: AtomicBool::new(false),
            gone: AtomicBool::new(false),
            evaluator: std::thread::current(),
        }
    }

    /// On the evaluator's thread, before it hands a batch on: wait while
    /// [`BATCHES_IN_FLIGHT`] are, until [`RESUME_AT`] are.
    fn admit(&self) {
        // Sequentially consistent throughout: the evaluator writes
        // `waiting` and reads `in_flight`, the back end the other way round,
        // so at least one of them sees the other's write (it does not park,
        // or it is woken).
        if self.in_flight.load(Ordering::SeqCst) >= BATCHES_IN_FLIGHT {
            self.waiting.store(true, Ordering::SeqCst);
            while self.in_flight.load(Ordering::SeqCst) > RESUME_AT
                && !self.gone.load(Ordering::SeqCst)
            {
                // A wake-up for nothing (`park` allows them) waits again.
                std::thread::park();
            }
            self.waiting.store(false, Ordering::SeqCst);
        }
        self.in_flight.fetch_add(1, Ordering::SeqCst);
    }

    /// On the back end's thread: a batch lowered.
    fn lowered(&self) {
        let left = self.in_flight.fetch_sub(1, Ordering::SeqCst) - 1;
        if left <= RESUME_AT && self.waiting.load(Ordering::SeqCst) {
            self.evaluator.unpark();
        }
    }

    /// A guard that, dropped as the back end's thread ends (or unwinds),
    /// lets the evaluator go on for good.
    fn gone_on_drop(&self) -> impl Drop + '_ {
        struct Gone<'t>(&'t Throttle);
        impl Drop for Gone<'_> {
            fn drop(&mut self) {
                self.0.gone.store(true, Ordering::SeqCst);
                self.0.evaluator.unpark();
            }
        }
        Gone(self)
    }
}

/// The back end's thread kept off the processor the evaluator's thread
/// was last seen on (Linux, where more than one is allowed). Left to
/// itself, the kernel now and then wakes the back end, woken for each
/// batch, on the evaluator's processor and leaves it there while the
/// other idles, and the compile takes up to twice as long (on this
/// project's virtual machine, traced, the threads shared a processor for
/// more than 3 ms in 74–85 of 200 runs of the 200k program, 6–10 with
/// this; ARCHITECTURE.md, "The eleventh stop"). The evaluator's thread is
/// left free, to go wherever the kernel sends it (a faster core, say):
/// each batch says where it was, and the back end moves off that
/// processor when it changes (one system call then, none otherwise). The
/// thread ends with the compile, and its affinity with it.
struct Apart {
    #[cfg(target_os = "linux")]
    allowed: Option<rustix::thread::CpuSet>,
    /// The processor kept off, if any yet.
    off: Option<usize>,
}

impl Apart {
    pub(super) fn new() -> Apart {
        Apart {
            #[cfg(target_os = "linux")]
            allowed: rustix::thread::sched_getaffinity(None)
                .ok()
                .filter(|cpus| cpus.count() >= 2),
            off: None,
        }
    }

    /// Keep off `cpu`, where the evaluator was when it sent the batch. A
    /// failure leaves the thread where the kernel puts it.
    fn keep_off(&mut self, cpu: usize) {
        if self.off == Some(cpu) {
            return;
        }
        self.off = Some(cpu);
        #[cfg(target_os = "linux")]
        if let Some(allowed) = &self.allowed {
            if cpu >= rustix::thread::CpuSet::MAX_CPU {
                return;
            }
            let mut others = *allowed;
            others.unset(cpu);
            if others.count() > 0 {
                let _ = rustix::thread::sched_setaffinity(None, &others);
            }
        }
    }
}

/// The processor this thread is on (0 where it cannot be known).
fn this_cpu() -> usize {
    #[cfg(target_os = "linux")]
    {
        rustix::thread::sched_getcpu()
    }
    #[cfg(not(target_os = "linux"))]
    {
        0
    }
}

/// What the evaluator sends the back-end thread.
enum Handed {
    Start(Box<ir::Start>),
    /// A batch, and the processor the evaluator sent it from.
    Batch(Vec<ir::Stmt>, usize),
}

/// The evaluator's end of [`on_two_threads`]: it runs the first `ahead`
/// passes on each batch and hands what comes out on.
struct Handoff<'t> {
    throttle: &'t Throttle,
    to_back: mpsc::SyncSender<Handed>,
    /// Emptied batches coming back, to be filled again.
    pub(super) spare: mpsc::Receiver<Vec<ir::Stmt>>,
    pub(super) ahead: usize,
    pub(super) lower_options: lower::LowerOptions,
    /// Those passes, made when the program starts.
    pub(super) lowering: Option<Pipeline>,
    pub(super) lower_time: Duration,
}

impl Handoff<'_> {
    /// The end of the program: the passes flush what they hold back.
    /// Returns them (for their diagnostics) and the time they took.
    pub(super) fn finish(mut self) -> (Option<Pipeline>, Duration) {
        if let Some(lowering) = &mut self.lowering {
            let (t0, mut handing) = (Instant::now(), Duration::ZERO);
            let handing_on = (self.throttle, &self.to_back, &self.spare);
            lowering.finish(&mut |lowered| handing += hand_on(handing_on, lowered));
            self.lower_time += t0.elapsed().saturating_sub(handing);
        }
        (self.lowering, self.lower_time)
    }
}

/// What a batch is handed on through: the throttle, the channel to the
/// back end, the emptied batches coming back.
type HandingOn<'h> = (
    &'h Throttle,
    &'h mpsc::SyncSender<Handed>,
    &'h mpsc::Receiver<Vec<ir::Stmt>>,
);

/// Send `stmts` to the back end, and leave an empty batch in their place;
/// the time it took (waiting while the back end is behind).
fn hand_on((throttle, to_back, spare): HandingOn, stmts: &mut Vec<ir::Stmt>) -> Duration {
    let t0 = Instant::now();
    // After the wait, if any: batches lowered meanwhile have come back.
    throttle.admit();
    let empty = spare
        .try_recv()
        .unwrap_or_else(|_| Vec::with_capacity(stmts.capacity()));
    let full = std::mem::replace(stmts, empty);
    let _ = to_back.send(Handed::Batch(full, this_cpu()));
    t0.elapsed()
}

impl ir::Sink for Handoff<'_> {
    fn start(&mut self, start: &ir::Start) {
        if self.ahead > 0 {
            let context = lower::Context {
                start,
                options: &self.lower_options,
            };
            self.lowering = Some(Pipeline::new(&context, 0..self.ahead));
        }
        let _ = self.to_back.send(Handed::Start(Box::new(start.clone())));
    }

    /// Lower the batch through the passes ahead (if any) and send what
    /// comes out to the back end, leaving an empty batch in its place.
    fn batch(&mut self, batch: &mut Vec<ir::Stmt>) {
        let handing_on = (self.throttle, &self.to_back, &self.spare);
        match &mut self.lowering {
            Some(lowering) => {
                let (t0, mut handing) = (Instant::now(), Duration::ZERO);
                lowering.run(batch, &mut |lowered| {
                    handing += hand_on(handing_on, lowered)
                });
                self.lower_time += t0.elapsed().saturating_sub(handing);
            }
            None => {
                hand_on(handing_on, batch);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    /// The back end moves off the evaluator's processor, and only off it:
    /// every other allowed processor stays allowed. (On one processor
    /// nothing changes.)
    #[cfg(target_os = "linux")]
    #[test]
    fn the_back_end_keeps_off_the_evaluators_processor() {
        use rustix::thread::sched_getaffinity;
        std::thread::spawn(|| {
            let allowed = sched_getaffinity(None).unwrap();
            let here = this_cpu();
            assert!(allowed.is_set(here));
            let mut apart = Apart::new();
            apart.keep_off(here);
            let now = sched_getaffinity(None).unwrap();
            if allowed.count() < 2 {
                assert_eq!(now, allowed);
                return;
            }
            assert!(!now.is_set(here), "still allowed on {here}");
            assert_eq!(now.count(), allowed.count() - 1);
            assert_ne!(this_cpu(), here, "not moved off {here}");
            // The evaluator moved: the first one is allowed again.
            let other = (0..rustix::thread::CpuSet::MAX_CPU)
                .find(|&c| c != here && allowed.is_set(c))
                .unwrap();
            apart.keep_off(other);
            let now = sched_getaffinity(None).unwrap();
            assert!(now.is_set(here) && !now.is_set(other));
        })
        .join()
        .unwrap();
    }

    /// The evaluator hands on as many batches as may be in flight without
    /// waiting; the next waits until the back end has lowered down to
    /// `RESUME_AT`, not for the first one lowered, nor for more.
    #[test]
    fn the_evaluator_waits_for_half_the_batches_to_be_lowered() {
        let throttle = Throttle::new();
        let (lowered, went_on) = (AtomicUsize::new(0), AtomicBool::new(false));
        for _ in 0..BATCHES_IN_FLIGHT {
            throttle.admit();
        }
        std::thread::scope(|scope| {
            scope.spawn(|| {
                for n in 1..=BATCHES_IN_FLIGHT {
                    std::thread::sleep(Duration::from_millis(2));
                    lowered.store(n, Ordering::SeqCst);
                    throttle.lowered();
                    if n == BATCHES_IN_FLIGHT - RESUME_AT {
                        // No more until the evaluator has gone on.
                        while !went_on.load(Ordering::SeqCst) {
                            std::thread::sleep(Duration::from_millis(1));
                        }
                    }
                }
            });
            throttle.admit();
            went_on.store(true, Ordering::SeqCst);
            assert_eq!(
                lowered.load(Ordering::SeqCst),
                BATCHES_IN_FLIGHT - RESUME_AT
            );
        });
        assert_eq!(throttle.in_flight.load(Ordering::SeqCst), 1);
    }

    /// A back end that ends (or panics) with batches not lowered lets the
    /// evaluator go on: it never waits for good.
    #[test]
    fn a_back_end_gone_lets_the_evaluator_go_on() {
        let throttle = Throttle::new();
        for _ in 0..BATCHES_IN_FLIGHT {
            throttle.admit();
        }
        std::thread::scope(|scope| {
            let back = scope.spawn(|| {
                let _gone = throttle.gone_on_drop();
                std::thread::sleep(Duration::from_millis(5));
                panic!("the back end fails");
            });
            throttle.admit();
            assert!(throttle.gone.load(Ordering::SeqCst));
            assert!(back.join().is_err());
        });
    }
}
