//! Grasp quality (after the paper's ref. \[15\]): contact area of the pads, torque arm of the
//! centre of gravity, margin to the cluster boundary, and the score combining them.

use pickplace_geometry::math::{Point2, Real, Vector2};
use pickplace_geometry::polygon::{self, Polygon};

/// The measured quality of one grasp.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspQuality {
    /// Area of the pad lying on both clusters (m²): the pad rectangle intersected with the
    /// pair's overlap region (first cluster ∩ second cluster projected onto it).
    pub contact_area: Real,
    /// Distance from the object's centre of gravity to the grasp axis, the line through the
    /// TCP along the closing direction (m). Gravity's torque about the axis grows with it.
    pub torque_arm: Real,
    /// Signed distance from the pad centre to the boundary of the overlap region (m),
    /// positive inside.
    pub boundary_margin: Real,
    /// How far the contact patch under either pad rises towards that pad above the point
    /// where the grasp line through the TCP crosses it (m): the pad touches the highest point
    /// under it, and the flexible sheet (§III-A, Fig. 2) must reach down this far to the rest
    /// of a curved or concave patch; at most `h_max`, 0 on flat faces.
    #[serde(default)]
    pub pad_depth: Real,
}

/// Weights and scales of the score.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ScoreModel {
    pub pad_area: Real,
    pub torque_scale: Real,
    pub margin_scale: Real,
    pub weights: [Real; 3],
}

impl ScoreModel {
    /// `score = (w_c·c + w_t·t + w_m·m) / (w_c + w_t + w_m)` with
    /// `c = contact_area / pad_area`, `t = 1 − min(torque_arm / torque_scale, 1)` and
    /// `m = clamp(boundary_margin / margin_scale, 0, 1)`; each term and the score lie in [0, 1].
    pub fn score(&self, q: &GraspQuality) -> Real {
        let c = (q.contact_area / self.pad_area).clamp(0.0, 1.0);
        let t = 1.0 - (q.torque_arm / self.torque_scale).min(1.0);
        let m = (q.boundary_margin / self.margin_scale).clamp(0.0, 1.0);
        let [wc, wt, wm] = self.weights;
        (wc * c + wt * t + wm * m) / (wc + wt + wm)
    }
}

/// The corners of a rectangle (counter-clockwise when `u × v > 0`, else reordered so).
pub(crate) fn rectangle(
    center: Point2,
    u: Vector2,
    v: Vector2,
    half_u: Real,
    half_v: Real,
) -> [Point2; 4] {
    let (a, b) = (u * half_u, v * half_v);
    let r = [
        center - a - b,
        center + a - b,
        center + a + b,
        center - a + b,
    ];
    if u.perp(&v) >= 0.0 {
        r
    } else {
        [r[3], r[2], r[1], r[0]]
    }
}

/// Area of a convex counter-clockwise `window` intersected with a set of polygons with holes
/// (m²). Every ring is clipped by the window (Sutherland–Hodgman); the clipped outer rings
/// count positively and the clipped holes negatively, which is exact for a convex window.
pub(crate) fn clipped_area(window: &[Point2; 4], polygons: &[Polygon]) -> Real {
    let mut buffers = (Vec::with_capacity(32), Vec::with_capacity(32));
    let mut total = 0.0;
    for p in polygons {
        total += polygon::signed_area(clip_ring(&p.outer, window, &mut buffers)).abs();
        for h in &p.holes {
            total -= polygon::signed_area(clip_ring(h, window, &mut buffers)).abs();
        }
    }
    total.max(0.0)
}

fn clip_ring<'a>(
    ring: &[Point2],
    window: &[Point2; 4],
    (a, b): &'a mut (Vec<Point2>, Vec<Point2>),
) -> &'a [Point2] {
    a.clear();
    a.extend_from_slice(ring);
    for k in 0..4 {
        let (p, q) = (window[k], window[(k + 1) % 4]);
        let e = q - p;
        let side = |x: &Point2| e.perp(&(x - p));
        b.clear();
        let n = a.len();
        for i in 0..n {
            let (cur, next) = (a[i], a[(i + 1) % n]);
            let (sc, sn) = (side(&cur), side(&next));
            if sc >= 0.0 {
                b.push(cur);
            }
            if (sc >= 0.0) != (sn >= 0.0) {
                let t = sc / (sc - sn);
                b.push(cur + (next - cur) * t);
            }
        }
        std::mem::swap(a, b);
        if a.is_empty() {
            break;
        }
    }
    a
}

