//! 2D polygons in the frame of a contact plane.
//!
//! The building blocks of the paper's cluster geometry (§III-A: 2D bounding box and boundary of
//! a cluster, Fig. 5(c)(d)) and of its stability test (§III-B.2, Fig. 7): convex hull,
//! area and centroid, point-in-polygon, minimum-area bounding rectangle (rotating calipers),
//! and boolean operations on polygons with holes (through `i_overlay`).
//!
//! Conventions: a ring is a closed loop given without repeating its first point. Outer rings
//! are counter-clockwise, holes clockwise, as returned by every function here; inputs may use
//! either orientation. Booleans use the even-odd rule within each operand, so the polygons of
//! one operand should not overlap each other.

use crate::math::{Point2, Real, Vector2};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// A polygon with holes: one outer ring and zero or more inner rings.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Polygon {
    /// Outer boundary (counter-clockwise).
    pub outer: Vec<Point2>,
    /// Holes (clockwise), each inside `outer`.
    pub holes: Vec<Vec<Point2>>,
}

impl Polygon {
    /// A polygon without holes.
    pub fn new(outer: Vec<Point2>) -> Self {
        Self {
            outer,
            holes: Vec::new(),
        }
    }

    /// Area (m²): outer area minus the holes' areas.
    pub fn area(&self) -> Real {
        signed_area(&self.outer).abs()
            - self
                .holes
                .iter()
                .map(|h| signed_area(h).abs())
                .sum::<Real>()
    }

    /// Area centroid, or `None` when the area is zero.
    pub fn centroid(&self) -> Option<Point2> {
        let (mut a, mut m) = ring_moments(&self.outer, 1.0);
        for h in &self.holes {
            let (ha, hm) = ring_moments(h, -1.0);
            a += ha;
            m += hm;
        }
        (a.abs() > 0.0).then(|| Point2::from(m / a))
    }

    /// True when `p` is inside the outer ring and outside every hole (boundary counts as
    /// either, depending on rounding).
    pub fn contains(&self, p: &Point2) -> bool {
        point_in_ring(p, &self.outer) && !self.holes.iter().any(|h| point_in_ring(p, h))
    }

    /// Every vertex of the outer ring and the holes.
    pub fn points(&self) -> impl Iterator<Item = &Point2> {
        self.outer.iter().chain(self.holes.iter().flatten())
    }
}

/// Signed area of a ring (m²): positive when counter-clockwise.
pub fn signed_area(ring: &[Point2]) -> Real {
    let n = ring.len();
    if n < 3 {
        return 0.0;
    }
    let o = ring[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += (ring[i] - o).perp(&(ring[i + 1] - o));
    }
    0.5 * twice
}

/// Area centroid of a ring, or `None` when its area is zero.
pub fn centroid(ring: &[Point2]) -> Option<Point2> {
    let (a, m) = ring_moments(ring, 1.0);
    (a.abs() > 0.0).then(|| Point2::from(m / a))
}

/// Returns (|area| · sign, first moment · sign) of a ring, orientation-independent.
fn ring_moments(ring: &[Point2], sign: Real) -> (Real, Vector2) {
    let n = ring.len();
    if n < 3 {
        return (0.0, Vector2::zeros());
    }
    let o = ring[0];
    let mut a = 0.0;
    let mut m = Vector2::zeros();
    for i in 1..n - 1 {
        let (p, q) = (ring[i] - o, ring[i + 1] - o);
        let t = 0.5 * p.perp(&q);
        a += t;
        m += t * (o.coords + (p + q) / 3.0);
    }
    let s = if a < 0.0 { -sign } else { sign };
    (a * s, m * s)
}

