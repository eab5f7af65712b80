//! Clustering on meshes with thousands of triangles (issue 17): normals that agree with their
//! triangles, no mergeable adjacent pair left, independence of the triangle order.

use crate::support::{Rng, ellipsoid, height_field, noisy_cylinder};
use pickplace_geometry::cluster::{
    ClusterParams, Clustering, ContactMode, MAX_FIT_DEVIATION, cluster_surface, fit_plane,
};
use pickplace_geometry::math::{Real, Vector3};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use pickplace_objects as objects;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::collections::BTreeSet;

/// Angle between two unit vectors (rad).
fn angle(a: &Vector3, b: &Vector3) -> Real {
    2.0 * (0.5 * (a - b).norm()).min(1.0).asin()
}

/// The area-weighted normal of a set of triangles, from the mesh directly.
fn area_weighted_normal(mesh: &TriMesh, triangles: &[u32]) -> Vector3 {
    let sum: Vector3 = triangles
        .iter()
        .map(|&t| mesh.triangle_scaled_normal(t as usize))
        .sum();
    sum.normalize()
}

/// The largest angle between a cluster's normal and the area-weighted normal of its triangles.
fn worst_normal_deviation(mesh: &TriMesh, c: &Clustering) -> Real {
    c.clusters
        .iter()
        .map(|cl| angle(&cl.normal, &area_weighted_normal(mesh, &cl.triangles)))
        .fold(0.0, Real::max)
}

/// The adjacent cluster pairs whose union would still be a valid cluster: thickness along the
/// union's plane normal at most `h_max` (with a margin against rounding), every triangle within
/// `max_facet_angle` of it. Thickness and angles are measured here from the mesh.
fn mergeable_pairs(mesh: &TriMesh, c: &Clustering) -> Vec<(u32, u32)> {
    let owner = c.cluster_of_triangles(mesh.triangle_count());
    let mut adjacent = BTreeSet::new();
    for t in 0..mesh.triangle_count() {
        for &nb in mesh.adjacency().neighbours(t) {
            if let (Some(a), Some(b)) = (owner[t], owner[nb as usize])
                && a < b
            {
                adjacent.insert((a, b));
            }
        }
    }
    let p = &c.params;
    adjacent
        .into_iter()
        .filter(|&(a, b)| {
            let tris: Vec<u32> = c.clusters[a as usize]
                .triangles
                .iter()
                .chain(&c.clusters[b as usize].triangles)
                .copied()
                .collect();
            let (n, _) = fit_plane(mesh, &tris).expect("triangles of the mesh");
            let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
            let mut facet: Real = 0.0;
            for &t in &tris {
                for q in mesh.triangle_points(t as usize) {
                    lo = lo.min(n.dot(&q.coords));
                    hi = hi.max(n.dot(&q.coords));
                }
                facet = facet.max(angle(&mesh.triangle_normal(t as usize), &n));
            }
            hi - lo < p.h_max - 1e-9 && facet < p.max_facet_angle - 1e-6
        })
        .collect()
}

/// The test meshes: noisy and tessellated cylinders and spheres, a scanned-looking blob, a
/// wavy height field, with thousands of triangles each.
fn meshes(seed: u64) -> Vec<(String, TriMesh)> {
    let mut rng = Rng::new(seed);
    vec![
        (
            "cylinder".into(),
            noisy_cylinder(0.033, 0.12, 96, 12, 0.0, &mut rng),
        ),
        (
            "noisy cylinder".into(),
            noisy_cylinder(0.04, 0.1, 80, 16, 0.0004, &mut rng),
        ),
        (
            "sphere".into(),
            ellipsoid([0.035; 3], 40, 60, 0.0, &mut rng),
        ),
        (
            "noisy ellipsoid".into(),
            ellipsoid([0.03, 0.025, 0.045], 50, 50, 0.0005, &mut rng),
        ),
        (
            "scan".into(),
            ellipsoid([0.05, 0.04, 0.03], 36, 48, 0.002, &mut rng),
        ),
        ("height field".into(), height_field(40, 0.2, 0.01, &mut rng)),
    ]
}

