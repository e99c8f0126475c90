//! Do two tool paths move the tool the same way? Move by move within a
//! tolerance (after dropping moves shorter than it, and optionally after
//! merging collinear lines and co-circular arcs), or by sampling both
//! paths and walking each along the other in order. The differential tests
//! use it against `rs274`; the round-trip fuzzer uses it on ger's own
//! output.

use super::{distance, EventKind, Move, MoveKind, Point, ToolPath};
use std::fmt;

#[derive(Clone, Debug)]
pub struct Options {
    /// mm.
    pub tol: f64,
    /// Relative tolerance of feeds and speeds.
    pub feed_tol: f64,
    /// Merge consecutive collinear lines and co-circular arcs first.
    pub merge: bool,
    /// Compare sampled polylines with this step (mm) instead of moves.
    pub sample: Option<f64>,
    pub ignore_feed: bool,
    /// Spindle and coolant.
    pub ignore_spindle: bool,
    pub ignore_tools: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tol: 0.001,
            feed_tol: 1e-3,
            merge: false,
            sample: None,
            ignore_feed: false,
            ignore_spindle: false,
            ignore_tools: false,
        }
    }
}

/// The first difference found, with the moves it is about.
#[derive(Clone, Debug)]
pub struct Difference {
    pub message: String,
    pub a: Option<Box<Move>>,
    pub b: Option<Box<Move>>,
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.message)?;
        for (label, m) in [("A", &self.a), ("B", &self.b)] {
            if let Some(m) = m {
                write!(f, "\n  {label} line {}: {}", m.span.line, describe(m))?;
            }
        }
        Ok(())
    }
}

fn describe(m: &Move) -> String {
    let p = |p: Point| format!("({:.4}, {:.4}, {:.4})", p[0], p[1], p[2]);
    let kind = match m.kind {
        MoveKind::Rapid => "rapid".to_string(),
        MoveKind::Feed => "feed".to_string(),
        MoveKind::Arc(a) => format!(
            "arc {:?} {} center {}",
            a.plane,
            if a.clockwise { "cw" } else { "ccw" },
            p(a.center)
        ),
    };
    format!(
        "{kind} {} -> {} F{} S{} T{}",
        p(m.start),
        p(m.end),
        m.state.feed,
        m.state.rpm,
        m.state.tool
    )
}

/// `Ok(number of moves compared)` or the first difference.
pub fn compare(a: &ToolPath, b: &ToolPath, o: &Options) -> Result<usize, Difference> {
    let ma = prepare(&a.moves, o);
    let mb = prepare(&b.moves, o);
    match o.sample {
        Some(step) => compare_sampled(&ma, &mb, step, o)?,
        None => compare_exact(&ma, &mb, o)?,
    }
    if !o.ignore_tools {
        let (ta, tb) = (tool_changes(a), tool_changes(b));
        if ta != tb {
            return Err(Difference {
                message: format!("tool change sequence {ta:?} vs {tb:?}"),
                a: None,
                b: None,
            });
        }
    }
    compare_pauses(a, b, o)?;
    Ok(ma.len())
}

fn tool_changes(path: &ToolPath) -> Vec<u32> {
    let mut tools: Vec<u32> = path
        .events
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::ToolChange(t) => Some(t),
            EventKind::Dwell(_) | EventKind::Stop(_) | EventKind::Sync { .. } | EventKind::End => {
                None
            }
        })
        .collect();
    tools.dedup();
    tools
}

/// The dwells and stops of a path, in order, each with where the tool is
/// when it happens (the end of the move before it).
fn pauses(path: &ToolPath) -> Vec<(EventKind, Point)> {
    path.events
        .iter()
        // A dwell of no time is no pause (rs274's G84 writes one).
        .filter(|e| match e.kind {
            EventKind::Dwell(seconds) => seconds > 0.0,
            EventKind::Stop(_) => true,
            EventKind::ToolChange(_) | EventKind::Sync { .. } | EventKind::End => false,
        })
        .map(|e| {
            let at = match e.after_move.checked_sub(1) {
                Some(i) => path.moves.get(i).map_or([0.0; 3], |m| m.end),
                None => [0.0; 3],
            };
            (e.kind, at)
        })
        .collect()
}

