//! Mass properties of a mesh: volume, centre of gravity, inertia tensor.
//!
//! The stability test of Harada et al. (§III-B.3, Fig. 7) needs the object's centre of gravity.
//! For a closed, consistently wound mesh the volume integrals are turned into surface sums by the
//! divergence theorem: every triangle `(a, b, c)` spans with a reference point `o` a signed
//! tetrahedron of volume `a·(b×c)/6` (corners relative to `o`), whose first moment is
//! `V (a+b+c)/4` and whose second moment `∫ x xᵀ dV` is `V/20 (s sᵀ + a aᵀ + b bᵀ + c cᵀ)` with
//! `s = a+b+c`. The signed sums over all triangles are the integrals over the enclosed solid.

use super::TriMesh;
use crate::math::{Matrix3, Point3, Real, Vector3};

/// How [`MassProperties`] were computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum MassMethod {
    /// Volume integrals over the enclosed solid, uniform density (closed, consistently wound
    /// mesh with a non-negligible volume).
    Volume,
    /// Area-weighted centroid of the surface: the fallback for open meshes, inconsistently
    /// wound ones, and closed meshes enclosing (almost) no volume. No inertia is given.
    SurfaceCentroid,
}

/// Volume, centre of gravity and inertia of a mesh, for uniform density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// How the values were computed.
    pub method: MassMethod,
    /// Enclosed volume (m³), positive; 0 for [`MassMethod::SurfaceCentroid`].
    pub volume: Real,
    /// Surface area (m²).
    pub area: Real,
    /// Centre of gravity (m) in the mesh frame: of the solid for [`MassMethod::Volume`], of the
    /// surface for [`MassMethod::SurfaceCentroid`].
    pub center_of_mass: Point3,
    /// Inertia tensor about the centre of gravity, axes of the mesh frame, per unit density
    /// (m⁵; multiply by the density in kg/m³ for kg·m²). `None` for
    /// [`MassMethod::SurfaceCentroid`].
    pub inertia_per_unit_density: Option<Matrix3>,
    /// True when the triangles are wound clockwise seen from outside (the signed volume was
    /// negative). The values above are then those of the solid the surface encloses, as if the
    /// winding were fixed.
    pub inverted_winding: bool,
}

impl MassProperties {
    /// Computes the mass properties of `mesh`; see [`MassMethod`] for when the surface
    /// fallback applies.
    ///
    /// # Performance
    /// Linear in the number of triangles, plus a sort of the directed edges.
    pub fn of(mesh: &TriMesh) -> Self {
        let area = mesh.area();
        let (lo, hi) = mesh.aabb();
        // Sums relative to the bounding-box centre keep the cancellation small for meshes far
        // from the origin.
        let origin = nalgebra::center(&lo, &hi);
        let diagonal = (hi - lo).norm();
        if mesh.report().is_closed() && consistently_wound(mesh.triangles()) {
            let (volume, first, second) = volume_integrals(mesh, &origin);
            // A closed surface around (almost) nothing, such as a two-sided sheet.
            if volume.abs() > 1e-9 * diagonal.powi(3) {
                let sign = volume.signum();
                let (volume, first, second) = (volume * sign, first * sign, second * sign);
                let offset = first / volume;
                let central = second - volume * offset * offset.transpose();
                let inertia = Matrix3::identity() * central.trace() - central;
                return Self {
                    method: MassMethod::Volume,
                    volume,
                    area,
                    center_of_mass: origin + offset,
                    inertia_per_unit_density: Some(inertia),
                    inverted_winding: sign < 0.0,
                };
            }
        }
        let mut weighted = Vector3::zeros();
        for t in 0..mesh.triangle_count() {
            let [a, b, c] = mesh.triangle_points(t);
            let centroid = ((a - origin) + (b - origin) + (c - origin)) / 3.0;
            weighted += mesh.triangle_area(t) * centroid;
        }
        Self {
            method: MassMethod::SurfaceCentroid,
            volume: 0.0,
            area,
            // Kept triangles have positive area, so `area > 0`.
            center_of_mass: origin + weighted / area,
            inertia_per_unit_density: None,
            inverted_winding: false,
        }
    }
}