/// Checks one mesh in both modes; returns a description of the first violation.
fn check_real(name: &str, mesh: &TriMesh) -> Result<(), String> {
    for params in [ClusterParams::environment(), ClusterParams::finger()] {
        let c = cluster_surface(mesh, &params).expect("valid");
        let worst = worst_normal_deviation(mesh, &c);
        if worst > MAX_FIT_DEVIATION + 1e-9 {
            return Err(format!(
                "{name} ({}): a normal is {:.1}° from its triangles",
                params.mode.name(),
                worst.to_degrees()
            ));
        }
        let left = mergeable_pairs(mesh, &c);
        if !left.is_empty() {
            return Err(format!(
                "{name} ({}, {} triangles): {} clusters, mergeable pairs left: {left:?}",
                params.mode.name(),
                mesh.triangle_count(),
                c.clusters.len()
            ));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 4,
        rng_seed: RngSeed::Fixed(0x17_17),
        ..ProptestConfig::default()
    })]

    /// On meshes with thousands of triangles, every cluster's normal is within
    /// `MAX_FIT_DEVIATION` (20°) of the area-weighted normal of its triangles, and no adjacent
    /// pair of clusters could still be merged.
    #[test]
    fn normals_agree_with_their_triangles_and_no_adjacent_pair_can_be_merged(seed in any::<u64>()) {
        for (name, mesh) in meshes(seed) {
            prop_assert_eq!(check_real(&name, &mesh), Ok(()));
        }
    }
}

/// The shipped meshes, in both modes.
#[test]
fn shipped_meshes_leave_no_mergeable_pair() {
    for mesh in objects::shipped_meshes() {
        let m = mesh.builder.build().expect("valid");
        for params in [ClusterParams::environment(), ClusterParams::finger()] {
            let c = cluster_surface(&m, &params).expect("valid");
            assert!(worst_normal_deviation(&m, &c) <= MAX_FIT_DEVIATION + 1e-9);
            assert_eq!(mergeable_pairs(&m, &c), Vec::new(), "{}", mesh.file_name);
        }
    }
}

/// The same mesh with its triangles permuted and each triangle's vertices rotated.
fn shuffled(mesh: &TriMesh, seed: u64) -> TriMesh {
    let mut rng = Rng::new(seed);
    let mut tris: Vec<[u32; 3]> = mesh.triangles().to_vec();
    for i in (1..tris.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        tris.swap(i, j);
    }
    for t in &mut tris {
        t.rotate_left((rng.next_u64() % 3) as usize);
    }
    TriMesh::from_soup(mesh.vertices(), &tris, &MeshOptions::default()).expect("valid")
}

/// A clustering as sets of triangles (by their vertex positions), normals and pairs' widths.
fn signature(mesh: &TriMesh, c: &Clustering) -> Vec<(Vec<[i64; 9]>, [i64; 3])> {
    let q = |x: Real| (x * 1e9).round() as i64;
    let mut out: Vec<(Vec<[i64; 9]>, [i64; 3])> = c
        .clusters
        .iter()
        .map(|cl| {
            let mut tris: Vec<[i64; 9]> = cl
                .triangles
                .iter()
                .map(|&t| {
                    let mut p = mesh
                        .triangle_points(t as usize)
                        .map(|p| [q(p.x), q(p.y), q(p.z)]);
                    p.sort_unstable();
                    [
                        p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2], p[2][0], p[2][1],
                        p[2][2],
                    ]
                })
                .collect();
            tris.sort_unstable();
            let n = cl.normal.map(|x| (x * 1e6).round() as i64);
            (tris, [n.x, n.y, n.z])
        })
        .collect();
    out.sort_unstable();
    out
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 8,
        rng_seed: RngSeed::Fixed(0x0de7_0de7),
        ..ProptestConfig::default()
    })]

    /// A permutation of the triangles and a rotation of the vertices within triangles give the
    /// same clusters (as sets of triangles), the same normals and the same pairs.
    #[test]
    fn clustering_does_not_depend_on_the_triangle_order(
        seed in any::<u64>(), which in 0usize..6, finger in any::<bool>(),
    ) {
        let (_, mesh) = meshes(seed % 3).swap_remove(which);
        let params = if finger { ClusterParams::finger() } else { ClusterParams::environment() };
        let a = cluster_surface(&mesh, &params).expect("valid");
        let other = shuffled(&mesh, seed);
        let b = cluster_surface(&other, &params).expect("valid");
        prop_assert_eq!(signature(&mesh, &a), signature(&other, &b));
        prop_assert_eq!(a.pairs.len(), b.pairs.len());
        for (p, r) in a.pairs.iter().zip(&b.pairs) {
            prop_assert!((p.width - r.width).abs() < 1e-9);
            prop_assert!((p.center - r.center).norm() < 1e-9);
        }
        prop_assert_eq!(params.mode == ContactMode::Finger, finger);
    }
}
