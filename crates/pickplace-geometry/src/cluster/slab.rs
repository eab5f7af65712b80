//! A contact plane for a set of triangles when the regression plane does not fit (issue 31).
//!
//! §III-A asks that a cluster's vertices fit in a slab of thickness `h_max` (Fig. 2); the
//! growth measures the slab along the regression plane `P`, which is not the thinnest one, and
//! a triangle tilted by noise can break the facet-angle limit along `P` but not along a
//! neighbouring direction. [`find_slab_normal`] looks for *any* direction `d` with
//! - `max d·p − min d·p ≤ h_max` over the points,
//! - every triangle normal within `max_facet_angle` of `d`,
//! - `d` within `max_deviation` ([`super::MAX_FIT_DEVIATION`]) of the area-weighted normal `m`.
//!
//! In the gnomonic chart `w = m + a·u + b·v` (`u`, `v` spanning the plane orthogonal to `m`)
//! the angle conditions are second-order cones, `cos α·|w| − n·w ≤ 0`: convex in `(a, b)`. The
//! slab condition `spread(w) ≤ h_max·|w|`, with `spread(w) = max p·w − min p·w` convex, is not
//! (convex minus convex), and two convex versions of it are used:
//! - *relaxed*: `spread(w) ≤ h_max·R` where `R` bounds `|w|` over the current search region:
//!   implied by the true condition, so a cut that removes points violating it never removes
//!   a solution;
//! - *strict at z*: `spread(w) ≤ h_max·z·w` for a unit `z`: implies the true condition
//!   (`|w| ≥ z·w`) and equals it for `w` along `z`.
//!
//! Each is a convex feasibility problem in two variables, solved by the ellipsoid method with
//! deep cuts: an iteration evaluates the worst violated condition and its subgradient at the
//! centre of the ellipse, and either stops (the centre satisfies the *true* conditions), proves
//! that no point of the ellipse can (the linear lower bound is positive over all of it), or
//! keeps the part of the ellipse that may hold a solution. The relaxed search runs first and
//! refuses most pairs within one or two iterations; where only the true slab condition fails it
//! steps along that condition's own linearisation, which is not a proof any more. When it ends
//! without an answer, two strict searches follow, each at the best direction found so far (the
//! convex-concave procedure), which settles the pairs whose thinnest admissible plane lies at
//! the edge of the 20° cone.

use super::geometry::tangent_pair;
use super::hull::convex_hull;
use super::width::{edge_pair_directions, face_directions};
use crate::math::{Real, Vector3};

/// Largest number of iterations of one ellipsoid search (each shrinks the area by at least
/// 23 %).
const MAX_ITERATIONS: usize = 80;
/// Strict searches after a relaxed one that ended unsure.
const STRICT_ROUNDS: usize = 12;
/// Unions with at most this many points get a ring of extra starts.
const RING_POINTS: usize = 64;

/// A slab search: the union's points and the triangle normals that can bind.
#[derive(Debug)]
pub(crate) struct SlabProblem<'a> {
    /// The points that must fit (any origin).
    pub points: &'a [Vector3],
    /// Unit normals of the triangles whose facet angle may bind.
    pub normals: &'a [Vector3],
    /// Unit area-weighted normal `m`.
    pub mean: Vector3,
    /// Slab thickness (m).
    pub h_max: Real,
    /// Largest angle between `d` and a triangle normal (rad), strict.
    pub max_facet_angle: Real,
    /// Largest angle between `d` and `m` (rad), below π/2.
    pub max_deviation: Real,
}

