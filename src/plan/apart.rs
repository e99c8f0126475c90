//! [`Tally`] on a thread of its own (`ger stats`): the back end hands the
//! moves over in batches through a bounded channel, so planning overlaps
//! the compile and what the user waits for is the longer of the two, not
//! their sum. At most `BATCHES_AHEAD` batches of `BATCH` moves wait, so
//! memory stays flat. Where no thread can be started, the tally runs on
//! the caller's.
//!
//! Architecture Invariant: the figures are those of a [`Tally`] fed the
//! same moves and events in the same order on the caller's thread; this
//! module plans nothing itself.

use super::{Figures, Limits, Tally};
use crate::toolpath::{Event, Move, PathSink};
use std::sync::mpsc::{self, Receiver, SyncSender};

/// Moves and events handed over at once.
const BATCH: usize = 1024;
/// Batches that may wait for the planner.
const BATCHES_AHEAD: usize = 4;

/// What the back end fed, in its order.
enum Fed {
    Move(Move),
    Event(Event),
    Restart,
}

/// The figures of what `feed` hands its sink, on the machine `limits`
/// describes (length / feed only, without one), planned on a second
/// thread while `feed` runs; `feed`'s result beside them.
pub fn tally_apart<R>(
    limits: Option<&Limits>,
    feed: impl FnOnce(&mut dyn PathSink) -> R,
) -> (R, Figures) {
    std::thread::scope(|scope| {
        let (to, from) = mpsc::sync_channel::<Vec<Fed>>(BATCHES_AHEAD);
        // Batches planned come back to be filled again: no fresh memory
        // (and its page faults) per batch.
        let (to_spare, spare) = mpsc::sync_channel::<Vec<Fed>>(BATCHES_AHEAD + 1);
        let planner = std::thread::Builder::new()
            .name("ger planner".into())
            .spawn_scoped(scope, move || {
                let mut tally = Tally::new(limits, false);
                for mut batch in from {
                    for fed in &batch {
                        match fed {
                            Fed::Move(m) => tally.feed_move(m),
                            Fed::Event(e) => tally.feed_event(e),
                            Fed::Restart => tally.restart(),
                        }
                    }
                    batch.clear();
                    let _ = to_spare.try_send(batch);
                }
                tally.finish()
            });
        let Ok(planner) = planner else {
            let mut tally = Tally::new(limits, false);
            let result = feed(&mut tally);
            return (result, tally.finish());
        };
        let mut handoff = Handoff {
            batch: Vec::with_capacity(BATCH),
            to,
            spare,
        };
        let result = feed(&mut handoff);
        handoff.send();
        // The channel closed: the planner has seen the last batch.
        drop(handoff);
        match planner.join() {
            Ok(figures) => (result, figures),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// The back end's side: a sink that fills batches and sends them.
struct Handoff {
    batch: Vec<Fed>,
    to: SyncSender<Vec<Fed>>,
    spare: Receiver<Vec<Fed>>,
}

impl Handoff {
    fn push(&mut self, fed: Fed) {
        self.batch.push(fed);
        if self.batch.len() >= BATCH {
            self.send();
        }
    }

    fn send(&mut self) {
        let next = self
            .spare
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BATCH));
        let batch = std::mem::replace(&mut self.batch, next);
        // A planner gone has panicked: the join says so.
        let _ = self.to.send(batch);
    }
}

impl PathSink for Handoff {
    fn feed_move(&mut self, m: &Move) {
        self.push(Fed::Move(*m));
    }

    fn feed_event(&mut self, e: &Event) {
        self.push(Fed::Event(*e));
    }

    fn restart(&mut self) {
        self.push(Fed::Restart);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::EventKind;

    #[test]
    fn figures_apart_are_those_planned_here() {
        // 5,000 moves (several batches) with dwells between them and a
        // restart after the first 100: the same figures, to the bit.
        let limits = crate::plan::tests::limits();
        let points: Vec<[f64; 3]> = (0..=5000)
            .map(|k| [(k % 7) as f64, (k % 11) as f64 * 0.5, 0.0])
            .collect();
        let mut path = crate::plan::tests::path(&points, 1200.0);
        let events = (0..50)
            .map(|k| Event {
                kind: EventKind::Dwell(0.5),
                after_move: k * 97,
                span: crate::source::Span::new(0, 2, 0, 0),
            })
            .collect();
        path.events = events;
        let feed = |sink: &mut dyn PathSink| {
            for m in &path.moves[..100] {
                sink.feed_move(m);
            }
            sink.restart();
            path.feed_to(sink);
        };
        let mut here = Tally::new(Some(&limits), false);
        feed(&mut here);
        let here = here.finish();
        let ((), apart) = tally_apart(Some(&limits), feed);
        assert_eq!(here.time_s, apart.time_s);
        assert_eq!(format!("{here:?}"), format!("{apart:?}"));
        assert!(here.time_s.unwrap() > 0.0);
    }
}