/// Signed distance from `p` to the boundary of a polygon set (m): positive inside.
pub(crate) fn boundary_margin(p: &Point2, polygons: &[Polygon]) -> Real {
    let distance = polygons
        .iter()
        .flat_map(|poly| std::iter::once(&poly.outer).chain(poly.holes.iter()))
        .map(|ring| polygon::distance_to_ring(p, ring))
        .fold(Real::INFINITY, Real::min);
    if polygons.iter().any(|poly| poly.contains(p)) {
        distance
    } else {
        -distance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: Real, y0: Real, s: Real) -> Vec<Point2> {
        pickplace_geometry::polygon::rectangle(Point2::new(x0, y0), Point2::new(x0 + s, y0 + s))
    }

    #[test]
    fn clipped_area_matches_the_polygon_boolean() {
        let mut hole = square(0.4, 0.4, 0.2);
        hole.reverse();
        // A non-convex L with a hole.
        let l = Polygon {
            outer: vec![
                Point2::new(0.0, 0.0),
                Point2::new(1.0, 0.0),
                Point2::new(1.0, 1.0),
                Point2::new(0.7, 1.0),
                Point2::new(0.7, 0.3),
                Point2::new(0.0, 0.3),
            ],
            holes: vec![],
        };
        let ring = Polygon {
            outer: square(0.0, 0.0, 1.0),
            holes: vec![hole],
        };
        let a = 0.35_f64;
        let (u, v) = (
            Vector2::new(a.cos(), a.sin()),
            Vector2::new(-a.sin(), a.cos()),
        );
        for shape in [l, ring] {
            for (c, hu, hv) in [
                (Point2::new(0.5, 0.5), 0.3, 0.2),
                (Point2::new(0.9, 0.2), 0.25, 0.4),
                (Point2::new(3.0, 3.0), 0.1, 0.1),
            ] {
                for (du, dv) in [(u, v), (v, u)] {
                    let w = rectangle(c, du, dv, hu, hv);
                    let expected = polygon::total_area(&polygon::intersection(
                        &[Polygon::new(w.to_vec())],
                        std::slice::from_ref(&shape),
                    ));
                    let got = clipped_area(&w, std::slice::from_ref(&shape));
                    assert!((got - expected).abs() < 1e-9, "{got} vs {expected}");
                }
            }
        }
    }

    #[test]
    fn margin_is_signed_and_sees_holes() {
        let mut hole = square(0.4, 0.4, 0.2);
        hole.reverse();
        let p = [Polygon {
            outer: square(0.0, 0.0, 1.0),
            holes: vec![hole],
        }];
        assert!((boundary_margin(&Point2::new(0.2, 0.5), &p) - 0.2).abs() < 1e-12);
        assert!((boundary_margin(&Point2::new(0.5, 0.5), &p) + 0.1).abs() < 1e-12);
        assert!((boundary_margin(&Point2::new(1.5, 0.5), &p) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn score_terms_are_normalised() {
        let m = ScoreModel {
            pad_area: 1.0,
            torque_scale: 1.0,
            margin_scale: 1.0,
            weights: [0.5, 0.3, 0.2],
        };
        let best = GraspQuality {
            contact_area: 1.0,
            torque_arm: 0.0,
            boundary_margin: 5.0,
            pad_depth: 0.0,
        };
        let worst = GraspQuality {
            contact_area: 0.0,
            torque_arm: 3.0,
            boundary_margin: -1.0,
            pad_depth: 0.0,
        };
        assert!((m.score(&best) - 1.0).abs() < 1e-12);
        assert_eq!(m.score(&worst), 0.0);
        let mid = GraspQuality {
            contact_area: 0.5,
            torque_arm: 0.5,
            boundary_margin: 0.5,
            pad_depth: 0.0,
        };
        assert!((m.score(&mid) - 0.5).abs() < 1e-12);
    }
}
