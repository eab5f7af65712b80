//! The path TOPP-RA times ([`BlendedPath`]): straight between waypoints, turning through each
//! interior waypoint on a circular arc tangent to both segments (Kunz and Stilman, RSS 2012,
//! §III), parameterized by arc length; split where it reverses.

use super::{EPS, last_at_most};
use crate::error::{Error, Result};

/// A turn sharper than this (rad, from straight on) is a reversal: the path is split there.
const REVERSAL: f64 = std::f64::consts::PI - 1e-6;

/// One piece of a [`BlendedPath`].
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Piece {
    /// `start + s · dir`, `s ∈ [0, length]`, `dir` a unit vector.
    Line {
        start: Vec<f64>,
        dir: Vec<f64>,
        length: f64,
    },
    /// `center + r (cos(s/r) x + sin(s/r) y)`, `s ∈ [0, r · angle]`, `x ⟂ y` unit vectors.
    Arc {
        center: Vec<f64>,
        x: Vec<f64>,
        y: Vec<f64>,
        radius: f64,
        angle: f64,
    },
}

impl Piece {
    pub(super) fn length(&self) -> f64 {
        match self {
            Piece::Line { length, .. } => *length,
            Piece::Arc { radius, angle, .. } => radius * angle,
        }
    }

    /// First and second derivatives at arc length `s` of the piece (as [`Piece::eval`]), an
    /// arc's sine and cosine from `angles` (this piece is number `k`).
    pub(super) fn derivatives(
        &self,
        k: usize,
        s: f64,
        angles: &mut ArcAngle,
        dq: &mut [f64],
        ddq: &mut [f64],
    ) {
        match self {
            Piece::Line { dir, .. } => {
                dq.copy_from_slice(dir);
                ddq.fill(0.0);
            }
            Piece::Arc { x, y, radius, .. } => {
                let (sin, cos) = angles.sin_cos(k, s / radius);
                for j in 0..dq.len() {
                    dq[j] = -sin * x[j] + cos * y[j];
                    ddq[j] = -(cos * x[j] + sin * y[j]) / radius;
                }
            }
        }
    }

    /// Position, first and second derivatives at arc length `s` of the piece.
    pub(super) fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        match self {
            Piece::Line { start, dir, .. } => {
                for j in 0..q.len() {
                    q[j] = start[j] + s * dir[j];
                    dq[j] = dir[j];
                    ddq[j] = 0.0;
                }
            }
            Piece::Arc {
                center,
                x,
                y,
                radius,
                ..
            } => {
                let (sin, cos) = (s / radius).sin_cos();
                for j in 0..q.len() {
                    q[j] = center[j] + radius * (cos * x[j] + sin * y[j]);
                    dq[j] = -sin * x[j] + cos * y[j];
                    ddq[j] = -(cos * x[j] + sin * y[j]) / radius;
                }
            }
        }
    }
}

/// A joint-space path through waypoints, straight between them, each interior corner replaced
/// by a circular arc, parameterized by arc length (Kunz and Stilman, §III).
#[derive(Clone, Debug, PartialEq)]
pub struct BlendedPath {
    dof: usize,
    pub(super) pieces: Vec<Piece>,
    /// Arc length at the start of each piece.
    pub(super) starts: Vec<f64>,
    /// For each piece, the index (in the waypoints given to [`BlendedPath::split_with`]) of
    /// the waypoint a line starts from, or of the corner an arc turns through.
    sources: Vec<usize>,
    /// Indices of the path's first and last waypoints in the waypoints given.
    ends: (usize, usize),
    length: f64,
}

/// Where an arc length lies on a [`BlendedPath`], by the waypoints it was made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// On the straight piece that runs from waypoint `from` towards waypoint `from + 1` (the
    /// next waypoint that is not a repeat of it).
    Line {
        /// The waypoint the piece starts from.
        from: usize,
    },
    /// On the blend arc of the corner at waypoint `corner`; `past_middle` on its second half.
    Arc {
        /// The waypoint whose corner the arc cuts.
        corner: usize,
        /// Whether the arc length is past the arc's middle.
        past_middle: bool,
    },
}