/// Dwells (their seconds) and stops must come in the same order at the
/// same places. The program end is not compared: ger adds one where the
/// input has none.
fn compare_pauses(a: &ToolPath, b: &ToolPath, o: &Options) -> Result<(), Difference> {
    let (pa, pb) = (pauses(a), pauses(b));
    for (i, ((ka, at_a), (kb, at_b))) in pa.iter().zip(&pb).enumerate() {
        let same_kind = match (ka, kb) {
            (EventKind::Dwell(x), EventKind::Dwell(y)) => (x - y).abs() <= 1e-3 * x.abs().max(1.0),
            (x, y) => x == y,
        };
        if !same_kind || distance(*at_a, *at_b) > o.tol {
            return Err(Difference {
                message: format!("pause {}: {ka:?} at {at_a:?} vs {kb:?} at {at_b:?}", i + 1),
                a: None,
                b: None,
            });
        }
    }
    if pa.len() != pb.len() {
        return Err(Difference {
            message: format!("{} dwells and stops vs {}", pa.len(), pb.len()),
            a: None,
            b: None,
        });
    }
    Ok(())
}

/// Moves longer than the tolerance (or that turn a rotary axis), merged
/// when asked.
fn prepare(moves: &[Move], o: &Options) -> Vec<Move> {
    let mut kept: Vec<Move> = Vec::with_capacity(moves.len());
    let mut extra = [0.0; 6];
    for m in moves {
        let turns_rotary = (0..3).any(|i| (m.extra[i] - extra[i]).abs() > o.tol);
        if m.length() > o.tol || turns_rotary {
            kept.push(*m);
        }
        extra = m.extra;
    }
    if !o.merge {
        return kept;
    }
    let mut merged: Vec<Move> = Vec::with_capacity(kept.len());
    let mut chain_start = 0;
    for (i, m) in kept.iter().enumerate() {
        let chain = &kept[chain_start..i];
        if !chain.is_empty() && can_merge(chain, m, o) {
            continue;
        }
        if !chain.is_empty() {
            merged.push(merge(chain));
        }
        chain_start = i;
    }
    if chain_start < kept.len() {
        merged.push(merge(&kept[chain_start..]));
    }
    merged
}

fn can_merge(chain: &[Move], m: &Move, o: &Options) -> bool {
    let last = &chain[chain.len() - 1];
    if state_difference(last, m, o).is_some() || last.extra != m.extra {
        return false;
    }
    match (last.kind, m.kind) {
        (MoveKind::Arc(a), MoveKind::Arc(b)) => {
            let (p, q, _) = a.plane.axes();
            let radius = |at: Point| (at[p] - a.center[p]).hypot(at[q] - a.center[q]);
            let r = radius(last.start);
            a.plane == b.plane
                && a.clockwise == b.clockwise
                && (a.center[p] - b.center[p]).hypot(a.center[q] - b.center[q]) <= o.tol
                && [m.start, m.end]
                    .iter()
                    .all(|&x| (radius(x) - r).abs() <= o.tol)
        }
        (MoveKind::Rapid, MoveKind::Rapid) | (MoveKind::Feed, MoveKind::Feed) => {
            let (s, e) = (chain[0].start, m.end);
            let forward = dot(sub(e, s), sub(last.end, s)) > 0.0;
            forward && chain.iter().all(|x| point_segment(x.end, s, e) <= o.tol)
        }
        _ => false,
    }
}

