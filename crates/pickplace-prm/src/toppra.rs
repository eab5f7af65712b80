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

/// Largest turn of the tangent within one stage on an arc (rad).
const ARC_STAGE_ANGLE: f64 = 0.2;

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
    length: f64,
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
        let mut points: Vec<&Vec<f64>> = Vec::with_capacity(waypoints.len());
        for w in waypoints {
            if points.last().is_none_or(|p| distance(p, w) > EPS) {
                points.push(w);
            }
        }
        let mut parts: Vec<Vec<&Vec<f64>>> = vec![Vec::new()];
        for (i, p) in points.iter().enumerate() {
            if let Some(part) = parts.last_mut() {
                part.push(p);
            }
            if i > 0 && i + 1 < points.len() && turn(points[i - 1], p, points[i + 1]) > REVERSAL {
                parts.push(vec![p]);
            }
        }
        Ok(parts
            .into_iter()
            .filter(|part| part.len() >= 2)
            .map(|part| Self::blend(&part, tolerance, dof))
            .collect())
    }

    /// The path through `points` (no reversal, no repeated point), corners blended.
    fn blend(points: &[&Vec<f64>], tolerance: f64, dof: usize) -> Self {
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
                .min(tolerance * half.sin() / (1.0 - half.cos()));
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
        for i in 0..n - 1 {
            let dir = unit(points[i], points[i + 1], seg_len[i]);
            let length = (seg_len[i] - cut[i] - cut[i + 1]).max(0.0);
            if length > EPS {
                pieces.push(Piece::Line {
                    start: (0..dof).map(|j| points[i][j] + cut[i] * dir[j]).collect(),
                    dir,
                    length,
                });
            }
            if let Some(arc) = arcs[i + 1].take() {
                pieces.push(arc);
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

    /// Position, tangent and curvature vector at arc length `s` (clamped into the path).
    pub fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        let s = s.clamp(0.0, self.length);
        let k = self.starts.partition_point(|&t| t <= s).saturating_sub(1);
        if let Some(piece) = self.pieces.get(k) {
            piece.eval(s - self.starts[k], q, dq, ddq);
        }
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
        let n = self.grid.len();
        if n < 2 {
            return (self.grid.first().copied().unwrap_or(0.0), 0.0, 0.0);
        }
        let t = t.clamp(0.0, self.duration());
        let i = self
            .times
            .partition_point(|&ti| ti <= t)
            .saturating_sub(1)
            .min(n - 2);
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
    let grid = grid(path, options.grid_step)?;
    let n = grid.len();
    if n < 2 {
        return Ok(Parameterization {
            grid,
            x: vec![0.0; n],
            times: vec![0.0; n],
        });
    }
    // Each stage's constraints, evaluated at its first grid point (collocation).
    let mut q = vec![0.0; dof];
    let mut dq = vec![0.0; dof];
    let mut ddq = vec![0.0; dof];
    // Each stage lies within one piece: its start's derivatives are the piece's at s_i, its
    // end's the same piece's just before s_{i+1} (at a junction the next piece's curvature
    // is another).
    let mut derivative = |s: f64| {
        path.eval(s, &mut q, &mut dq, &mut ddq);
        (dq.clone(), ddq.clone())
    };
    let stages: Vec<Stage> = (0..n - 1)
        .map(|i| {
            let d = grid[i + 1] - grid[i];
            let start = derivative(grid[i]);
            let end = derivative(grid[i + 1] - 1e-9 * d);
            Stage::new(&start, &end, d, options)
        })
        .collect();
    // Backward pass: controllable sets [lo, hi] of x, the last one {0}.
    let mut lo = vec![0.0; n];
    let mut hi = vec![0.0; n];
    for i in (0..n - 1).rev() {
        let d = grid[i + 1] - grid[i];
        let (a, b) = stages[i].x_range(d, lo[i + 1], hi[i + 1]);
        // Rest (x = 0, u = 0) is always admissible, so the set is never empty; rounding may
        // only make it look so.
        lo[i] = a.max(0.0).min(b.max(0.0));
        hi[i] = b.max(0.0);
    }
    // Forward pass: from rest, the largest u that keeps x controllable.
    let mut x = vec![0.0; n];
    for i in 0..n - 1 {
        let d = grid[i + 1] - grid[i];
        let (ulo, uhi) = stages[i].u_range(x[i], d, lo[i + 1], hi[i + 1]);
        let u = if uhi >= ulo { uhi } else { ulo.min(uhi) };
        x[i + 1] = (x[i] + 2.0 * d * u).clamp(lo[i + 1], hi[i + 1].max(lo[i + 1]));
    }
    x[n - 1] = 0.0;
    let mut times = vec![0.0; n];
    for i in 0..n - 1 {
        let d = grid[i + 1] - grid[i];
        let speed = x[i].sqrt() + x[i + 1].sqrt();
        // A stage with no speed at both ends only occurs for a zero-length stage.
        let dt = if speed > 0.0 { 2.0 * d / speed } else { 0.0 };
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
    let mut q = vec![0.0; dof];
    let mut dq = vec![0.0; dof];
    let mut ddq = vec![0.0; dof];
    let mut points = Vec::with_capacity(count + 1);
    for k in 0..=count {
        let t = (k as f64 * sample_period).min(duration);
        let (s, sd, sdd) = timing.state(t);
        path.eval(s, &mut q, &mut dq, &mut ddq);
        points.push(TrajectoryPoint {
            time_from_start: t,
            positions: q.clone(),
            velocities: dq.iter().map(|d| d * sd).collect(),
            accelerations: (0..dof).map(|j| dq[j] * sdd + ddq[j] * sd * sd).collect(),
        });
        if t >= duration {
            break;
        }
    }
    Ok(Trajectory { points })
}

/// The grid: every junction of pieces, and points between them at most `step` apart.
fn grid(path: &BlendedPath, step: f64) -> Result<Vec<f64>> {
    // On an arc the tangent turns: a stage turns it by at most ARC_STAGE_ANGLE, so that the
    // constraints met at both ends of a stage hold closely in between.
    let steps: Vec<(f64, f64, f64)> = path
        .pieces
        .iter()
        .zip(&path.starts)
        .map(|(p, &s0)| {
            let h = match p {
                Piece::Line { .. } => step,
                Piece::Arc { radius, .. } => step.min(radius * ARC_STAGE_ANGLE),
            };
            (s0, p.length(), h)
        })
        .collect();
    let mut count = 0.0;
    for &(_, len, h) in &steps {
        count += (len / h).ceil().max(1.0);
    }
    if count.is_nan() || count >= MAX_TRAJECTORY_SAMPLES as f64 {
        return Err(Error::TooManyPoints {
            what: "grid points",
            count,
            limit: MAX_TRAJECTORY_SAMPLES,
        });
    }
    let mut g = Vec::with_capacity(count as usize + 1);
    for (s0, len, h) in steps {
        if len <= EPS {
            continue;
        }
        let m = (len / h).ceil().max(1.0) as usize;
        for k in 0..m {
            g.push(s0 + len * k as f64 / m as f64);
        }
    }
    g.push(path.length());
    Ok(g)
}

/// One stage's constraints: `u ≥ l(x)` and `u ≤ h(x)` for lines `l`, `h`, and `x ≤ x_max`.
struct Stage {
    /// Lower lines `(slope, offset)`: `u ≥ slope · x + offset`.
    lower: Vec<(f64, f64)>,
    /// Upper lines: `u ≤ slope · x + offset`.
    upper: Vec<(f64, f64)>,
    /// Largest `x` the velocity limits and the acceleration constraints with no `u` allow.
    x_max: f64,
}

impl Stage {
    /// The constraints of the stage from `s_i` to `s_i + d`, whose path derivatives are
    /// `start` and `end` (`(q', q'')` at each end): the joint accelerations at both ends (at
    /// the end, `x_{i+1} = x + 2 d u`: TOPP-RA's first-order interpolation, so that the limits
    /// hold at every grid point, not only where each stage begins), and the joint velocities
    /// at the start (the end's are the next stage's).
    fn new(
        start: &(Vec<f64>, Vec<f64>),
        end: &(Vec<f64>, Vec<f64>),
        d: f64,
        o: &ToppraOptions,
    ) -> Self {
        let dof = start.0.len();
        let mut lower = Vec::with_capacity(2 * dof);
        let mut upper = Vec::with_capacity(2 * dof);
        let mut x_max = f64::INFINITY;
        for j in 0..dof {
            let v = o.max_velocities[j];
            let acc = o.max_accelerations[j];
            let (a0, b0) = (start.0[j], start.1[j]);
            if a0.abs() > EPS {
                x_max = x_max.min((v / a0) * (v / a0));
            }
            let (a1, b1) = (end.0[j], end.1[j]);
            // -acc ≤ a u + b x ≤ acc, at the start and (with x_{i+1} = x + 2 d u) at the end.
            for (a, b) in [(a0, b0), (a1 + 2.0 * d * b1, b1)] {
                if a.abs() > EPS {
                    // u between (∓acc - b x) / a.
                    let (l, h) = (-acc / a, acc / a);
                    let slope = -b / a;
                    if a > 0.0 {
                        lower.push((slope, l));
                        upper.push((slope, h));
                    } else {
                        lower.push((slope, h));
                        upper.push((slope, l));
                    }
                } else if b.abs() > EPS {
                    x_max = x_max.min(acc / b.abs());
                }
            }
        }
        Self {
            lower,
            upper,
            x_max,
        }
    }

    /// The controllable `x` of this stage given the next one's `[lo, hi]` and the stage's
    /// length `d`: `x ∈ [0, x_max]` with some admissible `u` such that
    /// `x + 2 d u ∈ [lo, hi]`.
    fn x_range(&self, d: f64, lo: f64, hi: f64) -> (f64, f64) {
        // (lo - x) / 2d ≤ u ≤ (hi - x) / 2d joins the stage's own lines.
        let next_lower = (-1.0 / (2.0 * d), lo / (2.0 * d));
        let next_upper = (-1.0 / (2.0 * d), hi / (2.0 * d));
        let mut a: f64 = 0.0;
        let mut b = self.x_max;
        for &(ls, lo_) in self.lower.iter().chain(std::iter::once(&next_lower)) {
            for &(hs, ho) in self.upper.iter().chain(std::iter::once(&next_upper)) {
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
    fn u_range(&self, x: f64, d: f64, lo: f64, hi: f64) -> (f64, f64) {
        let mut ulo = (lo - x) / (2.0 * d);
        let mut uhi = (hi - x) / (2.0 * d);
        for &(s, o) in &self.lower {
            ulo = ulo.max(s * x + o);
        }
        for &(s, o) in &self.upper {
            uhi = uhi.min(s * x + o);
        }
        (ulo, uhi)
    }
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
mod tests {
    use super::*;

    fn opts(dof: usize, v: f64, a: f64) -> ToppraOptions {
        ToppraOptions {
            max_velocities: vec![v; dof],
            max_accelerations: vec![a; dof],
            grid_step: 0.002,
            sample_period: 0.005,
        }
    }

    #[test]
    fn a_straight_line_takes_the_trapezoid_time() {
        // One joint, 1 rad, 1 rad/s, 2 rad/s²: accelerate 0.5 s over 0.25 rad, cruise 0.5 rad
        // in 0.5 s, decelerate 0.5 s: L / v + v / a = 1.5 s.
        let paths = BlendedPath::split(&[vec![0.0], vec![1.0]], 0.01).expect("path");
        assert_eq!(paths.len(), 1);
        let t = parameterize(&paths[0], &opts(1, 1.0, 2.0)).expect("timed");
        assert!((t.duration() - 1.5).abs() < 0.005, "{}", t.duration());
        // Triangle: 0.1 rad at 2 rad/s² peaks at √0.1 rad/s: 2 √(0.1 / 2) s.
        let short = BlendedPath::split(&[vec![0.0], vec![0.1]], 0.01).expect("path");
        let t = parameterize(&short[0], &opts(1, 1.0, 2.0)).expect("timed");
        let expected = 2.0 * (0.1f64 / 2.0).sqrt();
        assert!(
            (t.duration() - expected).abs() < 0.01 * expected,
            "{}",
            t.duration()
        );
    }

    #[test]
    fn blends_stay_within_the_tolerance_and_keep_the_tangent_continuous() {
        let w = vec![
            vec![0.0, 0.0, 0.0],
            vec![1.0, 0.0, 0.0],
            vec![1.0, 1.0, 0.5],
            vec![0.2, 1.2, 0.5],
        ];
        let tol = 0.05;
        let paths = BlendedPath::split(&w, tol).expect("path");
        assert_eq!(paths.len(), 1);
        let p = &paths[0];
        let (mut q, mut dq, mut ddq) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
        let mut prev: Option<Vec<f64>> = None;
        let n = 20_000;
        let mut nearest = [f64::INFINITY; 2];
        for k in 0..=n {
            let s = p.length() * k as f64 / n as f64;
            p.eval(s, &mut q, &mut dq, &mut ddq);
            assert!((norm(&dq) - 1.0).abs() < 1e-9, "unit tangent");
            if let Some(pd) = &prev {
                assert!(distance(pd, &dq) < 1e-2, "tangent jumps at s = {s}");
            }
            prev = Some(dq.clone());
            for (c, corner) in [&w[1], &w[2]].iter().enumerate() {
                nearest[c] = nearest[c].min(distance(&q, corner));
            }
        }
        for d in nearest {
            // The arc's middle is the tolerance away when the tolerance bounds the blend.
            assert!(d <= tol * (1.0 + 1e-6) && d > 0.5 * tol, "{d}");
        }
        // Ends are the first and last waypoints.
        p.eval(0.0, &mut q, &mut dq, &mut ddq);
        assert!(distance(&q, &w[0]) < 1e-12);
        p.eval(p.length(), &mut q, &mut dq, &mut ddq);
        assert!(distance(&q, &w[3]) < 1e-9);
    }

    #[test]
    fn a_reversal_splits_the_path() {
        let w = vec![
            vec![0.0, 0.0],
            vec![1.0, 0.0],
            vec![0.5, 0.0],
            vec![0.5, 0.5],
        ];
        let paths = BlendedPath::split(&w, 0.01).expect("paths");
        assert_eq!(paths.len(), 2);
        assert!((paths[0].length() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_limits_hold_along_the_timed_path() {
        let w = vec![
            vec![0.0, 0.0, 0.0],
            vec![0.8, 0.1, -0.3],
            vec![1.0, 0.9, 0.2],
            vec![0.1, 1.3, 0.6],
            vec![-0.4, 0.2, 0.1],
        ];
        let o = ToppraOptions {
            max_velocities: vec![1.0, 0.7, 1.5],
            max_accelerations: vec![3.0, 2.0, 4.0],
            ..opts(3, 1.0, 1.0)
        };
        let paths = BlendedPath::split(&w, 0.05).expect("path");
        let timing = parameterize(&paths[0], &o).expect("timed");
        let traj = sample(&paths[0], &timing, 0.002).expect("sampled");
        let first = &traj.points[0];
        let last = traj.points.last().expect("points");
        assert!(first.velocities.iter().all(|v| v.abs() < 1e-9));
        assert!(last.velocities.iter().all(|v| v.abs() < 1e-6));
        assert!(distance(&last.positions, &w[4]) < 1e-9);
        for p in &traj.points {
            for j in 0..3 {
                assert!(
                    p.velocities[j].abs() <= o.max_velocities[j] * 1.001,
                    "{p:?}"
                );
                // The limits are met at both ends of every stage; in between, on an arc,
                // the acceleration may drift by a fraction of a percent.
                assert!(
                    p.accelerations[j].abs() <= o.max_accelerations[j] * 1.01,
                    "{p:?}"
                );
            }
        }
        // Time-optimal: some joint is at a limit almost everywhere.
        let saturated = traj
            .points
            .iter()
            .filter(|p| {
                (0..3).any(|j| {
                    p.velocities[j].abs() >= 0.98 * o.max_velocities[j]
                        || p.accelerations[j].abs() >= 0.95 * o.max_accelerations[j]
                })
            })
            .count();
        assert!(
            saturated as f64 >= 0.9 * traj.points.len() as f64,
            "{saturated}"
        );
    }

    #[test]
    fn bad_options_are_refused() {
        let paths = BlendedPath::split(&[vec![0.0], vec![1.0]], 0.01).expect("path");
        let mut o = opts(1, 1.0, 1.0);
        o.max_velocities = vec![0.0];
        assert!(parameterize(&paths[0], &o).is_err());
        let mut o = opts(1, 1.0, 1.0);
        o.max_accelerations = vec![1.0, 1.0];
        assert!(parameterize(&paths[0], &o).is_err());
        let mut o = opts(1, 1.0, 1.0);
        o.grid_step = 1e-9;
        assert!(matches!(
            parameterize(&paths[0], &o),
            Err(Error::TooManyPoints { .. })
        ));
        assert!(BlendedPath::split(&[vec![0.0], vec![f64::NAN]], 0.01).is_err());
        assert!(BlendedPath::split(&[vec![0.0], vec![1.0]], 0.0).is_err());
    }
}
