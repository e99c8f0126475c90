//! The corner geometry against corners worked by hand, and random corners
//! against what a corner must be (on both moves, tangent, r or c away).

use super::{corner_cut, Corner, Cut, CutError, Element, Round, P2};
use crate::ir::Corner as C;

fn line(from: P2, to: P2) -> Element {
    Element::Line { from, to }
}

fn arc(from: P2, to: P2, centre: P2, ccw: bool) -> Element {
    Element::Arc {
        from,
        to,
        centre,
        ccw,
    }
}

fn near(a: P2, b: P2) -> bool {
    (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12 * a[0].abs().max(a[1].abs()).max(1.0) * 10.0
}

/// `cut` is the round from `start` to `end` about the absolute `centre`.
fn assert_round(cut: &Result<Cut, CutError>, start: P2, end: P2, centre: P2, ccw: bool) {
    let Ok(cut) = cut else {
        panic!("no cut: {cut:?}");
    };
    let round = cut.round.as_ref().expect("a round");
    let at = [
        cut.start[0] + round.centre[0],
        cut.start[1] + round.centre[1],
    ];
    assert!(near(cut.start, start), "{cut:?}");
    assert!(near(cut.end, end), "{cut:?}");
    assert!(near(at, centre), "{cut:?}, centre at {at:?}");
    assert_eq!(round.counter_clockwise, ccw, "{cut:?}");
}

/// Worked by hand: a square corner and one turned by 36.87° (the
/// 3-4-5 triangle: tan of its half is 0.5), each way.
#[test]
fn line_corners_worked_by_hand() {
    let left = corner_cut(
        line([0.0, 0.0], [40.0, 0.0]),
        line([40.0, 0.0], [40.0, 30.0]),
        Corner::Round(5.0),
    );
    let expected = Cut {
        start: [35.0, 0.0],
        end: [40.0, 5.0],
        round: Some(Round {
            centre: [0.0, 5.0],
            counter_clockwise: true,
        }),
    };
    assert_eq!(left, Ok(expected));
    let right = corner_cut(
        line([40.0, 30.0], [60.0, 30.0]),
        line([60.0, 30.0], [60.0, 10.0]),
        Corner::Round(3.0),
    );
    assert_round(&right, [57.0, 30.0], [60.0, 27.0], [57.0, 27.0], false);
    let turned = corner_cut(
        line([60.0, 27.0], [60.0, 10.0]),
        line([60.0, 10.0], [68.0, 4.0]),
        Corner::Round(4.0),
    );
    assert_round(&turned, [60.0, 12.0], [61.6, 8.8], [64.0, 12.0], true);
    let chamfer = corner_cut(
        line([0.0, 0.0], [40.0, 0.0]),
        line([40.0, 0.0], [40.0, -30.0]),
        Corner::Chamfer(4.0),
    );
    let expected = Cut {
        start: [36.0, 0.0],
        end: [40.0, -4.0],
        round: None,
    };
    assert_eq!(chamfer, Ok(expected));
}

/// A line along +X into the circle of radius 4 about (44, 0) at its left
/// point, counter-clockwise (down): a right turn. The round of 6 has its
/// centre 6 right of the line (y = −6) and 4 + 6 from the arc's centre:
/// x = 44 − √(10² − 6²) = 36. It touches the line at (36, 0) and the arc
/// 4/10 of the way from (44, 0) to (36, −6): (40.8, −2.4). The same path
/// backwards (a clockwise arc into a line along −X) turns left about the
/// same centre.
#[test]
fn line_into_arc_and_back_worked_by_hand() {
    let cut = corner_cut(
        line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], [48.0, 0.0], [44.0, 0.0], true),
        Corner::Round(6.0),
    );
    assert_round(&cut, [36.0, 0.0], [40.8, -2.4], [36.0, -6.0], false);
    let back = corner_cut(
        arc([44.0, -4.0], [40.0, 0.0], [44.0, 0.0], false),
        line([40.0, 0.0], [0.0, 0.0]),
        Corner::Round(6.0),
    );
    assert_round(&back, [40.8, -2.4], [36.0, 0.0], [36.0, -6.0], true);
}

/// Two counter-clockwise arcs of radius 10, about (0, 0) and (12, 0),
/// meeting at (6, 8): a left turn. The round of 3.5 has its centre 10 − 3.5
/// from both centres: (6, 2.5) (the 2.5-6-6.5 triangle; (6, −2.5), the
/// other, is farther). It touches each arc 10/6.5 of the way from its
/// centre through (6, 2.5): at (120/13, 50/13) and (36/13, 50/13).
#[test]
fn arc_into_arc_worked_by_hand() {
    let cut = corner_cut(
        arc([10.0, 0.0], [6.0, 8.0], [0.0, 0.0], true),
        arc([6.0, 8.0], [2.0, 0.0], [12.0, 0.0], true),
        Corner::Round(3.5),
    );
    let (t1, t2) = ([120.0 / 13.0, 50.0 / 13.0], [36.0 / 13.0, 50.0 / 13.0]);
    assert_round(&cut, t1, t2, [6.0, 2.5], true);
}