fn merge(chain: &[Move]) -> Move {
    let mut m = chain[0];
    m.end = chain[chain.len() - 1].end;
    m.extra = chain[chain.len() - 1].extra;
    if let MoveKind::Arc(a) = &mut m.kind {
        let sweep: f64 = chain.iter().map(Move::sweep).sum();
        a.turns = ((sweep / std::f64::consts::TAU) - 1e-9).ceil().max(1.0) as u32;
    }
    m
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn point_segment(p: Point, a: Point, b: Point) -> f64 {
    let (ab, ap) = (sub(b, a), sub(p, a));
    let l = dot(ab, ab);
    let t = if l == 0.0 {
        0.0
    } else {
        (dot(ap, ab) / l).clamp(0.0, 1.0)
    };
    distance(ap, [ab[0] * t, ab[1] * t, ab[2] * t])
}

fn state_difference(a: &Move, b: &Move, o: &Options) -> Option<String> {
    if matches!(a.kind, MoveKind::Rapid) || matches!(b.kind, MoveKind::Rapid) {
        return None;
    }
    let (sa, sb) = (a.state, b.state);
    let differs = |x: f64, y: f64| (x - y).abs() > o.feed_tol * x.abs().max(y.abs()).max(1.0);
    // A pitch is small: compared relative to itself, not to 1 mm.
    let same_lead = match (sa.lead, sb.lead) {
        (Some(x), Some(y)) => (x - y).abs() <= o.feed_tol * x.abs().max(y.abs()),
        (x, y) => x == y,
    };
    if !same_lead {
        return Some(format!(
            "spindle-synchronised K {:?} vs {:?} (mm/rev)",
            sa.lead, sb.lead
        ));
    }
    // A thread's speed is the spindle's: the F in force does not matter.
    if !o.ignore_feed && sa.lead.is_none() && differs(sa.feed, sb.feed) {
        return Some(format!("feed F{} vs F{} (mm/min)", sa.feed, sb.feed));
    }
    if !o.ignore_spindle {
        if sa.spindle != sb.spindle {
            return Some(format!("spindle {:?} vs {:?}", sa.spindle, sb.spindle));
        }
        if sa.spindle.is_some() && differs(sa.rpm, sb.rpm) {
            return Some(format!("spindle speed S{} vs S{}", sa.rpm, sb.rpm));
        }
        if (sa.flood, sa.mist) != (sb.flood, sb.mist) {
            return Some("coolant differs".to_string());
        }
    }
    if !o.ignore_tools && sa.tool != sb.tool {
        return Some(format!("tool T{} vs T{}", sa.tool, sb.tool));
    }
    let same_control = match (sa.path_control, sb.path_control) {
        (x, y) if x.tolerances().is_none() || y.tolerances().is_none() => x == y,
        (x, y) => {
            let ((p, q), (r, s)) = (x.tolerances()?, y.tolerances()?);
            (p - r).abs() <= o.tol && (q - s).abs() <= o.tol
        }
    };
    if !same_control {
        return Some(format!(
            "path control {:?} vs {:?}",
            sa.path_control, sb.path_control
        ));
    }
    None
}

fn move_difference(a: &Move, b: &Move, o: &Options) -> Option<String> {
    let kind = |m: &Move| match m.kind {
        MoveKind::Rapid => "rapid",
        MoveKind::Feed => "feed",
        MoveKind::Arc(_) => "arc",
    };
    if kind(a) != kind(b) {
        return Some(format!("kind {} vs {}", kind(a), kind(b)));
    }
    let d = distance(a.end, b.end);
    if d > o.tol {
        return Some(format!("end point differs by {d:.6} mm"));
    }
    if (0..6).any(|i| (a.extra[i] - b.extra[i]).abs() > o.tol) {
        return Some("extra axes (A B C U V W) differ".to_string());
    }
    if let (MoveKind::Arc(x), MoveKind::Arc(y)) = (a.kind, b.kind) {
        // The same rotation: same plane and direction, or the opposite
        // direction seen from the other side (never, for G17–G19).
        if x.plane != y.plane || x.clockwise != y.clockwise {
            return Some(format!(
                "arc {:?} {} vs {:?} {}",
                x.plane,
                if x.clockwise { "cw" } else { "ccw" },
                y.plane,
                if y.clockwise { "cw" } else { "ccw" }
            ));
        }
        let d = distance(x.center, y.center);
        if d > o.tol {
            return Some(format!("arc center differs by {d:.6} mm"));
        }
        let (p, q, _) = x.plane.axes();
        let r = (a.start[p] - x.center[p]).hypot(a.start[q] - x.center[q]);
        if (a.sweep() - b.sweep()).abs() * r > o.tol {
            return Some(format!(
                "arc sweep {:.4} vs {:.4} degrees",
                a.sweep().to_degrees(),
                b.sweep().to_degrees()
            ));
        }
    }
    state_difference(a, b, o)
}

fn compare_exact(ma: &[Move], mb: &[Move], o: &Options) -> Result<(), Difference> {
    for (i, (a, b)) in ma.iter().zip(mb).enumerate() {
        if let Some(why) = move_difference(a, b, o) {
            return Err(Difference {
                message: format!("move {i}: {why}"),
                a: Some(Box::new(*a)),
                b: Some(Box::new(*b)),
            });
        }
    }
    if ma.len() != mb.len() {
        let n = ma.len().min(mb.len());
        return Err(Difference {
            message: format!("{} moves vs {}", ma.len(), mb.len()),
            a: ma.get(n).copied().map(Box::new),
            b: mb.get(n).copied().map(Box::new),
        });
    }
    Ok(())
}

/// Points every `step` along the moves (arcs finer, so that a chord stays
/// within a tenth of the tolerance), each with its move's index.
fn samples(moves: &[Move], step: f64, tol: f64) -> Vec<(Point, usize)> {
    let mut out = Vec::new();
    for (i, m) in moves.iter().enumerate() {
        let mut n = (m.length() / step).ceil().max(1.0);
        if let MoveKind::Arc(a) = m.kind {
            let (p, q, _) = a.plane.axes();
            let r = (m.start[p] - a.center[p]).hypot(m.start[q] - a.center[q]);
            if r > tol / 10.0 {
                let chord_angle = 2.0 * (1.0 - tol / 10.0 / r).clamp(-1.0, 1.0).acos();
                n = n.max((m.sweep() / chord_angle.max(1e-6)).ceil());
            }
        }
        let n = n.min(100_000.0) as usize;
        if i == 0 {
            out.push((m.start, i));
        }
        for k in 1..=n {
            out.push((m.at(k as f64 / n as f64), i));
        }
    }
    out
}

/// Every point of `p` lies within `tol` of the polyline `q`, in order,
/// on a piece whose move is `compatible` with the point's.
fn walk(
    p: &[(Point, usize)],
    q: &[(Point, usize)],
    tol: f64,
    compatible: impl Fn(usize, usize) -> bool,
) -> Option<usize> {
    if q.is_empty() {
        return (!p.is_empty()).then_some(0);
    }
    let mut at = 0;
    for (k, &(point, i)) in p.iter().enumerate() {
        let near = |j: usize| {
            let next = (j + 1).min(q.len() - 1);
            let fits = compatible(i, q[next].1) || compatible(i, q[j].1);
            fits && point_segment(point, q[j].0, q[next].0) <= tol
        };
        // A monotone search: the match may only move forward.
        match (at..q.len()).find(|&j| near(j)) {
            Some(j) => at = j,
            None => return Some(k),
        }
    }
    None
}

fn compare_sampled(ma: &[Move], mb: &[Move], step: f64, o: &Options) -> Result<(), Difference> {
    let (sa, sb) = (samples(ma, step, o.tol), samples(mb, step, o.tol));
    for (p, q, p_moves, q_moves, label) in [(&sa, &sb, ma, mb, "A"), (&sb, &sa, mb, ma, "B")] {
        let compatible = |i: usize, j: usize| {
            let (x, y) = (&p_moves[i], &q_moves[j]);
            let cutting = |m: &Move| !matches!(m.kind, MoveKind::Rapid);
            cutting(x) == cutting(y) && state_difference(x, y, o).is_none()
        };
        if let Some(k) = walk(p, q, o.tol, compatible) {
            let (point, i) = p[k];
            let here = p_moves.get(i).copied().map(Box::new);
            return Err(Difference {
                message: format!(
                    "a point of {label} ({:.4}, {:.4}, {:.4}) is off the other path",
                    point[0], point[1], point[2]
                ),
                a: if label == "A" { here.clone() } else { None },
                b: if label == "B" { here } else { None },
            });
        }
    }
    Ok(())
}
