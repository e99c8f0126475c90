//! The evaluator and the back end on two threads, batches handed from one
//! to the other, the order of everything the one thread's order.

use super::backend::Backend;
use crate::ir;
use crate::lower::{self, Pipeline};
use std::sync::{mpsc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Run `front` (the evaluator) with a sink that hands each batch to
/// `backend` on a thread of its own, so lowering and printing one batch
/// overlap making the next; `backend` is given back when both are done.
/// Memory stays bounded: at most [`BATCHES_IN_FLIGHT`] batches wait between
/// the two. The order of everything is the one thread's order. Where no
/// thread can be started, both run on this one.
pub(super) fn on_two_threads<'s, R>(
    mut backend: Backend<'s>,
    front: impl FnOnce(&mut dyn ir::Sink) -> R,
) -> (R, Backend<'s>) {
    // The first passes run on the evaluator's thread, if there are two.
    let (ahead, lower_options) = backend.ahead();
    backend.ahead = ahead;
    let backend = Mutex::new(backend);
    let slot = &backend;
    let result = std::thread::scope(|scope| {
        let (to_back, from_front) = mpsc::sync_channel(BATCHES_IN_FLIGHT);
        let (to_front, spare) = mpsc::sync_channel(BATCHES_IN_FLIGHT + 1);
        let back = std::thread::Builder::new()
            .name("ger back end".into())
            .spawn_scoped(scope, move || {
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
struct Handoff {
    to_back: mpsc::SyncSender<Handed>,
    /// Emptied batches coming back, to be filled again.
    pub(super) spare: mpsc::Receiver<Vec<ir::Stmt>>,
    pub(super) ahead: usize,
    pub(super) lower_options: lower::LowerOptions,
    /// Those passes, made when the program starts.
    pub(super) lowering: Option<Pipeline>,
    pub(super) lower_time: Duration,
}

impl Handoff {
    /// The end of the program: the passes flush what they hold back.
    /// Returns them (for their diagnostics) and the time they took.
    pub(super) fn finish(mut self) -> (Option<Pipeline>, Duration) {
        if let Some(lowering) = &mut self.lowering {
            let (t0, mut handing) = (Instant::now(), Duration::ZERO);
            let (to_back, spare) = (&self.to_back, &self.spare);
            lowering.finish(&mut |lowered| handing += hand_on(to_back, spare, lowered));
            self.lower_time += t0.elapsed().saturating_sub(handing);
        }
        (self.lowering, self.lower_time)
    }
}

/// Send `stmts` to the back end, and leave an empty batch in their place;
/// the time it took (waiting while the back end is behind).
fn hand_on(
    to_back: &mpsc::SyncSender<Handed>,
    spare: &mpsc::Receiver<Vec<ir::Stmt>>,
    stmts: &mut Vec<ir::Stmt>,
) -> Duration {
    let t0 = Instant::now();
    let empty = spare
        .try_recv()
        .unwrap_or_else(|_| Vec::with_capacity(stmts.capacity()));
    let full = std::mem::replace(stmts, empty);
    let _ = to_back.send(Handed::Batch(full, this_cpu()));
    t0.elapsed()
}

impl ir::Sink for Handoff {
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
        let (to_back, spare) = (&self.to_back, &self.spare);
        match &mut self.lowering {
            Some(lowering) => {
                let (t0, mut handing) = (Instant::now(), Duration::ZERO);
                lowering.run(batch, &mut |lowered| {
                    handing += hand_on(to_back, spare, lowered)
                });
                self.lower_time += t0.elapsed().saturating_sub(handing);
            }
            None => {
                hand_on(to_back, spare, batch);
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
}
