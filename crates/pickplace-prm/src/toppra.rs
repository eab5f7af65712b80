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

mod blend;

use blend::{ArcAngle, Piece};
pub use blend::{BlendedPath, Location};

/// Below this, a turn is straight (no arc) and a length is zero.
const EPS: f64 = 1e-12;

/// Fewest stages of a path's grid.
const MIN_STAGES: f64 = 32.0;

/// Largest turn of the tangent within one stage on an arc (rad). The limits hold at the grid
/// points; between them a joint's velocity follows the turning tangent: with 0.2 rad, a slow
/// jaw opening while the arm starts moving overshot its limit by up to 6 % (issue 32's
/// one-jaw arm), with 0.05 rad by none the validator sees.
const ARC_STAGE_ANGLE: f64 = 0.05;

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
pub(super) fn last_at_most(sorted: &[f64], v: f64, hint: usize) -> usize {
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

#[cfg(test)]
mod tests;
