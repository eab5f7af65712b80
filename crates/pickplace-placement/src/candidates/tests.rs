//! Unit tests of `candidates`.

use super::search::spread_order;
use super::*;
use proptest::prelude::*;

fn placement(face: usize, contact: ContactKind, distance: Real) -> Placement {
    Placement {
        world_from_object: Isometry3::identity(),
        contact,
        object_cluster: face,
        env_cluster: 0,
        stability_margin: 0.01,
        tipping_angle: 0.1,
        distance_to_target: distance,
        tilt: 0.0,
    }
}

#[test]
fn yaws_are_spread_over_the_turn() {
    assert_eq!(spread_order(8), vec![0, 4, 2, 6, 1, 5, 3, 7]);
    let mut twelve = spread_order(12);
    twelve.sort_unstable();
    assert_eq!(twelve, (0..12).collect::<Vec<_>>());
}

#[test]
fn every_face_comes_before_a_second_variant() {
    // Face 0 has three variants ranked first, faces 1 and 2 one each after them.
    let sorted = vec![
        placement(0, ContactKind::FaceFace, 0.0),
        placement(0, ContactKind::FaceFace, 0.001),
        placement(0, ContactKind::FaceFace, 0.002),
        placement(1, ContactKind::FaceFace, 0.003),
        placement(2, ContactKind::EdgeFace, 0.004),
        placement(1, ContactKind::FaceFace, 0.005),
    ];
    let out = diversify(sorted.clone(), 100);
    let order: Vec<(usize, Real)> = out
        .iter()
        .map(|p| (p.object_cluster, p.distance_to_target))
        .collect();
    assert_eq!(
        order,
        vec![
            (0, 0.0),
            (1, 0.003),
            (2, 0.004),
            (0, 0.001),
            (1, 0.005),
            (0, 0.002)
        ]
    );
    // A cap of 2 still keeps the three faces; a cap of 4 adds the second of face 0.
    assert_eq!(diversify(sorted.clone(), 2).len(), 3);
    assert_eq!(diversify(sorted, 4).len(), 4);
}

proptest! {
    /// Whatever the faces and the cap: every face is kept, each face's placements keep
    /// their order, and no placement is invented or repeated.
    #[test]
    fn diversify_keeps_every_face_in_order(
        faces in proptest::collection::vec((0usize..6, any::<bool>()), 1..40),
        max in 0usize..50,
    ) {
        let sorted: Vec<Placement> = faces
            .iter()
            .enumerate()
            .map(|(i, &(f, edge))| {
                let kind = if edge { ContactKind::EdgeFace } else { ContactKind::FaceFace };
                placement(f, kind, i as Real)
            })
            .collect();
        let all: std::collections::BTreeSet<_> = sorted.iter().map(face_of).collect();
        let out = diversify(sorted.clone(), max);
        let kept: std::collections::BTreeSet<_> = out.iter().map(face_of).collect();
        prop_assert_eq!(&kept, &all);
        prop_assert_eq!(out.len(), max.max(all.len()).min(sorted.len()));
        for face in &all {
            let d: Vec<Real> = out
                .iter()
                .filter(|p| face_of(p) == *face)
                .map(|p| p.distance_to_target)
                .collect();
            prop_assert!(d.windows(2).all(|w| w[0] < w[1]));
        }
    }
}