impl TriMesh {
    /// The mesh's [`MassProperties`].
    pub fn mass_properties(&self) -> MassProperties {
        MassProperties::of(self)
    }
}

/// True when every directed edge is used once: neighbours traverse their shared edge in
/// opposite directions, so the outside is on one side everywhere.
fn consistently_wound(triangles: &[[u32; 3]]) -> bool {
    let mut directed: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    directed.sort_unstable();
    directed.windows(2).all(|w| w[0] != w[1])
}

/// Signed volume, first moment `∫ x dV` and second moment `∫ x xᵀ dV`, relative to `origin`.
fn volume_integrals(mesh: &TriMesh, origin: &Point3) -> (Real, Vector3, Matrix3) {
    let mut volume = 0.0;
    let mut first = Vector3::zeros();
    let mut second = Matrix3::zeros();
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.triangle_points(t).map(|p| p - origin);
        let v = a.dot(&b.cross(&c)) / 6.0;
        let s = a + b + c;
        volume += v;
        first += v * s / 4.0;
        second += (v / 20.0)
            * (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
    }
    (volume, first, second)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::MeshOptions;
    use crate::shapes;

    #[test]
    fn unit_cube_offset_from_origin() {
        let mut b = shapes::box_builder([0.5, 1.0, 1.5]);
        for p in &mut b.positions {
            p.x += 10.0;
        }
        let m = b.build().expect("valid").mass_properties();
        assert_eq!(m.method, MassMethod::Volume);
        assert!(!m.inverted_winding);
        assert!((m.volume - 6.0).abs() < 1e-9, "{}", m.volume);
        assert!((m.center_of_mass - Point3::new(10.0, 0.0, 0.0)).norm() < 1e-9);
        let i = m.inertia_per_unit_density.expect("closed");
        // Box of sides 1 x 2 x 3, mass 6: Ixx = m (b² + c²) / 12.
        let expected = Matrix3::from_diagonal(&Vector3::new(
            6.0 * (4.0 + 9.0) / 12.0,
            6.0 * (1.0 + 9.0) / 12.0,
            6.0 * (1.0 + 4.0) / 12.0,
        ));
        assert!((i - expected).norm() < 1e-9, "{i}");
    }

    #[test]
    fn inverted_winding_gives_the_same_solid() {
        let mut b = shapes::box_builder([0.5, 0.5, 0.5]);
        for t in &mut b.triangles {
            t.swap(1, 2);
        }
        let m = b.build().expect("valid").mass_properties();
        assert_eq!(m.method, MassMethod::Volume);
        assert!(m.inverted_winding);
        assert!((m.volume - 1.0).abs() < 1e-12);
    }

    #[test]
    fn open_or_inconsistent_meshes_fall_back_to_the_surface() {
        let mut b = shapes::box_builder([0.5, 0.5, 0.5]);
        b.triangles.truncate(10); // drop the +x face
        let m = b.build().expect("valid").mass_properties();
        assert_eq!(m.method, MassMethod::SurfaceCentroid);
        assert!(m.inertia_per_unit_density.is_none());
        // Five unit faces: the -x face pulls the centroid to x = -0.5 / 5.
        assert!((m.center_of_mass - Point3::new(-0.1, 0.0, 0.0)).norm() < 1e-12);

        let mut b = shapes::box_builder([0.5, 0.5, 0.5]);
        b.triangles[0].swap(1, 2);
        b.triangles[1].swap(1, 2);
        let mesh =
            TriMesh::from_soup(&b.positions, &b.triangles, &MeshOptions::default()).expect("valid");
        assert!(mesh.report().is_closed());
        assert_eq!(mesh.mass_properties().method, MassMethod::SurfaceCentroid);
    }
}