/// Even-odd point-in-ring test.
pub fn point_in_ring(p: &Point2, ring: &[Point2]) -> bool {
    let n = ring.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (ring[i], ring[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Distance from `p` to the closest edge of `ring` (m).
pub fn distance_to_ring(p: &Point2, ring: &[Point2]) -> Real {
    let n = ring.len();
    if n == 0 {
        return Real::INFINITY;
    }
    (0..n)
        .map(|i| segment_distance(p, &ring[i], &ring[(i + 1) % n]))
        .fold(Real::INFINITY, Real::min)
}

fn segment_distance(p: &Point2, a: &Point2, b: &Point2) -> Real {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// Signed distance of `p` to the boundary of a ring (m): positive inside, negative outside.
///
/// With the convex hull of a support region, this is the stability margin of the paper's
/// Fig. 7 test: how far the vertical line through the centre of gravity is from leaving the
/// supported area.
pub fn signed_margin(p: &Point2, ring: &[Point2]) -> Real {
    let d = distance_to_ring(p, ring);
    if point_in_ring(p, ring) { d } else { -d }
}

/// The counter-clockwise ring of the axis-aligned rectangle with corners `min` and `max`,
/// starting at `min`.
pub fn rectangle(min: Point2, max: Point2) -> Vec<Point2> {
    vec![
        min,
        Point2::new(max.x, min.y),
        max,
        Point2::new(min.x, max.y),
    ]
}

/// Signed distance of `p` to the boundary of a counter-clockwise convex ring (m): positive
/// inside, negative outside; [`Real::NEG_INFINITY`] for a ring of fewer than three points.
///
/// The convex specialisation of [`signed_margin`]: inside, the distance is the smallest
/// distance to the edges' lines (half-plane test, no parity count); outside, the distance to
/// the nearest edge. The two agree to rounding (the last bits can differ). Edges shorter than
/// 1e-15 m are skipped.
pub fn signed_distance_convex(ring: &[Point2], p: &Point2) -> Real {
    if ring.len() < 3 {
        return Real::NEG_INFINITY;
    }
    let mut inside = Real::INFINITY;
    let mut outside: Real = 0.0;
    let mut is_inside = true;
    for i in 0..ring.len() {
        let a = ring[i];
        let b = ring[(i + 1) % ring.len()];
        let e = b - a;
        let len = e.norm();
        if len < 1e-15 {
            continue;
        }
        let d = e.perp(&(p - a)) / len; // > 0 left of the edge = inside
        inside = inside.min(d);
        if d < 0.0 {
            is_inside = false;
        }
        let t = ((p - a).dot(&e) / (len * len)).clamp(0.0, 1.0);
        let dist = (p - (a + e * t)).norm();
        outside = if outside == 0.0 {
            dist
        } else {
            outside.min(dist)
        };
    }
    if is_inside { inside } else { -outside }
}

/// 2D convex hull (Andrew's monotone chain), counter-clockwise, without collinear points.
///
/// Fewer than three distinct non-collinear points give the distinct points in order (a
/// segment or a point).
pub fn convex_hull(points: &[Point2]) -> Vec<Point2> {
    let mut p: Vec<Point2> = points
        .iter()
        .copied()
        .filter(|q| q.x.is_finite() && q.y.is_finite())
        .collect();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: &Point2, a: &Point2, b: &Point2| (a - o).perp(&(b - o));
    let mut hull: Vec<Point2> = Vec::with_capacity(2 * p.len());
    for q in &p {
        while hull.len() >= 2 && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], q) <= 0.0 {
            hull.pop();
        }
        hull.push(*q);
    }
    let lower = hull.len() + 1;
    for q in p.iter().rev().skip(1) {
        while hull.len() >= lower && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], q) <= 0.0 {
            hull.pop();
        }
        hull.push(*q);
    }
    hull.pop();
    hull
}

/// An oriented rectangle in 2D.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rect2 {
    /// Centre.
    pub center: Point2,
    /// Unit direction of the first side (the second is its left perpendicular).
    pub axis: Vector2,
    /// Half side lengths along `axis` and its perpendicular (m).
    pub half_extents: Vector2,
}

impl Rect2 {
    /// Area (m²).
    pub fn area(&self) -> Real {
        4.0 * self.half_extents.x * self.half_extents.y
    }

    /// Side lengths sorted (shorter, longer) (m): what the paper's `includeBoundingBox`
    /// compares.
    pub fn sorted_sides(&self) -> (Real, Real) {
        let (a, b) = (2.0 * self.half_extents.x, 2.0 * self.half_extents.y);
        if a <= b { (a, b) } else { (b, a) }
    }

    /// The four corners, counter-clockwise.
    pub fn corners(&self) -> [Point2; 4] {
        let u = self.axis * self.half_extents.x;
        let v = Vector2::new(-self.axis.y, self.axis.x) * self.half_extents.y;
        [
            self.center - u - v,
            self.center + u - v,
            self.center + u + v,
            self.center - u + v,
        ]
    }