/// Chamfers on an arc: the leg is the chord c from the corner. On the
/// circle of radius 4 about (44, 0) from (40, 0), the chord 4.8 is the
/// angle 2·asin(0.6) (cos 0.28, sin 0.96): (44 − 4·0.28, −4·0.96).
#[test]
fn chamfers_on_arcs_worked_by_hand() {
    let cut = corner_cut(
        line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], [48.0, 0.0], [44.0, 0.0], true),
        Corner::Chamfer(4.8),
    );
    let Ok(cut) = cut else { panic!("{cut:?}") };
    assert!(near(cut.start, [35.2, 0.0]), "{cut:?}");
    assert!(near(cut.end, [42.88, -3.84]), "{cut:?}");
    assert_eq!(cut.round, None);
    // Backwards: back along the clockwise arc is counter-clockwise.
    let (into, out) = (
        arc([44.0, -4.0], [40.0, 0.0], [44.0, 0.0], false),
        line([40.0, 0.0], [0.0, 0.0]),
    );
    let Ok(back) = corner_cut(into, out, Corner::Chamfer(4.8)) else {
        panic!("no cut")
    };
    assert!(near(back.start, [42.88, -3.84]), "{back:?}");
    assert!(near(back.end, [35.2, 0.0]), "{back:?}");
    // The chord 4·√2 is the whole quarter circle: nothing left of it.
    let all = corner_cut(into, out, Corner::Chamfer(4.0 * 2f64.sqrt()));
    assert!(matches!(all, Err(CutError::TooShort { .. })), "{all:?}");
}

#[test]
fn corners_that_cannot_be_cut() {
    let cut = |a, b, c| corner_cut(a, b, c);
    let in_line = cut(
        line([0.0, 0.0], [10.0, 0.0]),
        line([10.0, 0.0], [20.0, 0.0]),
        C::Round(1.0),
    );
    assert_eq!(in_line, Err(CutError::InLine));
    let back = cut(
        line([0.0, 0.0], [10.0, 0.0]),
        line([10.0, 0.0], [5.0, 0.0]),
        C::Chamfer(1.0),
    );
    assert_eq!(back, Err(CutError::InLine));
    // A square corner's round takes r of each move.
    let short = cut(
        line([0.0, 0.0], [10.0, 0.0]),
        line([10.0, 0.0], [10.0, 3.0]),
        C::Round(4.0),
    );
    let expected = CutError::TooShort {
        need: 4.0,
        room: 3.0,
    };
    assert_eq!(short, Err(expected));
    let exact = cut(
        line([0.0, 0.0], [10.0, 0.0]),
        line([10.0, 0.0], [10.0, 4.0]),
        C::Chamfer(4.0),
    );
    assert!(exact.is_ok(), "{exact:?}");
    // A line into the circle about (10, 5) at its lowest point goes on
    // tangent.
    let tangent = cut(
        line([0.0, 0.0], [10.0, 0.0]),
        arc([10.0, 0.0], [15.0, 5.0], [10.0, 5.0], true),
        C::Round(1.0),
    );
    assert_eq!(tangent, Err(CutError::Tangent));
    // A chord longer than the arc's diameter; a chord beyond its end.
    let into = arc([40.0, 0.0], [44.0, -4.0], [44.0, 0.0], true);
    let wide = cut(line([0.0, 0.0], [40.0, 0.0]), into, C::Chamfer(8.5));
    assert_eq!(wide, Err(CutError::NoCut));
    let beyond = cut(line([0.0, 0.0], [40.0, 0.0]), into, C::Chamfer(6.0));
    assert!(
        matches!(beyond, Err(CutError::TooShort { need, room }) if need > room),
        "{beyond:?}"
    );
    // The round would take all of the quarter circle: nothing left of it.
    let all = cut(line([0.0, 0.0], [40.0, 0.0]), into, C::Round(400.0));
    assert!(matches!(all, Err(CutError::TooShort { .. })), "{all:?}");
}

/// A random move ending (`last`) or starting at `at`: a line, or an arc
/// of a random circle through `at` turning up to nearly a full turn.
fn random_element(value: &mut impl FnMut(f64) -> f64, at: P2, scale: f64, last: bool) -> Element {
    let other = [at[0] + value(scale), at[1] + value(scale)];
    if value(1.0) < 0.0 {
        return match last {
            true => line(other, at),
            false => line(at, other),
        };
    }
    let ccw = value(1.0) < 0.0;
    let centre = other;
    let turn = (value(1.0).abs() * 0.98 + 0.01) * std::f64::consts::TAU;
    let turn = if ccw == last { -turn } else { turn };
    let (s, c) = turn.sin_cos();
    let v = [at[0] - centre[0], at[1] - centre[1]];
    let far = [
        centre[0] + v[0] * c - v[1] * s,
        centre[1] + v[0] * s + v[1] * c,
    ];
    match last {
        true => arc(far, at, centre, ccw),
        false => arc(at, far, centre, ccw),
    }
}

