//! What a pad touches (§III-A, Fig. 2; the paper's ref. \[15\]): the triangles that may lie
//! under a pad, the rise of the surface under it and the area its flexible sheet meets.

use super::GraspPlanner;
use pickplace_geometry::math::{Point3, Real, Vector3};

/// A pad's rectangle: its in-plane axes (unit), half sizes along them (m) and where its centre
/// lies from the contact point.
pub(super) struct Footprint {
    pub(super) lateral: Vector3,
    pub(super) approach: Vector3,
    pub(super) half: (Real, Real),
    /// How far the pad's centre lies behind the contact point along `-approach` (m): 0 for a
    /// pad centred on its contact point, more for a pad drawn back so that the finger tip
    /// stops short of the edge of a thin object ([`super::GraspOptions`], "tip shift").
    pub(super) shift: Real,
}

/// The triangles that may lie under a pad ([`GraspPlanner::facing_near`]): their corners
/// relative to the contact point, in triangle order, with each one's highest corner along the
/// direction to the pad, and their indices from the highest down.
pub(super) struct Near {
    triangles: Vec<[Vector3; 3]>,
    top: Vec<Real>,
    by_top: Vec<usize>,
    toward: Vector3,
}

impl Near {
    pub(super) fn new(triangles: Vec<[Vector3; 3]>, toward: Vector3) -> Self {
        let top: Vec<Real> = triangles
            .iter()
            .map(|d| {
                d.iter()
                    .map(|d| d.dot(&toward))
                    .fold(Real::NEG_INFINITY, Real::max)
            })
            .collect();
        let mut by_top: Vec<usize> = (0..triangles.len()).collect();
        by_top.sort_unstable_by(|&i, &j| top[j].total_cmp(&top[i]).then(i.cmp(&j)));
        Self {
            triangles,
            top,
            by_top,
            toward,
        }
    }

    pub(super) fn empty() -> Self {
        Self::new(Vec::new(), Vector3::z())
    }
}

impl GraspPlanner {
    /// The triangles facing `toward` (unit, from the surface to a pad) that meet the cylinder
    /// of radius `radius` about `contact` along `toward`, from `h_max` below it to `ceiling`
    /// above it (conservatively: through the BVH, then the square about the disc): every
    /// triangle that can lie under a pad centred on `contact`, whatever the approach
    /// direction.
    ///
    /// Returns their corners relative to `contact`, in triangle order; triangles lying wholly
    /// more than `h_max` below `contact` or more than `ceiling` above it (beyond the back of
    /// the open finger: never touched) are left out.
    pub(super) fn facing_near(
        &self,
        contact: &Point3,
        toward: &Vector3,
        radius: Real,
        (h_max, ceiling): (Real, Real),
    ) -> Near {
        let reach = Vector3::repeat(radius + h_max.max(ceiling));
        let near = self
            .collider
            .triangles_near(&(contact - reach), &(contact + reach));
        // Any in-plane basis: the pad's rectangle turns about the contact point, inside the
        // disc of `radius`, so a triangle wholly beside the disc's square is never under it.
        let u = toward.cross(&Vector3::x());
        let u = if u.norm_squared() > 1e-6 {
            u.normalize()
        } else {
            toward.cross(&Vector3::y()).normalize()
        };
        let v = toward.cross(&u);
        let triangles = near
            .iter()
            .filter_map(|&t| {
                let tri = self.triangles.get(t as usize)?;
                let [a, b, c] = tri.map(|v| self.vertices[v as usize]);
                if (b - a).cross(&(c - a)).dot(toward) <= 0.0 {
                    return None;
                }
                let d = [a - contact, b - contact, c - contact];
                let beside = |axis: &Vector3| {
                    d.iter().all(|d| d.dot(axis) > radius)
                        || d.iter().all(|d| d.dot(axis) < -radius)
                };
                let heights = d.map(|d| d.dot(toward));
                let reached =
                    heights.iter().any(|&h| h >= -h_max) && heights.iter().any(|&h| h <= ceiling);
                (reached && !beside(&u) && !beside(&v)).then_some(d)
            })
            .collect::<Vec<_>>();
        Near::new(triangles, *toward)
    }

