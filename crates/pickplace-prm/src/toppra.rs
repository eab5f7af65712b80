//! Time-optimal path parameterization by reachability analysis (TOPP-RA: H. Pham and Q.-C.
//! Pham, "A New Approach to Time-Optimal Path Parameterization Based on Reachability
//! Analysis", IEEE T-RO 34(3), 2018), on paths whose corners are blended with circular arcs
//! (T. Kunz and M. Stilman, "Time-Optimal Trajectory Generation for Path Following with
//! Bounded Acceleration and Velocity", RSS 2012, §III).
//!
//! A [`BlendedPath`] runs straight between waypoints and turns through each interior waypoint
//! on a circular arc tangent to both segments, no farther than a tolerance from the waypoint;
//! it is parameterized by arc length, so its tangent is continuous and its curvature bounded.
//! Where the path turns back on itself (a reversal) no arc fits: the path is split there and
//! the robot stops ([`BlendedPath::split`]).
//!
//! [`parameterize`] then finds the fastest motion along the path under per-joint velocity and
//! acceleration limits. With `x = ṡ²` and `u = s̈` on a grid `s₀ < … < s_N`, joint velocities
//! are `q'(s) ṡ` and accelerations `q'(s) u + q''(s) x`: linear in `(u, x)`, and
//! `x_{i+1} = x_i + 2 Δᵢ uᵢ`. The backward pass computes each grid point's controllable set
//! (the `x` from which the path's end can still be reached at rest, an interval); the forward
//! pass starts at rest and takes the largest admissible `u` that stays controllable. Each
//! stage's sets are exact: the constraints on `u` are lines in `x`, and `x` is admissible where
//! every lower line lies under every upper line, an intersection of half-lines.

use crate::error::{Error, Result};
use crate::timing::{MAX_TRAJECTORY_SAMPLES, Trajectory, TrajectoryPoint};

/// Below this, a turn is straight (no arc) and a length is zero.
const EPS: f64 = 1e-12;

/// Fewest stages of a path's grid.
const MIN_STAGES: f64 = 32.0;

/// Largest turn of the tangent within one stage on an arc (rad). The limits hold at the grid
/// points; between them a joint's velocity follows the turning tangent: with 0.2 rad, a slow
/// jaw opening while the arm starts moving overshot its limit by up to 6 % (issue 32's
/// one-jaw arm), with 0.05 rad by none the validator sees.
const ARC_STAGE_ANGLE: f64 = 0.05;

/// A turn sharper than this (rad, from straight on) is a reversal: the path is split there.
const REVERSAL: f64 = std::f64::consts::PI - 1e-6;

/// One piece of a [`BlendedPath`].
#[derive(Clone, Debug, PartialEq)]
enum Piece {
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
    fn length(&self) -> f64 {
        match self {
            Piece::Line { length, .. } => *length,
            Piece::Arc { radius, angle, .. } => radius * angle,
        }
    }