impl BlendedPath {
    /// The waypoints split where the path turns back on itself (a turn of nearly 180°, where
    /// the robot must stop), repeated waypoints dropped; each part, with at least two
    /// waypoints, becomes a path. An empty list when the waypoints are all one point.
    ///
    /// # Errors
    /// [`Error::JointCount`] for waypoints of different lengths, [`Error::InvalidOption`] for
    /// non-finite values or a tolerance that is not positive and finite.
    pub fn split(waypoints: &[Vec<f64>], tolerance: f64) -> Result<Vec<BlendedPath>> {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(Error::InvalidOption {
                name: "tolerance",
                value: tolerance,
                expected: "a positive, finite distance",
            });
        }
        Self::split_with(waypoints, &vec![tolerance; waypoints.len()])
    }

    /// As [`BlendedPath::split`], with a tolerance per waypoint: `tolerances[i]` bounds the
    /// blend of the corner at waypoint `i` (the ends' are not used), and a corner whose
    /// tolerance is 0 is not blended: the path is split there too, and the robot stops. Of
    /// repeated waypoints the first one's tolerance counts.
    ///
    /// # Errors
    /// [`Error::JointCount`] for waypoints of different lengths or a tolerance list of
    /// another length, [`Error::InvalidOption`] for non-finite values or a negative
    /// tolerance.
    pub fn split_with(waypoints: &[Vec<f64>], tolerances: &[f64]) -> Result<Vec<BlendedPath>> {
        if tolerances.len() != waypoints.len() {
            return Err(Error::JointCount {
                what: "the tolerances",
                expected: waypoints.len(),
                found: tolerances.len(),
            });
        }
        if let Some(t) = tolerances.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
            return Err(Error::InvalidOption {
                name: "tolerance",
                value: *t,
                expected: "a finite distance, 0 or more",
            });
        }
        let Some(dof) = waypoints.first().map(Vec::len) else {
            return Ok(Vec::new());
        };
        if let Some(w) = waypoints.iter().find(|w| w.len() != dof) {
            return Err(Error::JointCount {
                what: "a waypoint",
                expected: dof,
                found: w.len(),
            });
        }
        if let Some(v) = waypoints.iter().flatten().find(|v| !v.is_finite()) {
            return Err(Error::InvalidOption {
                name: "waypoints",
                value: *v,
                expected: "finite joint values",
            });
        }
        // The waypoints kept (index, point): repeats dropped.
        let mut points: Vec<(usize, &Vec<f64>)> = Vec::with_capacity(waypoints.len());
        for (i, w) in waypoints.iter().enumerate() {
            if points.last().is_none_or(|(_, p)| distance(p, w) > EPS) {
                points.push((i, w));
            }
        }
        let mut parts: Vec<Vec<(usize, &Vec<f64>)>> = vec![Vec::new()];
        for (i, &p) in points.iter().enumerate() {
            if let Some(part) = parts.last_mut() {
                part.push(p);
            }
            if i > 0
                && i + 1 < points.len()
                && (tolerances[p.0] <= 0.0
                    || turn(points[i - 1].1, p.1, points[i + 1].1) > REVERSAL)
            {
                parts.push(vec![p]);
            }
        }
        Ok(parts
            .into_iter()
            .filter(|part| part.len() >= 2)
            .map(|part| Self::blend(&part, tolerances, dof))
            .collect())
    }

    /// The path through `points` (no reversal, no repeated point), corners blended.
    fn blend(indexed: &[(usize, &Vec<f64>)], tolerances: &[f64], dof: usize) -> Self {
        let points: Vec<&Vec<f64>> = indexed.iter().map(|&(_, p)| p).collect();
        let n = points.len();
        // The distance cut from each side of every corner (0 at the two ends).
        let mut cut = vec![0.0; n];
        let seg_len: Vec<f64> = (0..n - 1)
            .map(|i| distance(points[i], points[i + 1]))
            .collect();
        let mut arcs: Vec<Option<Piece>> = vec![None; n];
        for i in 1..n.saturating_sub(1) {
            let alpha = turn(points[i - 1], points[i], points[i + 1]);
            if alpha <= 1e-9 {
                continue;
            }
            let y1 = unit(points[i - 1], points[i], seg_len[i - 1]);
            let y2 = unit(points[i], points[i + 1], seg_len[i]);
            let half = alpha / 2.0;
            // Kunz and Stilman eq. (3): the arc's distance from the corner is at most the
            // tolerance, and it uses at most half of each adjacent segment.
            let l = (seg_len[i - 1] / 2.0)
                .min(seg_len[i] / 2.0)
                .min(tolerances[indexed[i].0] * half.sin() / (1.0 - half.cos()));
            let radius = l / half.tan();
            let bisector: Vec<f64> = (0..dof).map(|j| y2[j] - y1[j]).collect();
            let bn = norm(&bisector);
            if radius <= EPS || bn <= EPS {
                continue;
            }
            let center: Vec<f64> = (0..dof)
                .map(|j| points[i][j] + bisector[j] / bn * radius / half.cos())
                .collect();
            let entry: Vec<f64> = (0..dof).map(|j| points[i][j] - l * y1[j]).collect();
            let to_entry: Vec<f64> = (0..dof).map(|j| entry[j] - center[j]).collect();
            let tn = norm(&to_entry);
            if tn <= EPS {
                continue;
            }
            cut[i] = l;
            arcs[i] = Some(Piece::Arc {
                center,
                x: to_entry.iter().map(|v| v / tn).collect(),
                y: y1,
                radius,
                angle: alpha,
            });
        }
        let mut pieces = Vec::with_capacity(2 * n);
        let mut sources = Vec::with_capacity(2 * n);
        for i in 0..n - 1 {
            let dir = unit(points[i], points[i + 1], seg_len[i]);
            let length = (seg_len[i] - cut[i] - cut[i + 1]).max(0.0);
            if length > EPS {
                pieces.push(Piece::Line {
                    start: (0..dof).map(|j| points[i][j] + cut[i] * dir[j]).collect(),
                    dir,
                    length,
                });
                sources.push(indexed[i].0);
            }
            if let Some(arc) = arcs[i + 1].take() {
                pieces.push(arc);
                sources.push(indexed[i + 1].0);
            }
        }
        let mut starts = Vec::with_capacity(pieces.len());
        let mut length = 0.0;
        for p in &pieces {
            starts.push(length);
            length += p.length();
        }
        Self {
            dof,
            pieces,
            starts,
            sources,
            ends: (indexed[0].0, indexed[n - 1].0),
            length,
        }
    }

    /// Joints of the path.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Arc length of the path (in joint space).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The index of the straight piece that contains arc length `s` (its ends included),
    /// `None` on a blend arc. Two points on the same straight piece are joined by the
    /// straight segment between the path's waypoints; anything else left the waypoints'
    /// polyline and is checked again by the caller (the blends cut corners).
    pub fn line_at(&self, s: f64) -> Option<usize> {
        let s = s.clamp(0.0, self.length);
        let k = self.starts.partition_point(|&t| t <= s).saturating_sub(1);
        // A point at a junction belongs to both pieces: prefer the straight one.
        let candidates = [Some(k), k.checked_sub(1), Some(k + 1)];
        candidates
            .into_iter()
            .flatten()
            .find(|&i| match self.pieces.get(i) {
                Some(Piece::Line { length, .. }) => {
                    let (a, b) = (self.starts[i], self.starts[i] + length);
                    s >= a - 1e-9 && s <= b + 1e-9
                }
                _ => false,
            })
    }

    /// Where arc length `s` (clamped into the path) lies, by the waypoints the path was made
    /// from; at the junction of two pieces, on the first.
    pub fn locate(&self, s: f64) -> Location {
        let s = s.clamp(0.0, self.length);
        let k = self
            .starts
            .partition_point(|&t| t < s)
            .saturating_sub(1)
            .min(self.pieces.len().saturating_sub(1));
        match (self.pieces.get(k), self.sources.get(k)) {
            (Some(Piece::Arc { radius, angle, .. }), Some(&corner)) => Location::Arc {
                corner,
                past_middle: s - self.starts[k] > 0.5 * radius * angle,
            },
            (_, source) => Location::Line {
                from: source.copied().unwrap_or(self.ends.0),
            },
        }
    }

    /// The arc length of the middle of the blend of the corner at waypoint `corner` (an
    /// index in the waypoints given), if this path blends that corner.
    pub fn corner_middle(&self, corner: usize) -> Option<f64> {
        self.pieces
            .iter()
            .zip(&self.sources)
            .zip(&self.starts)
            .find_map(|((p, &c), &start)| match p {
                Piece::Arc { radius, angle, .. } if c == corner => {
                    Some(start + 0.5 * radius * angle)
                }
                _ => None,
            })
    }

    /// The corners (waypoint indices) whose blend arcs overlap the arc lengths from `s0` to
    /// `s1`: what a straight line between the path's points at `s0` and `s1` cuts across.
    pub fn corners_between(&self, s0: f64, s1: f64) -> Vec<usize> {
        let (a, b) = (s0.min(s1), s0.max(s1));
        self.pieces
            .iter()
            .zip(&self.sources)
            .zip(&self.starts)
            .filter_map(|((p, &c), &start)| match p {
                Piece::Arc { .. } if start < b && start + p.length() > a => Some(c),
                _ => None,
            })
            .collect()
    }

    /// Indices of the path's first and last waypoints in the waypoints it was made from.
    pub fn ends(&self) -> (usize, usize) {
        self.ends
    }

    /// Position, tangent and curvature vector at arc length `s` (clamped into the path).
    pub fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        let s = s.clamp(0.0, self.length);
        let k = self.starts.partition_point(|&t| t <= s).saturating_sub(1);
        if let Some(piece) = self.pieces.get(k) {
            piece.eval(s - self.starts[k], q, dq, ddq);
        }
    }

    /// The piece [`BlendedPath::eval`] evaluates at `s`, searched forward from piece `hint`.
    pub(super) fn piece_at(&self, s: f64, hint: usize) -> usize {
        last_at_most(&self.starts, s.clamp(0.0, self.length), hint)
    }

    /// [`BlendedPath::eval`], the piece searched forward from piece `hint`; returns the piece.
    pub(super) fn eval_from(
        &self,
        hint: usize,
        s: f64,
        q: &mut [f64],
        dq: &mut [f64],
        ddq: &mut [f64],
    ) -> usize {
        let s = s.clamp(0.0, self.length);
        let k = last_at_most(&self.starts, s, hint);
        if let Some(piece) = self.pieces.get(k) {
            piece.eval(s - self.starts[k], q, dq, ddq);
        }
        k
    }

    /// The derivatives of piece `k` at arc length `s` of the path (clamped into the path,
    /// not into the piece), an arc's sine and cosine from `angles`.
    pub(super) fn derivatives_on(
        &self,
        k: usize,
        s: f64,
        angles: &mut ArcAngle,
        dq: &mut [f64],
        ddq: &mut [f64],
    ) {
        let s = s.clamp(0.0, self.length);
        if let (Some(piece), Some(start)) = (self.pieces.get(k), self.starts.get(k)) {
            piece.derivatives(k, s - start, angles, dq, ddq);
        }
    }
}