    /// True when `p` is inside (within `tolerance` m).
    pub fn contains(&self, p: &Point2, tolerance: Real) -> bool {
        let d = p - self.center;
        let v = Vector2::new(-self.axis.y, self.axis.x);
        d.dot(&self.axis).abs() <= self.half_extents.x + tolerance
            && d.dot(&v).abs() <= self.half_extents.y + tolerance
    }
}

/// Minimum-area bounding rectangle of a point set (rotating calipers over its convex hull).
///
/// One side of the optimal rectangle lies on a hull edge; the calipers visit every edge and
/// advance three support pointers monotonically, so the cost is linear in the hull size after
/// the hull is built. Returns `None` for an empty input; a single point or a segment gives a
/// rectangle with zero extents.
pub fn min_area_rect(points: &[Point2]) -> Option<Rect2> {
    let hull = convex_hull(points);
    match hull.len() {
        0 => return None,
        1 => {
            return Some(Rect2 {
                center: hull[0],
                axis: Vector2::x(),
                half_extents: Vector2::zeros(),
            });
        }
        2 => {
            let d = hull[1] - hull[0];
            let len = d.norm();
            return Some(Rect2 {
                center: Point2::from((hull[0].coords + hull[1].coords) * 0.5),
                axis: d / len,
                half_extents: Vector2::new(0.5 * len, 0.0),
            });
        }
        _ => {}
    }
    let n = hull.len();
    let edge = |i: usize| -> Vector2 { (hull[(i + 1) % n] - hull[i]).normalize() };
    let (mut right, mut top, mut left) = (0usize, 0usize, 0usize);
    let mut best: Option<(Real, Rect2)> = None;
    for i in 0..n {
        let u = edge(i);
        let v = Vector2::new(-u.y, u.x);
        let o = hull[i];
        let along = |k: usize| (hull[k % n] - o).dot(&u);
        let up = |k: usize| (hull[k % n] - o).dot(&v);
        if i == 0 {
            right = i;
            top = i;
        }
        right = right.max(i);
        while along(right + 1) >= along(right) && right < i + n {
            right += 1;
        }
        top = top.max(right);
        while up(top + 1) >= up(top) && top < i + n {
            top += 1;
        }
        if i == 0 {
            left = top;
        }
        left = left.max(top);
        while along(left + 1) <= along(left) && left < i + 2 * n {
            left += 1;
        }
        let (a0, a1, h) = (along(left), along(right), up(top));
        let area = (a1 - a0) * h;
        if best.as_ref().is_none_or(|(b, _)| area < *b) {
            let center = o + u * (0.5 * (a0 + a1)) + v * (0.5 * h);
            best = Some((
                area,
                Rect2 {
                    center,
                    axis: u,
                    half_extents: Vector2::new(0.5 * (a1 - a0), 0.5 * h),
                },
            ));
        }
    }
    best.map(|(_, r)| r)
}

fn to_shape(p: &Polygon) -> Vec<Vec<[f64; 2]>> {
    std::iter::once(&p.outer)
        .chain(p.holes.iter())
        .filter(|r| r.len() >= 3)
        .map(|r| r.iter().map(|q| [q.x, q.y]).collect())
        .collect()
}

fn to_shapes(polygons: &[Polygon]) -> Vec<Vec<Vec<[f64; 2]>>> {
    polygons
        .iter()
        .map(to_shape)
        .filter(|s| !s.is_empty())
        .collect()
}

fn from_shapes(shapes: Vec<Vec<Vec<[f64; 2]>>>) -> Vec<Polygon> {
    shapes
        .into_iter()
        .filter_map(|shape| {
            let mut rings = shape
                .into_iter()
                .map(|c| c.into_iter().map(|[x, y]| Point2::new(x, y)).collect());
            let mut outer: Vec<Point2> = rings.next()?;
            if signed_area(&outer) < 0.0 {
                outer.reverse();
            }
            let holes = rings
                .map(|mut h: Vec<Point2>| {
                    if signed_area(&h) > 0.0 {
                        h.reverse();
                    }
                    h
                })
                .collect();
            Some(Polygon { outer, holes })
        })
        .collect()
}