    /// First and second derivatives at arc length `s` of the piece (as [`Piece::eval`]), an
    /// arc's sine and cosine from `angles` (this piece is number `k`).
    fn derivatives(
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
    fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
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
    pieces: Vec<Piece>,
    /// Arc length at the start of each piece.
    starts: Vec<f64>,
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
    fn piece_at(&self, s: f64, hint: usize) -> usize {
        last_at_most(&self.starts, s.clamp(0.0, self.length), hint)
    }

    /// [`BlendedPath::eval`], the piece searched forward from piece `hint`; returns the piece.
    fn eval_from(
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
    fn derivatives_on(
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
struct ArcAngle {
    piece: usize,
    angle: f64,
    sin: f64,
    cos: f64,
    /// The last step, its sine and cosine.
    step: Option<(f64, f64, f64)>,
}

impl ArcAngle {
    fn new() -> Self {
        Self {
            piece: usize::MAX,
            angle: 0.0,
            sin: 0.0,
            cos: 1.0,
            step: None,
        }
    }

    /// `angle.sin_cos()` on arc `piece`.
    fn sin_cos(&mut self, piece: usize, angle: f64) -> (f64, f64) {
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

/// Options of [`parameterize`].
#[derive(Clone, Debug, PartialEq)]
pub struct ToppraOptions {
    /// Per-joint velocity limits (rad/s or m/s).
    pub max_velocities: Vec<f64>,
    /// Per-joint acceleration limits (rad/s² or m/s²).
    pub max_accelerations: Vec<f64>,
    /// Largest spacing of the grid along the path (in path length; default 0.01). Every
    /// junction of pieces is a grid point too, and on an arc of radius `r` the spacing is at
    /// most `0.2 r` (the tangent turns at most 0.2 rad per stage).
    pub grid_step: f64,
    /// Sampling period of the output trajectory, s (default 0.01).
    pub sample_period: f64,
}

impl Default for ToppraOptions {
    fn default() -> Self {
        Self {
            max_velocities: Vec::new(),
            max_accelerations: Vec::new(),
            grid_step: 0.01,
            sample_period: 0.01,
        }
    }
}

/// The time-optimal parameterization of a path: `ṡ²` at each grid point, rest to rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameterization {
    /// Grid points (arc length).
    pub grid: Vec<f64>,
    /// `x = ṡ²` at each grid point (0 at both ends).
    pub x: Vec<f64>,
    /// Time at each grid point, s.
    pub times: Vec<f64>,
}

impl Parameterization {
    /// Duration of the motion, s.
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// `(s, ṡ, s̈)` at time `t` (clamped): within a stage `s̈` is constant.
    pub fn state(&self, t: f64) -> (f64, f64, f64) {
        self.state_in(self.stage_at(t, 0), t)
    }

    /// The stage [`Parameterization::state`] uses at `t`, searched forward from `hint`.
    fn stage_at(&self, t: f64, hint: usize) -> usize {
        let n = self.grid.len().min(self.times.len());
        let t = t.clamp(0.0, self.duration());
        last_at_most(&self.times, t, hint).min(n.saturating_sub(2))
    }

    /// `(s, ṡ, s̈)` at time `t` (clamped) in stage `i` (from [`Parameterization::stage_at`]).
    fn state_in(&self, i: usize, t: f64) -> (f64, f64, f64) {
        let n = self.grid.len();
        if n < 2 {
            return (self.grid.first().copied().unwrap_or(0.0), 0.0, 0.0);
        }
        let t = t.clamp(0.0, self.duration());
        let ds = self.grid[i + 1] - self.grid[i];
        let u = if ds > 0.0 {
            (self.x[i + 1] - self.x[i]) / (2.0 * ds)
        } else {
            0.0
        };
        let v0 = self.x[i].max(0.0).sqrt();
        let tau = t - self.times[i];
        let s =
            (self.grid[i] + v0 * tau + 0.5 * u * tau * tau).clamp(self.grid[i], self.grid[i + 1]);
        (s, (v0 + u * tau).max(0.0), u)
    }
}

/// The fastest rest-to-rest motion along `path` under the options' joint velocity and
/// acceleration limits (TOPP-RA, see the module's documentation).
///
/// # Errors
/// [`Error::JointCount`] or [`Error::InvalidLimit`] for limits that are not one positive
/// finite value per joint, [`Error::InvalidOption`] for a grid step that is not positive and
/// finite, [`Error::TooManyPoints`] when the grid would exceed [`MAX_TRAJECTORY_SAMPLES`]
/// points.
pub fn parameterize(path: &BlendedPath, options: &ToppraOptions) -> Result<Parameterization> {
    let dof = path.dof();
    crate::timing::check_limits(dof, &options.max_velocities, &options.max_accelerations)?;
    if !(options.grid_step.is_finite() && options.grid_step > 0.0) {
        return Err(Error::InvalidOption {
            name: "grid_step",
            value: options.grid_step,
            expected: "a positive, finite length",
        });
    }
    // At least MIN_STAGES stages however short the path (a gripper closing by millimetres):
    // the speed lives between grid points, and one stage from rest to rest cannot move.
    let step = if path.length() > 0.0 {
        options.grid_step.min(path.length() / MIN_STAGES)
    } else {
        options.grid_step
    };
    let grid = grid(path, step)?;
    let n = grid.len();
    if n < 2 {
        return Ok(Parameterization {
            grid,
            x: vec![0.0; n],
            times: vec![0.0; n],
        });
    }
    let stages = Stages::new(path, &grid, options);
    // Backward pass: controllable sets [lo, hi] of x, the last one {0}.
    let mut lo = vec![0.0; n];
    let mut hi = vec![0.0; n];
    // Hints: the pairs that bound the last two stages, and the last one's lower line against
    // the next set (deceleration).
    let mut hints: Vec<Pair> = Vec::with_capacity(3);
    for i in (0..n - 1).rev() {
        let d = grid[i + 1] - grid[i];
        let next = (lo[i + 1], hi[i + 1]);
        let ((a, b), binding) = x_range(stages.bands(i), stages.x_max[i], d, next, &hints);
        if let Some(pair) = binding {
            let last = hints.first().copied();
            hints.clear();
            hints.push(pair);
            hints.push((pair.0, usize::MAX));
            hints.extend(last.filter(|&p| p != pair));
        }
        // Rest (x = 0, u = 0) is always admissible, so the set is never empty; rounding may
        // only make it look so.
        lo[i] = a.max(0.0).min(b.max(0.0));
        hi[i] = b.max(0.0);
    }
    // Forward pass: from rest, the largest u that keeps x controllable.
    let mut x = vec![0.0; n];
    for i in 0..n - 1 {
        let d = grid[i + 1] - grid[i];
        let (ulo, uhi) = u_range(stages.bands(i), x[i], d, lo[i + 1], hi[i + 1]);
        let u = if uhi >= ulo { uhi } else { ulo.min(uhi) };
        x[i + 1] = (x[i] + 2.0 * d * u).clamp(lo[i + 1], hi[i + 1].max(lo[i + 1]));
    }
    x[n - 1] = 0.0;
    // The controllable sets are done with: their buffer holds the times.
    let mut times = lo;
    times[0] = 0.0;
    for i in 0..n - 1 {
        let d = grid[i + 1] - grid[i];
        let speed = x[i].sqrt() + x[i + 1].sqrt();
        // A stage with no speed at both ends takes no time only when it has no length; with
        // a length, the limits allow no motion (a limit so small that its square underflows):
        // the motion would last forever, which no trajectory can sample.
        let dt = if speed > 0.0 {
            2.0 * d / speed
        } else if d > 0.0 {
            return Err(Error::TooManyPoints {
                what: "samples (the limits allow no speed along the path)",
                count: f64::INFINITY,
                limit: MAX_TRAJECTORY_SAMPLES,
            });
        } else {
            0.0
        };
        times[i + 1] = times[i] + dt;
    }
    Ok(Parameterization { grid, x, times })
}

/// The trajectory of `path` timed by `timing`, sampled every `sample_period` seconds (and at
/// the end), with positions, velocities and accelerations.
///
/// # Errors
/// [`Error::InvalidOption`] for a sample period that is not positive and finite;
/// [`Error::TooManyPoints`] over [`MAX_TRAJECTORY_SAMPLES`].
pub fn sample(
    path: &BlendedPath,
    timing: &Parameterization,
    sample_period: f64,
) -> Result<Trajectory> {
    if !(sample_period.is_finite() && sample_period > 0.0) {
        return Err(Error::InvalidOption {
            name: "sample_period",
            value: sample_period,
            expected: "a positive, finite time",
        });
    }
    let duration = timing.duration();
    let count = (duration / sample_period).ceil();
    if count.is_nan() || count >= MAX_TRAJECTORY_SAMPLES as f64 {
        return Err(Error::TooManyPoints {
            what: "samples",
            count,
            limit: MAX_TRAJECTORY_SAMPLES,
        });
    }
    let count = count as usize;
    let dof = path.dof();
    let mut points = Vec::with_capacity(count + 1);
    // Time and arc length only grow: the stage and the piece are found from the last ones.
    let (mut stage, mut piece) = (0, 0);
    for k in 0..=count {
        let t = (k as f64 * sample_period).min(duration);
        stage = timing.stage_at(t, stage);
        let (s, sd, sdd) = timing.state_in(stage, t);
        // The point's own vectors take the path's derivatives, then become its velocities
        // and accelerations: three allocations per point, no scratch.
        let mut positions = vec![0.0; dof];
        let mut velocities = vec![0.0; dof];
        let mut accelerations = vec![0.0; dof];
        piece = path.eval_from(
            piece,
            s,
            &mut positions,
            &mut velocities,
            &mut accelerations,
        );
        for (v, a) in velocities.iter_mut().zip(accelerations.iter_mut()) {
            *a = *v * sdd + *a * sd * sd;
            *v *= sd;
        }
        points.push(TrajectoryPoint {
            time_from_start: t,
            positions,
            velocities,
            accelerations,
        });
        if t >= duration {
            break;
        }
    }
    Ok(Trajectory { points })
}

/// The last index `i` of the nondecreasing `sorted` with `sorted[i] ≤ v` (0 when there is
/// none), as `sorted.partition_point(|&t| t <= v).saturating_sub(1)`, searched forward from
/// `hint` for a few steps before bisecting (walks along a path or a timing are monotone).
fn last_at_most(sorted: &[f64], v: f64, hint: usize) -> usize {
    let mut i = hint;
    if sorted.get(i).is_some_and(|&t| t <= v) {
        for _ in 0..8 {
            match sorted.get(i + 1) {
                Some(&t) if t <= v => i += 1,
                _ => return i,
            }
        }
    }
    sorted.partition_point(|&t| t <= v).saturating_sub(1)
}

/// The grid: every junction of pieces, and points between them at most `step` apart.
fn grid(path: &BlendedPath, step: f64) -> Result<Vec<f64>> {
    // On an arc the tangent turns: a stage turns it by at most ARC_STAGE_ANGLE, so that the
    // constraints met at both ends of a stage hold closely in between.
    let spacing = |p: &Piece| match p {
        Piece::Line { .. } => step,
        Piece::Arc { radius, .. } => step.min(radius * ARC_STAGE_ANGLE),
    };
    let mut count = 0.0;
    for p in &path.pieces {
        count += (p.length() / spacing(p)).ceil().max(1.0);
    }
    if count.is_nan() || count >= MAX_TRAJECTORY_SAMPLES as f64 {
        return Err(Error::TooManyPoints {
            what: "grid points",
            count,
            limit: MAX_TRAJECTORY_SAMPLES,
        });
    }
    let mut g = Vec::with_capacity(count as usize + 1);
    for (p, &s0) in path.pieces.iter().zip(&path.starts) {
        let len = p.length();
        if len <= EPS {
            continue;
        }
        let m = (len / spacing(p)).ceil().max(1.0) as usize;
        for k in 0..m {
            g.push(s0 + len * k as f64 / m as f64);
        }
    }
    g.push(path.length());
    Ok(g)
}

/// One constraint of a stage on `u` at `x`: `slope · x + lo ≤ u ≤ slope · x + hi` (a joint's
/// acceleration limits, both lines of the same slope).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Band {
    slope: f64,
    lo: f64,
    hi: f64,
}

/// Every stage's constraints, in flat arrays: stage `i`'s bands are
/// `bands[ends[i - 1]..ends[i]]` (from 0 for the first), and `x ≤ x_max[i]`.
struct Stages {
    bands: Vec<Band>,
    ends: Vec<usize>,
    /// Largest `x` the velocity limits and the acceleration constraints with no `u` allow.
    x_max: Vec<f64>,
}

impl Stages {
    /// The constraints of every stage of `grid` on `path`. Each stage lies within one piece
    /// (the piece of its first grid point): its start's derivatives are the piece's at `s_i`,
    /// its end's the same piece's at `s_{i+1}` (at a junction the next piece's curvature is
    /// another). Inside a piece a grid point's derivatives serve as the end of one stage and
    /// the start of the next.
    fn new(path: &BlendedPath, grid: &[f64], o: &ToppraOptions) -> Self {
        let dof = path.dof();
        let stages = grid.len().saturating_sub(1);
        let mut out = Self {
            bands: Vec::with_capacity(stages * 2 * dof),
            ends: Vec::with_capacity(stages),
            x_max: Vec::with_capacity(stages),
        };
        let (mut dq0, mut ddq0) = (vec![0.0; dof], vec![0.0; dof]);
        let (mut dq1, mut ddq1) = (vec![0.0; dof], vec![0.0; dof]);
        let Some(&first) = grid.first() else {
            return out;
        };
        let mut inv = vec![0.0; 2 * dof];
        let mut angles = ArcAngle::new();
        let mut piece = path.piece_at(first, 0);
        path.derivatives_on(piece, first, &mut angles, &mut dq0, &mut ddq0);
        for i in 0..stages {
            let d = grid[i + 1] - grid[i];
            path.derivatives_on(piece, grid[i + 1], &mut angles, &mut dq1, &mut ddq1);
            let start = (&dq0[..], &ddq0[..]);
            let x_max = push_bands(&mut out.bands, start, (&dq1, &ddq1), d, o, &mut inv);
            out.x_max.push(x_max);
            out.ends.push(out.bands.len());
            if i + 2 < grid.len() {
                let next = path.piece_at(grid[i + 1], piece);
                if next == piece {
                    std::mem::swap(&mut dq0, &mut dq1);
                    std::mem::swap(&mut ddq0, &mut ddq1);
                } else {
                    piece = next;
                    path.derivatives_on(piece, grid[i + 1], &mut angles, &mut dq0, &mut ddq0);
                }
            }
        }
        out
    }

    fn bands(&self, i: usize) -> &[Band] {
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        &self.bands[start..self.ends[i]]
    }
}

/// Appends the bands of the stage of length `d` whose path derivatives are `start` and `end`
/// (`(q', q'')` at each end) and returns its `x_max`: the joint accelerations at both ends (at
/// the end, `x_{i+1} = x + 2 d u`: TOPP-RA's first-order interpolation, so that the limits
/// hold at every grid point, not only where each stage begins), and the joint velocities at
/// the start (the end's are the next stage's). `inv` is scratch of two values per joint.
fn push_bands(
    bands: &mut Vec<Band>,
    start: (&[f64], &[f64]),
    end: (&[f64], &[f64]),
    d: f64,
    o: &ToppraOptions,
    inv: &mut [f64],
) -> f64 {
    // The stage's divisions first: independent of one another, they overlap.
    for (((r, &a0), &a1), &b1) in inv.chunks_exact_mut(2).zip(start.0).zip(end.0).zip(end.1) {
        r[0] = 1.0 / a0;
        r[1] = 1.0 / (a1 + 2.0 * d * b1);
    }
    let mut x_max = f64::INFINITY;
    let joints = start
        .0
        .iter()
        .zip(start.1)
        .zip(end.0.iter().zip(end.1))
        .zip(o.max_velocities.iter().zip(&o.max_accelerations))
        .zip(inv.chunks_exact(2));
    for ((((&a0, &b0), (&a1, &b1)), (&v, &acc)), r) in joints {
        if a0.abs() > EPS {
            let w = v * r[0];
            x_max = x_max.min(w * w);
        }
        // -acc ≤ a u + b x ≤ acc, at the start and (with x_{i+1} = x + 2 d u) at the end.
        for (a, b, inv) in [(a0, b0, r[0]), (a1 + 2.0 * d * b1, b1, r[1])] {
            if a.abs() > EPS {
                // u between (∓acc - b x) / a.
                let h = acc * inv;
                let slope = -b * inv;
                bands.push(if a > 0.0 {
                    Band {
                        slope,
                        lo: -h,
                        hi: h,
                    }
                } else {
                    Band {
                        slope,
                        lo: h,
                        hi: -h,
                    }
                });
            } else if b.abs() > EPS {
                x_max = x_max.min(acc / b.abs());
            }
        }
    }
    x_max
}

/// A lower and an upper line of a stage, each the index of its band (the stage's bands, then
/// the next stage's set as the last).
type Pair = (usize, usize);

/// The highest lower line and the lowest upper line at `x` of `bands` and `next` (index
/// `bands.len()`), and `F(x)`, the first's value less the second's.
fn envelope(bands: &[Band], next: &Band, x: f64) -> (Pair, f64) {
    let sx = next.slope * x;
    let (mut lv, mut hv) = (sx + next.lo, sx + next.hi);
    let (mut li, mut hi) = (bands.len(), bands.len());
    for (k, b) in bands.iter().enumerate() {
        let sx = b.slope * x;
        let l = sx + b.lo;
        if l > lv {
            (lv, li) = (l, k);
        }
        let h = sx + b.hi;
        if h < hv {
            (hv, hi) = (h, k);
        }
    }
    ((li, hi), lv - hv)
}

/// Where the lower line of `pair` meets its upper line, `r / c` of `c x ≤ r`: an upper bound of
/// the admissible `x` when `c > 0`, a lower bound when `c < 0`.
fn pair_root(bands: &[Band], next: &Band, (l, h): Pair) -> (f64, f64) {
    let lower = bands.get(l).unwrap_or(next);
    let upper = bands.get(h).unwrap_or(next);
    let c = lower.slope - upper.slope;
    (c, (upper.hi - lower.lo) / c)
}

/// The controllable `x` of a stage of length `d` with `bands` (each with `lo ≤ 0 ≤ hi`, as
/// [`push_bands`] makes them) and `x ≤ x_max`, given the next stage's `[lo, hi]`:
/// `x ∈ [0, x_max]` with some admissible `u` such that `x + 2 d u ∈ [lo, hi]`, as `(a, b)`
/// (empty when `a > b`), and the pair of lines that binds at `b` if any.
///
/// `x` is admissible where `F(x) = max(lower lines) - min(upper lines) ≤ 0`; `F` is convex
/// and piecewise linear, so the set is an interval, and Newton's method finds each end
/// exactly: at an `x` with `F(x) > 0` the active pair of lines is a supporting line of `F`,
/// its root lies between `x` and the end, and the next step starts from that root; every
/// step leaves a piece of `F` for good, so that there are at most as many steps as pieces,
/// each of `O(L)` for `L` lines (the pairwise intersection of all half-lines is `O(L²)`). The
/// end is the root of the pair of lines that binds there, as in the pairwise computation.
/// The root of any pair whose lines cross with `c > 0` bounds the set from above: `hints`,
/// such as the pairs that bound the neighbouring stages, often bind here too, and Newton's
/// method starts from their least root (one evaluation of `F` when that pair binds). A hint's
/// index past the bands is the next stage's set.
fn x_range(
    bands: &[Band],
    x_max: f64,
    d: f64,
    (lo, hi): (f64, f64),
    hints: &[Pair],
) -> ((f64, f64), Option<Pair>) {
    if !x_max.is_finite() {
        // No line bounds x from the start (no joint moves): never with a unit tangent.
        return (x_range_pairwise(bands, x_max, d, lo, hi), None);
    }
    // (lo - x) / 2d ≤ u ≤ (hi - x) / 2d joins the stage's own lines.
    let next = Band {
        slope: -1.0 / (2.0 * d),
        lo: lo / (2.0 * d),
        hi: hi / (2.0 * d),
    };
    // F has at most 2 (L + 1) pieces; more steps only come from rounding.
    let steps = 2 * bands.len() + 4;
    // The right end: from x_max, or the least root of the hints, leftwards.
    let mut b = x_max;
    let mut binding = None;
    for &pair in hints {
        let (c, root) = pair_root(bands, &next, pair);
        if c > 0.0 && root < b {
            (b, binding) = (root, Some(pair));
        }
    }
    let mut done = false;
    for _ in 0..steps {
        if b < 0.0 {
            // Below rest: the caller clips at 0.
            done = true;
            break;
        }
        let (pair, f) = envelope(bands, &next, b);
        if f <= 0.0 {
            done = true;
            break;
        }
        let (c, root) = pair_root(bands, &next, pair);
        if c.is_nan() || c <= 0.0 {
            // F does not decrease leftwards: nothing at or left of b is admissible.
            b = f64::NEG_INFINITY;
            done = true;
            break;
        }
        binding = Some(pair);
        if root.is_nan() || root >= b {
            // No progress: only by rounding, b is the root.
            done = true;
            break;
        }
        b = root;
    }
    // The left end: 0 when rest is admissible, F(0) ≤ 0: every band has lo ≤ 0 ≤ hi, so it
    // is when the next set holds 0; else from 0 rightwards.
    let mut a: f64 = 0.0;
    let mut left_done = lo <= 0.0 && hi >= 0.0;
    for _ in 0..steps {
        if left_done || a > b {
            left_done = true;
            break;
        }
        let (pair, f) = envelope(bands, &next, a);
        if f <= 0.0 {
            left_done = true;
            break;
        }
        let (c, root) = pair_root(bands, &next, pair);
        if c.is_nan() || c >= 0.0 {
            // F does not decrease rightwards: nothing at or right of a is admissible.
            a = f64::INFINITY;
            left_done = true;
            break;
        }
        if root.is_nan() || root <= a {
            left_done = true;
            break;
        }
        a = root;
    }
    if !(done && left_done) {
        return (x_range_pairwise(bands, x_max, d, lo, hi), None);
    }
    ((a, b), binding)
}

/// [`x_range`] by intersecting the half-lines of every pair of a lower and an upper line.
fn x_range_pairwise(bands: &[Band], x_max: f64, d: f64, lo: f64, hi: f64) -> (f64, f64) {
    let next_lower = (-1.0 / (2.0 * d), lo / (2.0 * d));
    let next_upper = (-1.0 / (2.0 * d), hi / (2.0 * d));
    let lower = bands.iter().map(|b| (b.slope, b.lo)).chain([next_lower]);
    let mut a: f64 = 0.0;
    let mut b = x_max;
    for (ls, lo_) in lower {
        let upper = bands.iter().map(|b| (b.slope, b.hi)).chain([next_upper]);
        for (hs, ho) in upper {
            // ls x + lo_ ≤ hs x + ho  ⇔  (ls - hs) x ≤ ho - lo_
            let c = ls - hs;
            let r = ho - lo_;
            if c > EPS {
                b = b.min(r / c);
            } else if c < -EPS {
                a = a.max(r / c);
            } else if r < 0.0 {
                // Parallel lines the wrong way round: only rounding makes them so when
                // both come from the same joint at u's bound; keep rest admissible.
                b = b.min(0.0);
            }
        }
    }
    (a, b)
}

/// The admissible `u` at `x` that keeps the next `x` in `[lo, hi]`.
fn u_range(bands: &[Band], x: f64, d: f64, lo: f64, hi: f64) -> (f64, f64) {
    let mut ulo = (lo - x) / (2.0 * d);
    let mut uhi = (hi - x) / (2.0 * d);
    for b in bands {
        let sx = b.slope * x;
        ulo = ulo.max(sx + b.lo);
        uhi = uhi.min(sx + b.hi);
    }
    (ulo, uhi)
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn norm(a: &[f64]) -> f64 {
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

#[cfg(test)]
mod tests;
