//! Oriented boxes and their separating-axis tests: box against box (the two hands at a
//! handover) and box against triangle (a gripper box against an object's surface).

use crate::math::{Matrix3, Point3, Real, Vector3};

/// A solid box: its centre, its axes (the columns of `axes`, orthonormal) and its half extents
/// along them, all in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    /// The centre.
    pub center: Point3,
    /// Columns: the box axes.
    pub axes: Matrix3,
    /// Half extents along the axes.
    pub half: Vector3,
}

impl Obb {
    /// Half extents of the axis-aligned box that bounds this one.
    #[inline]
    pub fn reach(&self) -> Vector3 {
        Vector3::from_fn(|i, _| {
            (0..3)
                .map(|k| self.axes[(i, k)].abs() * self.half[k])
                .sum::<Real>()
        })
    }

    /// Whether two solid boxes overlap (touching counts): the separating-axis test over the
    /// 15 candidate axes (each box's 3 axes and the 9 cross products).
    #[inline]
    pub fn intersects(&self, other: &Obb) -> bool {
        let d = other.center - self.center;
        let mut axes: Vec<Vector3> = Vec::with_capacity(15);
        for i in 0..3 {
            axes.push(self.axes.column(i).into_owned());
            axes.push(other.axes.column(i).into_owned());
        }
        for i in 0..3 {
            for j in 0..3 {
                let c = self.axes.column(i).cross(&other.axes.column(j));
                if c.norm_squared() > 1e-12 {
                    axes.push(c.normalize());
                }
            }
        }
        let radius = |b: &Obb, axis: &Vector3| -> Real {
            (0..3)
                .map(|i| b.half[i] * b.axes.column(i).dot(axis).abs())
                .sum()
        };
        axes.iter()
            .all(|axis| d.dot(axis).abs() <= radius(self, axis) + radius(other, axis))
    }

    /// Whether the solid box and the triangle overlap (touching counts): the separating-axis
    /// test over the three box axes, the triangle's normal and the nine cross products of box
    /// axes and triangle edges.
    #[inline]
    pub fn touches_triangle(&self, tri: [Point3; 3]) -> bool {
        // Triangle in the box frame.
        let to_box = self.axes.transpose();
        let v = tri.map(|p| to_box * (p - self.center));
        let h = self.half;
        for k in 0..3 {
            let (lo, hi) = (
                v[0][k].min(v[1][k]).min(v[2][k]),
                v[0][k].max(v[1][k]).max(v[2][k]),
            );
            if lo > h[k] || hi < -h[k] {
                return false;
            }
        }
        let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
        let separated = |axis: Vector3| {
            let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
            let p = [axis.dot(&v[0]), axis.dot(&v[1]), axis.dot(&v[2])];
            p[0].min(p[1]).min(p[2]) > r || p[0].max(p[1]).max(p[2]) < -r
        };
        if separated(e[0].cross(&e[1])) {
            return false;
        }
        for edge in &e {
            for unit in [Vector3::x(), Vector3::y(), Vector3::z()] {
                if separated(unit.cross(edge)) {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::UnitQuaternion;

    fn unit(x: Real) -> Obb {
        Obb {
            center: Point3::new(x, 0.0, 0.0),
            axes: Matrix3::identity(),
            half: Vector3::new(0.5, 0.5, 0.5),
        }
    }

    #[test]
    fn boxes_separate_along_a_face_axis_and_touch_when_they_overlap() {
        assert!(unit(0.0).intersects(&unit(0.9)));
        assert!(unit(0.0).intersects(&unit(1.0)));
        assert!(!unit(0.0).intersects(&unit(1.1)));
        // Rotated 45° about z, the corner reaches 0.707 along x.
        let rotated = Obb {
            axes: *UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_4)
                .to_rotation_matrix()
                .matrix(),
            ..unit(1.15)
        };
        assert!(unit(0.0).intersects(&rotated));
        assert!(rotated.intersects(&unit(0.0)));
        let farther = Obb {
            center: Point3::new(1.25, 0.0, 0.0),
            ..rotated
        };
        assert!(!unit(0.0).intersects(&farther));
        assert!((rotated.reach().x - 0.5 * 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_triangle_crossing_a_face_touches_and_one_beside_it_does_not() {
        let b = unit(0.0);
        let tri = |x: Real| {
            [
                Point3::new(x, -1.0, -1.0),
                Point3::new(x, 1.0, -1.0),
                Point3::new(x, 0.0, 1.0),
            ]
        };
        assert!(b.touches_triangle(tri(0.4)));
        assert!(b.touches_triangle(tri(0.5)));
        assert!(!b.touches_triangle(tri(0.6)));
        // Across the box's vertical edge, overlapping it along every box axis: only the
        // triangle's normal separates it (x + y = 1.05 misses the corner at x + y = 1).
        let diagonal = |s: Real| {
            [
                Point3::new(s, 0.0, -1.0),
                Point3::new(0.0, s, -1.0),
                Point3::new(s / 2.0, s / 2.0, 1.0),
            ]
        };
        assert!(!b.touches_triangle(diagonal(1.05)));
        assert!(b.touches_triangle(diagonal(0.95)));
    }
}