fn overlay(a: &[Polygon], b: &[Polygon], rule: OverlayRule) -> Vec<Polygon> {
    let (sa, sb) = (to_shapes(a), to_shapes(b));
    if sa.is_empty() {
        return Vec::new();
    }
    if sb.is_empty() {
        return match rule {
            OverlayRule::Intersect => Vec::new(),
            _ => from_shapes(sa.overlay(
                &Vec::<Vec<Vec<[f64; 2]>>>::new(),
                OverlayRule::Subject,
                FillRule::EvenOdd,
            )),
        };
    }
    from_shapes(sa.overlay(&sb, rule, FillRule::EvenOdd))
}

/// Intersection of two polygon sets (each polygon may have holes).
pub fn intersection(a: &[Polygon], b: &[Polygon]) -> Vec<Polygon> {
    overlay(a, b, OverlayRule::Intersect)
}

/// The part of `a` outside `b`.
pub fn difference(a: &[Polygon], b: &[Polygon]) -> Vec<Polygon> {
    overlay(a, b, OverlayRule::Difference)
}

/// Union of two polygon sets.
pub fn union(a: &[Polygon], b: &[Polygon]) -> Vec<Polygon> {
    if a.is_empty() {
        return overlay(b, &[], OverlayRule::Union);
    }
    overlay(a, b, OverlayRule::Union)
}

/// Total area of a polygon set (m²).
pub fn total_area(polygons: &[Polygon]) -> Real {
    polygons.iter().map(Polygon::area).sum()
}

/// Area centroid of a polygon set, or `None` when its area is zero.
pub fn total_centroid(polygons: &[Polygon]) -> Option<Point2> {
    let mut a = 0.0;
    let mut m = Vector2::zeros();
    for p in polygons {
        if let Some(c) = p.centroid() {
            let pa = p.area();
            a += pa;
            m += c.coords * pa;
        }
    }
    (a > 0.0).then(|| Point2::from(m / a))
}

/// The supported region of two touching clusters (paper Fig. 7, first two steps): the common
/// area of the two outer boundaries, minus the holes of both.
pub fn support_region(a: &Polygon, b: &Polygon) -> Vec<Polygon> {
    let common = intersection(
        &[Polygon::new(a.outer.clone())],
        &[Polygon::new(b.outer.clone())],
    );
    let holes = |p: &Polygon| -> Vec<Polygon> {
        p.holes
            .iter()
            .filter(|h| h.len() >= 3)
            .map(|h| Polygon::new(h.clone()))
            .collect()
    };
    let (ha, hb) = (holes(a), holes(b));
    if ha.is_empty() && hb.is_empty() {
        common
    } else {
        // The holes' union: overlapping holes of the two polygons, subtracted as one list,
        // would cancel under the even-odd rule.
        difference(&common, &union(&ha, &hb))
    }
}

/// Whether `ring` lies strictly inside `polygon`: every vertex inside it (outside its holes)
/// and no edge of `ring` crossing or touching an edge of `polygon`'s outer ring or holes.
/// Conservative: a touching edge counts as crossing.
fn ring_inside(ring: &[Point2], polygon: &Polygon) -> bool {
    if ring.len() < 3 || polygon.outer.len() < 3 || !ring.iter().all(|p| polygon.contains(p)) {
        return false;
    }
    let rings = std::iter::once(&polygon.outer).chain(polygon.holes.iter());
    for other in rings {
        for (q1, q2) in edges(other) {
            for (p1, p2) in edges(ring) {
                if segments_meet(p1, p2, q1, q2) {
                    return false;
                }
            }
        }
    }
    true
}

/// The edges of a closed ring.
fn edges(r: &[Point2]) -> impl Iterator<Item = (Point2, Point2)> + '_ {
    let n = r.len();
    (0..n).map(move |i| (r[i], r[(i + 1) % n]))
}