/// Where `e` goes at `p` (unit), whether `p` is on it (within `tol`),
/// and how far along it from its start.
fn on(e: Element, p: P2, tol: f64) -> (P2, bool) {
    let len = |v: P2| v[0].hypot(v[1]);
    match e {
        Element::Line { from, to } => {
            let d = [
                (to[0] - from[0]) / len([to[0] - from[0], to[1] - from[1]]),
                (to[1] - from[1]) / len([to[0] - from[0], to[1] - from[1]]),
            ];
            let w = [p[0] - from[0], p[1] - from[1]];
            let t = w[0] * d[0] + w[1] * d[1];
            let off = (w[0] * d[1] - w[1] * d[0]).abs();
            let inside = t >= -tol && t <= len([to[0] - from[0], to[1] - from[1]]) + tol;
            (d, off < tol && inside)
        }
        Element::Arc {
            from,
            to,
            centre,
            ccw,
        } => {
            let r = len([to[0] - centre[0], to[1] - centre[1]]);
            let v = [p[0] - centre[0], p[1] - centre[1]];
            let n = [v[0] / len(v), v[1] / len(v)];
            let d = if ccw { [-n[1], n[0]] } else { [n[1], -n[0]] };
            let angle = |q: P2| (q[1] - centre[1]).atan2(q[0] - centre[0]);
            let turned = |a: f64, b: f64| {
                let t = if ccw { b - a } else { a - b };
                t.rem_euclid(std::f64::consts::TAU)
            };
            let (a0, a1, ap) = (angle(from), angle(to), angle(p));
            let sweep = turned(a0, a1);
            let inside = turned(a0, ap) <= sweep + tol / r || turned(ap, a0) < tol / r;
            ((d), (len(v) - r).abs() < tol && inside)
        }
    }
}

/// Random corners of lines and arcs: the round starts on the first move
/// and ends on the second, r from its centre, tangent to each and turning
/// with them there; the chamfer's ends are on the moves, c in a straight
/// line from the corner. Within 1e-9 of the moves' size.
#[test]
fn rounds_are_tangent_and_chamfer_legs_equal() {
    let mut random = crate::test_random::Random::new(0x9e37_79b9_7f4a_7c15);
    let mut value = |scale: f64| (random.below(2_000_001) as f64 / 1e6 - 1.0) * scale;
    let (mut rounds, mut chamfers, mut curved) = (0, 0, 0);
    for i in 0..40_000 {
        let scale = [1.0, 100.0, 2000.0][i % 3];
        let at = [value(scale), value(scale)];
        let a = random_element(&mut value, at, scale, true);
        let b = random_element(&mut value, at, scale, false);
        let size = value(scale).abs() * 0.3 + 1e-3;
        let corner = if i % 2 == 0 {
            Corner::Round(size)
        } else {
            Corner::Chamfer(size)
        };
        let Ok(cut) = corner_cut(a, b, corner) else {
            continue;
        };
        let tol = 1e-9 * scale;
        let (da, on_a) = on(a, cut.start, tol);
        let (db, on_b) = on(b, cut.end, tol);
        assert!(on_a && on_b, "{a:?} {b:?} {corner:?}: {cut:?}");
        let len = |v: P2| v[0].hypot(v[1]);
        let sub = |p: P2, q: P2| [p[0] - q[0], p[1] - q[1]];
        match (corner, &cut.round) {
            (Corner::Round(r), Some(round)) => {
                let centre = [
                    cut.start[0] + round.centre[0],
                    cut.start[1] + round.centre[1],
                ];
                let (v1, v2) = (sub(cut.start, centre), sub(cut.end, centre));
                assert!(
                    (len(v1) - r).abs() < tol && (len(v2) - r).abs() < tol,
                    "{cut:?}"
                );
                // Tangent: the radius square to the move; and turning the
                // way the move goes.
                let dot = |p: P2, q: P2| p[0] * q[0] + p[1] * q[1];
                let cross = |p: P2, q: P2| p[0] * q[1] - p[1] * q[0];
                for (v, d) in [(v1, da), (v2, db)] {
                    assert!(dot(v, d).abs() < tol, "{a:?} {b:?} {cut:?}");
                    assert_eq!(cross(v, d) > 0.0, round.counter_clockwise, "{cut:?}");
                }
                rounds += 1;
            }
            (Corner::Chamfer(c), None) => {
                assert!((len(sub(cut.start, at)) - c).abs() < tol, "{cut:?}");
                assert!((len(sub(cut.end, at)) - c).abs() < tol, "{cut:?}");
                chamfers += 1;
            }
            _ => panic!("{corner:?} cut as {cut:?}"),
        }
        if !matches!((a, b), (Element::Line { .. }, Element::Line { .. })) {
            curved += 1;
        }
    }
    assert!(
        rounds > 4000 && chamfers > 4000 && curved > 4000,
        "{rounds} rounds, {chamfers} chamfers, {curved} with an arc"
    );
}