/// A direction satisfying every condition of `problem` (see the module documentation), or
/// `None` when the search proves there is none, or gives up. Deterministic.
pub(crate) fn find_slab_normal(problem: &SlabProblem<'_>) -> Option<Vector3> {
    let m = problem.mean;
    let (u, v) = tangent_pair(&m);
    let cos_facet = (problem.max_facet_angle * (1.0 - 1e-9)).cos();
    let cos_deviation = (problem.max_deviation * (1.0 - 1e-9)).cos();
    // A normal at least max_facet_angle + max_deviation from m cannot be within the facet
    // angle of any admissible direction.
    let hopeless = (problem.max_facet_angle + problem.max_deviation).cos();
    if problem.normals.iter().any(|n| n.dot(&m) <= hopeless) {
        return None;
    }
    let mean_point = problem.points.iter().sum::<Vector3>() / (problem.points.len().max(1) as Real);
    let scale = problem
        .points
        .iter()
        .map(|p| (p - mean_point).norm())
        .fold(0.0, Real::max)
        .max(1e-12);
    let search = Search {
        problem,
        u,
        v,
        cos_facet,
        cos_deviation,
        scale,
        h: problem.h_max * (1.0 - 1e-9),
        r0: problem.max_deviation.tan(),
    };
    let relaxed_best = match search.run(None) {
        Outcome::Found(d) => return Some(d),
        Outcome::Infeasible => return None,
        Outcome::Unsure(best) => best,
    };
    // The slab condition may have several local minima over the cap: the thinnest
    // directions of the points (hull faces and edge pairs, super::width), brought onto the cap
    // when outside it, are tried as answers and as starts of the strict searches.
    let mut starts = Vec::new();
    if let Some(hull) = convex_hull(problem.points) {
        let rim = problem.max_deviation * (1.0 - 1e-7);
        let critical: Vec<(Vector3, Real)> = face_directions(problem.points, &hull)
            .into_iter()
            .chain(edge_pair_directions(problem.points, &hull))
            .collect();
        // The least of these widths is the points' minimum width over every direction (on
        // the hull's vertices, so never above it): beyond h_max, no plane at all fits.
        if critical.iter().all(|(_, w)| *w > problem.h_max) {
            return None;
        }
        let mut thin: Vec<(Real, Vector3)> = critical
            .into_iter()
            .map(|(d, w)| {
                let d = if d.dot(&m) < 0.0 { -d } else { d };
                let d = if d.dot(&m) >= cos_deviation {
                    d
                } else {
                    match (d - m * d.dot(&m)).try_normalize(1e-12) {
                        Some(t) => m * rim.cos() + t * rim.sin(),
                        None => m,
                    }
                };
                (w, d)
            })
            .collect();
        thin.sort_by(|p, q| {
            p.0.total_cmp(&q.0)
                .then(p.1.x.total_cmp(&q.1.x))
                .then(p.1.y.total_cmp(&q.1.y))
                .then(p.1.z.total_cmp(&q.1.z))
        });
        for &(_, d) in thin.iter().take_while(|(w, _)| *w <= search.h) {
            if search.fits(&d) {
                return Some(d);
            }
        }
        starts.extend(thin.iter().take(2).map(|&(_, d)| d));
    }
    starts.push(relaxed_best);
    // Then a ring of starts over the cap (the slab condition's basins can lie anywhere in it),
    // for small unions only: each start costs a few ellipsoid searches over the points.
    if problem.points.len() <= RING_POINTS {
        let (u, v) = (search.u, search.v);
        for (radius, count) in [(0.95, 8), (0.6, 6)] {
            let polar = problem.max_deviation * radius;
            for k in 0..count {
                let azimuth = std::f64::consts::TAU * k as Real / count as Real;
                starts
                    .push(m * polar.cos() + (u * azimuth.cos() + v * azimuth.sin()) * polar.sin());
            }
        }
    }
    for start in starts {
        let mut z = start;
        for _ in 0..STRICT_ROUNDS {
            match search.run(Some(z)) {
                Outcome::Found(d) => return Some(d),
                Outcome::Infeasible => return None,
                Outcome::Unsure(next) => {
                    // The convex-concave procedure has settled.
                    if (next - z).norm() < 1e-10 {
                        break;
                    }
                    z = next;
                }
            }
        }
    }
    None
}

/// What one ellipsoid search ended with.
enum Outcome {
    /// A direction satisfying the true conditions.
    Found(Vector3),
    /// Proof that none exists.
    Infeasible,
    /// Neither; the direction to go on from: the least violation of the true conditions seen
    /// (relaxed search) or of the search's own (strict search).
    Unsure(Vector3),
}

/// The chart and the constants of one problem.
struct Search<'a> {
    problem: &'a SlabProblem<'a>,
    /// The chart's axes (orthogonal to `m`).
    u: Vector3,
    v: Vector3,
    cos_facet: Real,
    cos_deviation: Real,
    /// Radius of the points (m): the slab condition is divided by it, so that it weighs like
    /// the angle conditions.
    scale: Real,
    /// `h_max`, a hair thinner.
    h: Real,
    /// Radius of the chart's disc, `tan(max_deviation)`.
    r0: Real,
}