/// Largest difference (rad) between an angle and the previous one turned by the last step for
/// [`ArcAngle`] to turn the previous sine and cosine instead of calling `sin_cos`.
const ROTATION_MATCH: f64 = 1e-12;

/// The sine and cosine of angles along one arc in increasing order (its grid points): the
/// first step from the arc's start (angle 0, sine 0, cosine 1) costs a `sin_cos` and gives
/// the step's sine and cosine; on the arc's uniform grid the next angles are the previous
/// turned by that step, one rotation each (its rounding, about one unit in the last place a
/// step, is far below the grid's own). Any other angle gets its `sin_cos`.
#[derive(Clone, Copy, Debug)]
pub(super) struct ArcAngle {
    piece: usize,
    angle: f64,
    sin: f64,
    cos: f64,
    /// The last step, its sine and cosine.
    step: Option<(f64, f64, f64)>,
}

impl ArcAngle {
    pub(super) fn new() -> Self {
        Self {
            piece: usize::MAX,
            angle: 0.0,
            sin: 0.0,
            cos: 1.0,
            step: None,
        }
    }

    /// `angle.sin_cos()` on arc `piece`.
    pub(super) fn sin_cos(&mut self, piece: usize, angle: f64) -> (f64, f64) {
        if piece != self.piece {
            *self = Self {
                piece,
                ..Self::new()
            };
        }
        if angle == self.angle {
            return (self.sin, self.cos);
        }
        if let Some((delta, ds, dc)) = self.step {
            let next = self.angle + delta;
            if (angle - next).abs() <= ROTATION_MATCH {
                let (sin, cos) = (self.sin * dc + self.cos * ds, self.cos * dc - self.sin * ds);
                (self.angle, self.sin, self.cos) = (next, sin, cos);
                return (sin, cos);
            }
        }
        let (sin, cos) = angle.sin_cos();
        // From the arc's start the step is the angle itself.
        self.step = (self.angle == 0.0).then_some((angle, sin, cos));
        (self.angle, self.sin, self.cos) = (angle, sin, cos);
        (sin, cos)
    }
}

pub(super) fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

pub(super) fn norm(a: &[f64]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The unit vector from `a` to `b`, `len` apart.
fn unit(a: &[f64], b: &[f64], len: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| (y - x) / len).collect()
}

/// The angle the path turns at `b` (0 straight on, π a reversal).
fn turn(a: &[f64], b: &[f64], c: &[f64]) -> f64 {
    let l1 = distance(a, b);
    let l2 = distance(b, c);
    if l1 <= EPS || l2 <= EPS {
        return 0.0;
    }
    let dot: f64 = (0..a.len())
        .map(|j| (b[j] - a[j]) * (c[j] - b[j]))
        .sum::<f64>()
        / (l1 * l2);
    dot.clamp(-1.0, 1.0).acos()
}