/// Whether segments `p1p2` and `q1q2` intersect or touch (collinear overlaps included).
fn segments_meet(p1: Point2, p2: Point2, q1: Point2, q2: Point2) -> bool {
    let (lo, hi) = (p1.coords.inf(&p2.coords), p1.coords.sup(&p2.coords));
    let (qlo, qhi) = (q1.coords.inf(&q2.coords), q1.coords.sup(&q2.coords));
    if hi.x < qlo.x || qhi.x < lo.x || hi.y < qlo.y || qhi.y < lo.y {
        return false;
    }
    let side = |a: Point2, b: Point2, c: Point2| (b - a).perp(&(c - a));
    let (d1, d2) = (side(q1, q2, p1), side(q1, q2, p2));
    let (d3, d4) = (side(p1, p2, q1), side(p1, p2, q2));
    // Opposite sides (or on the line) both ways: the bounding boxes overlap, so they meet.
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}

/// Convex hull of the support region of two clusters (paper Fig. 7, third step). The object
/// is statically stable when the vertical through its centre of gravity passes inside; use
/// [`signed_margin`] for the margin.
///
/// When one outer ring lies inside the other polygon (no edges crossing or touching, every
/// vertex inside it), the hull is that ring's hull: holes strictly inside a ring leave its
/// hull unchanged, so the boolean operations are skipped (the common case of an object's
/// face on a much larger table top, where they were most of Algorithm 2's time).
pub fn support_hull(a: &Polygon, b: &Polygon) -> Vec<Point2> {
    if ring_inside(&a.outer, b) {
        return convex_hull(&a.outer);
    }
    if ring_inside(&b.outer, a) {
        return convex_hull(&b.outer);
    }
    convex_hull(&intersection_corners(a, b))
}

/// Points whose convex hull is the hull of the closed intersection of `a` and `b` (holes
/// included): the intersection's boundary is made of pieces of the two polygons' rings, so its
/// corners are among the vertices of each polygon inside the other and the points where
/// their rings cross or touch (both ends of a collinear overlap), and every such point lies in
/// the intersection. O(n m) segment tests against the boolean operations'
/// sweep ([`support_region`]), which cost ten times more on a scanned object's support
/// straddling an edge (issue 31).
fn intersection_corners(a: &Polygon, b: &Polygon) -> Vec<Point2> {
    let mut points: Vec<Point2> = a.points().filter(|p| b.contains(p)).copied().collect();
    points.extend(b.points().filter(|q| a.contains(q)).copied());
    let rings = |p: &Polygon| -> Vec<(Point2, Point2)> {
        std::iter::once(&p.outer)
            .chain(p.holes.iter())
            .filter(|r| r.len() >= 2)
            .flat_map(|r| edges(r))
            .collect()
    };
    let b_edges = rings(b);
    for (p1, p2) in rings(a) {
        for &(q1, q2) in &b_edges {
            crossing(p1, p2, q1, q2, &mut points);
        }
    }
    points
}