impl Search<'_> {
    /// Whether unit `d` satisfies every condition (with the search's margins).
    fn fits(&self, d: &Vector3) -> bool {
        let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
        for q in self.problem.points {
            lo = lo.min(q.dot(d));
            hi = hi.max(q.dot(d));
        }
        hi - lo <= self.h
            && d.dot(&self.problem.mean) >= self.cos_deviation
            && self
                .problem
                .normals
                .iter()
                .all(|n| n.dot(d) >= self.cos_facet)
    }

    /// One ellipsoid search from the chart's disc: relaxed (`strict_at` `None`) or strict at
    /// the given direction (module documentation).
    fn run(&self, strict_at: Option<Vector3>) -> Outcome {
        let (m, u, v, h, scale) = (self.problem.mean, self.u, self.v, self.h, self.scale);
        let (mut c, mut p) = ([0.0, 0.0], [self.r0 * self.r0, 0.0, self.r0 * self.r0]);
        let mut best = (Real::INFINITY, m);
        // The least violation of a strict search's own conditions, and where.
        let mut least = (Real::INFINITY, m);
        // Whether a cut followed the true slab condition's linearisation (not a valid cut).
        let mut local_steps = false;
        for _ in 0..MAX_ITERATIONS {
            let w = m + u * c[0] + v * c[1];
            let len = w.norm();
            let dlen = [c[0] / len, c[1] / len];
            // The worst angle condition: value and subgradient in (a, b).
            let mut worst = self.cos_deviation * len - 1.0;
            let mut grad = [self.cos_deviation * dlen[0], self.cos_deviation * dlen[1]];
            for n in self.problem.normals {
                let value = self.cos_facet * len - n.dot(&w);
                if value > worst {
                    worst = value;
                    grad = [
                        self.cos_facet * dlen[0] - n.dot(&u),
                        self.cos_facet * dlen[1] - n.dot(&v),
                    ];
                }
            }
            let (mut lo, mut hi) = ((Real::INFINITY, 0), (Real::NEG_INFINITY, 0));
            for (i, q) in self.problem.points.iter().enumerate() {
                let x = q.dot(&w);
                if x < lo.0 {
                    lo = (x, i);
                }
                if x > hi.0 {
                    hi = (x, i);
                }
            }
            let spread = hi.0 - lo.0;
            let across = (self.problem.points[hi.1] - self.problem.points[lo.1]) / scale;
            let exact = worst.max((spread - h * len) / scale);
            if exact <= 0.0 {
                return Outcome::Found(w / len);
            }
            if exact < best.0 {
                best = (exact, w / len);
            }
            match strict_at {
                Some(z) => {
                    let value = (spread - h * z.dot(&w)) / scale;
                    if value > worst {
                        worst = value;
                        let e = across - z * (h / scale);
                        grad = [e.dot(&u), e.dot(&v)];
                    }
                }
                None => {
                    // Every point of the ellipse has |w| ≤ reach.
                    let radius = {
                        let (mean, diff) = (0.5 * (p[0] + p[2]), 0.5 * (p[0] - p[2]));
                        (mean + (diff * diff + p[1] * p[1]).sqrt()).max(0.0).sqrt()
                    };
                    let reach = (1.0 + (c[0].hypot(c[1]) + radius).powi(2))
                        .min(1.0 + self.r0 * self.r0)
                        .sqrt();
                    let value = (spread - h * reach) / scale;
                    if value > worst {
                        worst = value;
                        grad = [across.dot(&u), across.dot(&v)];
                    }
                    if worst <= 0.0 {
                        // Only the true slab condition fails here: a local step along its
                        // linearisation.
                        local_steps = true;
                        worst = (spread - h * len) / scale;
                        let e = across - w * (h / (len * scale));
                        grad = [e.dot(&u), e.dot(&v)];
                    }
                }
            }
            // Deep cut {x : worst + g·(x − c) ≤ 0} of the ellipse {x : (x−c)ᵀP⁻¹(x−c) ≤ 1}.
            let pg = [
                p[0] * grad[0] + p[1] * grad[1],
                p[1] * grad[0] + p[2] * grad[1],
            ];
            let gpg = grad[0] * pg[0] + grad[1] * pg[1];
            if !(gpg.is_finite() && gpg > 1e-300) {
                break;
            }
            let s = gpg.sqrt();
            // Strict searches minimise their violation (the next round starts from the
            // minimiser): the cut keeps what may beat the best value so far.
            let target = match strict_at {
                Some(_) => {
                    if worst < least.0 {
                        least = (worst, w / len);
                    }
                    least.0
                }
                None => 0.0,
            };
            let alpha = (worst - target) / s;
            if alpha >= 1.0 {
                // The linear lower bound is positive over the whole ellipse: a proof when
                // every cut so far was valid for the true conditions.
                if strict_at.is_none() && !local_steps {
                    return Outcome::Infeasible;
                }
                break;
            }
            let b = [pg[0] / s, pg[1] / s];
            let step = (1.0 + 2.0 * alpha) / 3.0;
            c = [c[0] - step * b[0], c[1] - step * b[1]];
            let shrink = 4.0 / 3.0 * (1.0 - alpha * alpha);
            let k = 2.0 * (1.0 + 2.0 * alpha) / (3.0 * (1.0 + alpha));
            p = [
                shrink * (p[0] - k * b[0] * b[0]),
                shrink * (p[1] - k * b[0] * b[1]),
                shrink * (p[2] - k * b[1] * b[1]),
            ];
            if !(p[0] > 0.0 && p[2] > 0.0 && p[0] * p[2] - p[1] * p[1] > 0.0) || p[0] + p[2] < 1e-24
            {
                break;
            }
        }
        match strict_at {
            Some(_) => Outcome::Unsure(least.1),
            None => Outcome::Unsure(best.1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem<'a>(
        points: &'a [Vector3],
        normals: &'a [Vector3],
        mean: Vector3,
    ) -> SlabProblem<'a> {
        SlabProblem {
            points,
            normals,
            mean,
            h_max: 0.005,
            max_facet_angle: 80f64.to_radians(),
            max_deviation: 20f64.to_radians(),
        }
    }

    #[test]
    fn a_tilted_slab_is_found_away_from_the_mean_normal() {
        // Points in a 4 mm slab whose normal is 12° from m: along m they span 1 cm.
        let n = Vector3::new(12f64.to_radians().sin(), 0.0, 12f64.to_radians().cos());
        let (u, v) = tangent_pair(&n);
        let mut points = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                let depth = if (i + j) % 2 == 0 { 0.0 } else { 0.004 };
                points.push(u * (i as Real * 0.01) + v * (j as Real * 0.01) + n * depth);
            }
        }
        let m = Vector3::z();
        let d = find_slab_normal(&problem(&points, &[], m)).expect("a slab");
        let (lo, hi) = points
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), p| {
                (l.min(d.dot(p)), h.max(d.dot(p)))
            });
        assert!(hi - lo <= 0.005, "{}", hi - lo);
        assert!(d.dot(&m) >= 20f64.to_radians().cos());
    }

    #[test]
    fn a_tilted_triangle_is_kept_within_the_facet_angle() {
        // m is z; one normal 85° away: d must lean towards it by at least 5°.
        let far = Vector3::new(85f64.to_radians().sin(), 0.0, 85f64.to_radians().cos());
        let normals = [Vector3::z(), far];
        let points = [Vector3::zeros(), Vector3::x() * 0.001];
        let d = find_slab_normal(&problem(&points, &normals, Vector3::z())).expect("a plane");
        assert!(d.dot(&far) > 80f64.to_radians().cos());
        // 101° away: no direction within 20° of m is within 80° of it.
        let beyond = Vector3::new(101f64.to_radians().sin(), 0.0, 101f64.to_radians().cos());
        assert!(find_slab_normal(&problem(&points, &[beyond], Vector3::z())).is_none());
    }

    #[test]
    fn a_corner_is_refused() {
        // Two perpendicular 5 cm faces: no slab of 5 mm holds both.
        let mut points = Vec::new();
        for i in 0..6 {
            points.push(Vector3::new(i as Real * 0.01, 0.0, 0.0));
            points.push(Vector3::new(0.0, 0.0, i as Real * 0.01));
        }
        let m = Vector3::new(1.0, 0.0, 1.0).normalize();
        assert!(find_slab_normal(&problem(&points, &[], m)).is_none());
    }
}
