//! Grasp quality (after the paper's ref. \[15\]): contact area of the pads, torque arm of the
//! centre of gravity, margin to the cluster boundary, and the score combining them.

use pickplace_geometry::math::{Point2, Real};
use pickplace_geometry::polygon::{self, Polygon};

/// The measured quality of one grasp.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspQuality {
    /// Area of the object's surface both pads touch (m²), the smaller of the two: under each
    /// pad, the part of the mesh within the flexible sheet's depth `h_max` of the highest
    /// point the rigid pad rests on (§III-A, Fig. 2), projected onto the pad. A flat face
    /// under the whole pad gives the pad's area; a curved body, the cap the sheet wraps.
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
    /// How far the pads are drawn back along the approach from the grasp centre (m): 0, or on
    /// a region shorter than the pad is deep (a thin or small object), enough for the finger
    /// tips to stop the clearance short of the region's far edge (a table under a flat
    /// object). The TCP, the pads' centre, then lies off the region.
    #[serde(default)]
    pub tip_shift: Real,
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
            tip_shift: 0.0,
        };
        let worst = GraspQuality {
            contact_area: 0.0,
            torque_arm: 3.0,
            boundary_margin: -1.0,
            pad_depth: 0.0,
            tip_shift: 0.0,
        };
        assert!((m.score(&best) - 1.0).abs() < 1e-12);
        assert_eq!(m.score(&worst), 0.0);
        let mid = GraspQuality {
            contact_area: 0.5,
            torque_arm: 0.5,
            boundary_margin: 0.5,
            pad_depth: 0.0,
            tip_shift: 0.0,
        };
        assert!((m.score(&mid) - 0.5).abs() < 1e-12);
    }
}