    /// The rise under a pad (its first pass) or the area it touches (its second): what a
    /// pad centred on a contact point of the surface, facing the surface from `toward` (unit,
    /// from the surface to the pad), with the rectangle `footprint`, meets.
    ///
    /// The rigid pad first touches the highest point of the surface under it; its flexible
    /// sheet of depth `h_max` (§III-A, Fig. 2; the paper's ref. \[15\]) then reaches every part
    /// of the surface within `h_max` below that point. The touched area is that part, measured
    /// on the mesh itself (every triangle facing the pad, not only the clusters'), so a pad on
    /// a curved body (a duck, a fruit, a bottle's neck) touches the cap the sheet wraps, and a
    /// pad on a flat face touches the face under it. Triangles facing away (the far side of a
    /// thin wall) are not touched. Each triangle is projected onto the pad plane, clipped to
    /// the rectangle, to the sheet's reach below the contact point and to the back of the open
    /// finger (`ceiling`); the height is affine over a triangle, so the highest point is at a
    /// corner of a clipped polygon.
    ///
    /// With `level = None` returns the rise: the height of the highest point above the contact
    /// point (m, at least 0). With `level = Some(l)` returns the area (m², projected onto the
    /// pad, at most the pad's) of the parts at height `l` or more: with `l = rise − h_max`,
    /// what the pressed sheet touches. Two passes, so that a candidate whose rise is already
    /// too deep costs no area.
    ///
    /// `near` lists the triangles facing the pad that may lie under it, their corners relative
    /// to the contact point ([`Self::facing_near`]).
    pub(super) fn pad_scan(
        footprint: &Footprint,
        (h_max, ceiling): (Real, Real),
        near: &Near,
        level: Option<Real>,
    ) -> Real {
        let (hw, hd) = footprint.half;
        let floor = level.unwrap_or(-h_max).max(-h_max);
        // The part of triangle `i` under the pad, between `floor` and `ceiling`.
        let clipped = |i: usize| -> Option<Poly> {
            let corners = near.triangles[i].map(|d| {
                [
                    d.dot(&footprint.lateral),
                    d.dot(&footprint.approach) + footprint.shift,
                    d.dot(&near.toward),
                ]
            });
            // Quick exits: entirely beside the pad, below the reach, above the finger's back.
            if corners.iter().all(|q| q[0] > hw)
                || corners.iter().all(|q| q[0] < -hw)
                || corners.iter().all(|q| q[1] > hd)
                || corners.iter().all(|q| q[1] < -hd)
                || corners.iter().all(|q| q[2] < floor)
                || corners.iter().all(|q| q[2] > ceiling)
            {
                return None;
            }
            // Two buffers in turn: a cut writes the other one, no copy.
            let mut buffers = [Poly::triangle(corners), Poly::EMPTY];
            let mut current = 0;
            for (axis, sign, limit) in [
                (0, 1.0, hw),
                (0, -1.0, hw),
                (1, 1.0, hd),
                (1, -1.0, hd),
                (2, -1.0, -floor),
                (2, 1.0, ceiling),
            ] {
                let [a, b] = &mut buffers;
                let (src, dst) = if current == 0 { (a, b) } else { (b, a) };
                if clip_into(src, dst, axis, sign, limit) {
                    current = 1 - current;
                }
                if buffers[current].len < 3 {
                    return None;
                }
            }
            Some(buffers[current])
        };
        match level {
            None => {
                // From the highest triangle down: once a triangle's highest corner is no
                // higher than the rise found, no later one can raise it.
                let mut rise: Real = 0.0;
                for &i in &near.by_top {
                    if near.top[i].min(ceiling) <= rise {
                        break;
                    }
                    if let Some(poly) = clipped(i) {
                        for q in poly.points() {
                            rise = rise.max(q[2]);
                        }
                    }
                }
                rise
            }
            Some(_) => {
                // In triangle order (the sum's order); a triangle wholly below the level
                // touches nothing.
                let mut area = 0.0;
                for i in 0..near.triangles.len() {
                    if near.top[i] < floor {
                        continue;
                    }
                    if let Some(poly) = clipped(i) {
                        area += poly.area();
                    }
                }
                area.min(4.0 * hw * hd)
            }
        }
    }
}

/// A convex polygon of at most [`Poly::CAPACITY`] points `[x, y, height]`, on the stack: a
/// triangle clipped by up to 6 half-planes (4 sides of the pad, the sheet's reach, the back of
/// the open finger).
#[derive(Debug, Clone, Copy)]
struct Poly {
    points: [[Real; 3]; Poly::CAPACITY],
    len: usize,
}

impl Poly {
    const CAPACITY: usize = 9;
    const EMPTY: Self = Self {
        points: [[0.0; 3]; Self::CAPACITY],
        len: 0,
    };

    fn triangle(corners: [[Real; 3]; 3]) -> Self {
        let mut points = [[0.0; 3]; Self::CAPACITY];
        points[..3].copy_from_slice(&corners);
        Self { points, len: 3 }
    }

    fn points(&self) -> &[[Real; 3]] {
        &self.points[..self.len]
    }

    /// Twice the signed area of the projection onto `(x, y)`.
    fn area(&self) -> Real {
        let p = self.points();
        let mut twice = 0.0;
        for (i, a) in p.iter().enumerate() {
            let b = &p[(i + 1) % p.len()];
            twice += a[0] * b[1] - b[0] * a[1];
        }
        0.5 * twice.abs()
    }
}

/// Sutherland–Hodgman: the part of a polygon (points `[x, y, height]`) where
/// `sign · p[axis] ≤ limit`, the height interpolated along the cut edges.
/// Sutherland–Hodgman from `src` into `dst`: the part of a polygon (points
/// `[x, y, height]`) where `sign · p[axis] ≤ limit`, the height interpolated along the cut
/// edges; `false` (and `dst` untouched) when nothing is cut off.
fn clip_into(src: &Poly, dst: &mut Poly, axis: usize, sign: Real, limit: Real) -> bool {
    let inside = |p: &[Real; 3]| sign * p[axis] <= limit;
    let points = src.points();
    if points.iter().all(inside) {
        return false;
    }
    dst.len = 0;
    let mut push = |q: [Real; 3]| {
        // A convex polygon gains one point per cut: the capacity is never reached by the
        // clips made here; a degenerate sliver past it only loses points.
        if dst.len < Poly::CAPACITY {
            dst.points[dst.len] = q;
            dst.len += 1;
        }
    };
    for (i, p) in points.iter().enumerate() {
        let q = &points[(i + 1) % points.len()];
        if inside(p) {
            push(*p);
        }
        if inside(p) != inside(q) {
            let (a, b) = (sign * p[axis] - limit, sign * q[axis] - limit);
            let t = a / (a - b);
            push([
                p[0] + (q[0] - p[0]) * t,
                p[1] + (q[1] - p[1]) * t,
                p[2] + (q[2] - p[2]) * t,
            ]);
        }
    }
    true
}