/// Appends where segments `p1p2` and `q1q2` meet: their crossing point, or the ends of one
/// lying on the other when they are collinear.
fn crossing(p1: Point2, p2: Point2, q1: Point2, q2: Point2, out: &mut Vec<Point2>) {
    let (lo, hi) = (p1.coords.inf(&p2.coords), p1.coords.sup(&p2.coords));
    let (qlo, qhi) = (q1.coords.inf(&q2.coords), q1.coords.sup(&q2.coords));
    if hi.x < qlo.x || qhi.x < lo.x || hi.y < qlo.y || qhi.y < lo.y {
        return;
    }
    let (r, s) = (p2 - p1, q2 - q1);
    let denom = r.perp(&s);
    let w = q1 - p1;
    if denom != 0.0 {
        let t = w.perp(&s) / denom;
        let u = w.perp(&r) / denom;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
            out.push(p1 + r * t);
        }
        return;
    }
    if w.perp(&r) != 0.0 {
        return; // parallel, on different lines
    }
    // Collinear: the ends of each inside the other (the boxes overlap, so the segments do).
    let on = |x: Point2, a: Point2, b: Point2| {
        let (l, h) = (a.coords.inf(&b.coords), a.coords.sup(&b.coords));
        (l.x..=h.x).contains(&x.x) && (l.y..=h.y).contains(&x.y)
    };
    for (x, a, b) in [(p1, q1, q2), (p2, q1, q2), (q1, p1, p2), (q2, p1, p2)] {
        if on(x, a, b) {
            out.push(x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: Real, y0: Real, s: Real) -> Vec<Point2> {
        rectangle(Point2::new(x0, y0), Point2::new(x0 + s, y0 + s))
    }

    #[test]
    fn convex_distance_agrees_with_the_general_margin() {
        let ring = square(0.0, 0.0, 2.0);
        for (p, expected) in [
            (Point2::new(1.0, 1.0), 1.0),
            (Point2::new(0.5, 1.0), 0.5),
            (Point2::new(3.0, 1.0), -1.0),
            (Point2::new(3.0, 3.0), -(2.0 as Real).sqrt()),
            (Point2::new(2.0, 1.0), 0.0),
        ] {
            let convex = signed_distance_convex(&ring, &p);
            assert!((convex - expected).abs() < 1e-12, "{p}: {convex}");
            assert!((convex - signed_margin(&p, &ring)).abs() < 1e-12, "{p}");
        }
        assert_eq!(
            signed_distance_convex(&ring[..2], &Point2::origin()),
            Real::NEG_INFINITY
        );
    }

    #[test]
    fn area_centroid_and_containment_of_a_square_with_a_hole() {
        let mut hole = square(0.25, 0.25, 0.5);
        hole.reverse();
        let p = Polygon {
            outer: square(0.0, 0.0, 1.0),
            holes: vec![hole],
        };
        assert!((p.area() - 0.75).abs() < 1e-12);
        let c = p.centroid().expect("non-zero area");
        assert!((c - Point2::new(0.5, 0.5)).norm() < 1e-12);
        assert!(p.contains(&Point2::new(0.1, 0.1)));
        assert!(!p.contains(&Point2::new(0.5, 0.5)));
        assert!(!p.contains(&Point2::new(1.5, 0.5)));
    }

    #[test]
    fn hull_drops_interior_and_collinear_points() {
        let mut pts = square(0.0, 0.0, 2.0);
        pts.push(Point2::new(1.0, 1.0));
        pts.push(Point2::new(1.0, 0.0));
        let h = convex_hull(&pts);
        assert_eq!(h.len(), 4);
        assert!((signed_area(&h) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn min_rect_of_a_rotated_rectangle_is_tight() {
        let a: Real = 0.3;
        let (u, v) = (
            Vector2::new(a.cos(), a.sin()),
            Vector2::new(-a.sin(), a.cos()),
        );
        let pts: Vec<Point2> = [
            (-2.0, -1.0),
            (2.0, -1.0),
            (2.0, 1.0),
            (-2.0, 1.0),
            (0.5, 0.2),
        ]
        .iter()
        .map(|&(x, y)| Point2::from(u * x + v * y) + Vector2::new(3.0, 4.0))
        .collect();
        let r = min_area_rect(&pts).expect("non-empty");
        assert!((r.area() - 8.0).abs() < 1e-9, "{r:?}");
        assert!((r.center - Point2::new(3.0, 4.0)).norm() < 1e-9);
        for p in &pts {
            assert!(r.contains(p, 1e-9));
        }
    }

    #[test]
    fn booleans_of_overlapping_squares() {
        let a = [Polygon::new(square(0.0, 0.0, 2.0))];
        let b = [Polygon::new(square(1.0, 1.0, 2.0))];
        assert!((total_area(&intersection(&a, &b)) - 1.0).abs() < 1e-6);
        assert!((total_area(&difference(&a, &b)) - 3.0).abs() < 1e-6);
        assert!((total_area(&union(&a, &b)) - 7.0).abs() < 1e-6);
        let c = total_centroid(&intersection(&a, &b)).expect("overlap");
        assert!((c - Point2::new(1.5, 1.5)).norm() < 1e-6);
    }

    #[test]
    fn support_hull_excludes_holes_but_hull_fills_them() {
        // Fig. 7: a plate with a hole in the middle resting on a larger plate.
        let mut hole = square(0.4, 0.4, 0.2);
        hole.reverse();
        let object = Polygon {
            outer: square(0.0, 0.0, 1.0),
            holes: vec![hole],
        };
        let env = Polygon::new(square(-1.0, -1.0, 3.0));
        let region = support_region(&object, &env);
        assert!((total_area(&region) - 0.96).abs() < 1e-6);
        let hull = support_hull(&object, &env);
        assert!((signed_area(&hull) - 1.0).abs() < 1e-6);
        assert!((signed_margin(&Point2::new(0.5, 0.5), &hull) - 0.5).abs() < 1e-6);
        assert!(signed_margin(&Point2::new(1.5, 0.5), &hull) < 0.0);
    }

    /// The hull through the boolean operations, as before the containment shortcut.
    fn hull_by_booleans(a: &Polygon, b: &Polygon) -> Vec<Point2> {
        let region = support_region(a, b);
        let points: Vec<Point2> = region.iter().flat_map(|p| p.points().copied()).collect();
        convex_hull(&points)
    }

    #[test]
    fn the_containment_shortcut_gives_the_hull_of_the_booleans() {
        let mut env_hole = square(0.2, 0.2, 0.1);
        env_hole.reverse();
        let env = Polygon {
            outer: square(-1.0, -1.0, 3.0),
            holes: vec![env_hole],
        };
        let cases = [
            // Inside, around the environment's hole, inside the object, straddling the edge,
            // touching the edge, larger than the environment.
            square(0.5, 0.5, 0.4),
            square(0.0, 0.0, 1.0),
            square(0.21, 0.21, 0.05),
            square(1.5, 1.5, 1.0),
            square(1.0, 1.0, 1.0),
            square(-2.0, -2.0, 5.0),
        ];
        for (k, outer) in cases.into_iter().enumerate() {
            let object = Polygon::new(outer);
            let fast = support_hull(&object, &env);
            let slow = hull_by_booleans(&object, &env);
            assert_eq!(fast.len(), slow.len(), "case {k}: {fast:?} / {slow:?}");
            assert!(
                (signed_area(&fast) - signed_area(&slow)).abs() < 1e-6,
                "case {k}"
            );
            for p in &slow {
                assert!(distance_to_ring(p, &fast) < 1e-6, "case {k}: {p}");
            }
        }
        assert!(ring_inside(&square(0.5, 0.5, 0.4), &env));
        assert!(!ring_inside(&square(1.5, 1.5, 1.0), &env));
        assert!(
            !ring_inside(&square(1.0, 1.0, 1.0), &env),
            "touching counts as crossing"
        );
        assert!(
            !ring_inside(&square(0.21, 0.21, 0.05), &env),
            "inside the hole"
        );
    }

    proptest::proptest! {
        /// The hull through the polygons' corners and crossings is the hull of the boolean
        /// intersection, for a rotated polygon (a support with a hole) straddling a
        /// non-convex region with a hole (an L-shaped table top with a cut-out).
        #[test]
        fn the_corner_hull_is_the_hull_of_the_booleans(
            x in -0.6..1.6f64, y in -0.6..1.6f64, yaw in 0.0..6.3f64, size in 0.05..0.9f64,
            sides in 3usize..12,
        ) {
            let ring: Vec<Point2> = (0..sides)
                .map(|k| {
                    let a = yaw + std::f64::consts::TAU * k as Real / sides as Real;
                    Point2::new(x + size * a.cos(), y + size * (0.7 * a).sin().abs().max(0.3) * a.sin())
                })
                .collect();
            let ring = convex_hull(&ring);
            let mut hole: Vec<Point2> =
                ring.iter().map(|p| Point2::new(x, y) + (p - Point2::new(x, y)) * 0.3).collect();
            hole.reverse();
            let object = Polygon { outer: ring, holes: vec![hole] };
            let mut env_hole = square(0.2, 0.2, 0.15);
            env_hole.reverse();
            let env = Polygon {
                outer: vec![
                    Point2::new(0.0, 0.0),
                    Point2::new(1.0, 0.0),
                    Point2::new(1.0, 0.5),
                    Point2::new(0.5, 0.5),
                    Point2::new(0.5, 1.0),
                    Point2::new(0.0, 1.0),
                ],
                holes: vec![env_hole],
            };
            let fast = support_hull(&object, &env);
            let slow = hull_by_booleans(&object, &env);
            // The booleans snap to a grid of about 1e-9 (i_overlay's integer coordinates).
            proptest::prop_assert!((signed_area(&fast) - signed_area(&slow)).abs() < 1e-7);
            for p in &slow {
                proptest::prop_assert!(distance_to_ring(p, &fast) < 1e-7, "{p}");
            }
            for p in &fast {
                proptest::prop_assert!(distance_to_ring(p, &slow) < 1e-7, "{p}");
            }
        }
    }
}
