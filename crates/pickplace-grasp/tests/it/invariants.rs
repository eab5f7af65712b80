//! Invariants every returned grasp satisfies, on the shipped objects and on random boxes.

use super::support::{self, Planned};
use pickplace_geometry::cluster::Cluster;
use pickplace_geometry::math::Point3;
use pickplace_geometry::polygon;
use pickplace_geometry::shapes;
use pickplace_grasp::{GraspOptions, GripperParams};
use pickplace_objects as objects;
use proptest::prelude::*;

fn inside_region(c: &Cluster, p: &Point3) -> bool {
    let q = c.frame.to_2d(p);
    c.region.contains(&q)
        || std::iter::once(&c.region.outer)
            .chain(c.region.holes.iter())
            .any(|r| polygon::distance_to_ring(&q, r) < 1e-6)
}

/// Checks every grasp of `planned`; returns a description of the first violation.
fn check(planned: &Planned, gripper: &GripperParams, options: &GraspOptions) -> Result<(), String> {
    let Planned {
        mesh,
        clustering,
        set,
    } = planned;
    let h_max = clustering.params.h_max;
    let rejected = set.rejected;
    let sum = set.grasps.len()
        + rejected.width
        + rejected.pad_tilt
        + rejected.contact
        + rejected.finger_collision
        + rejected.palm_collision;
    if sum != set.candidates {
        return Err(format!("{sum} outcomes for {} candidates", set.candidates));
    }
    if !set.grasps.windows(2).all(|w| w[0].score >= w[1].score) {
        return Err("not ranked".into());
    }
    for (i, g) in set.grasps.iter().enumerate() {
        if !(g.width >= gripper.opening_min && g.width <= gripper.opening_max) {
            return Err(format!(
                "grasp {i}: width {} outside the opening range",
                g.width
            ));
        }
        if !(0.0..=1.0).contains(&g.score) {
            return Err(format!("grasp {i}: score {}", g.score));
        }
        for (sign, id) in [(1.0, g.positive_cluster), (-1.0, g.negative_cluster)] {
            let c = &clustering.clusters[id as usize];
            let pad = support::pad_points(g, gripper, sign);
            // A pad drawn back on a thin region (tip shift) is centred off the region, by at
            // most half its depth and the clearance; its grasp centre is on it.
            let tip_limit = 0.5 * gripper.pad_depth + options.clearance + 1e-9;
            if !(0.0..=tip_limit).contains(&g.quality.tip_shift) {
                return Err(format!("grasp {i}: tip shift {}", g.quality.tip_shift));
            }
            let centre = pad[0] + support::approach(g, gripper) * g.quality.tip_shift;
            // The grasp centre is on the patch (width measured on the mesh), or above it by at
            // most the pad's depth when the surface under the pad rises beside the patch (the
            // pad touches the highest point under it); the pad stays within the sheet's depth
            // of the patch's plane beyond the patch's own thickness.
            let above = g.quality.pad_depth + 1e-9;
            if c.plane_distance(&centre) > above || c.plane_distance(&centre) < -c.h - 1e-9 {
                return Err(format!(
                    "grasp {i}: grasp centre {} m off cluster {id}'s plane (h = {})",
                    c.plane_distance(&centre),
                    c.h
                ));
            }
            if g.quality.pad_depth > h_max + 1e-9 {
                return Err(format!("grasp {i}: pad depth {}", g.quality.pad_depth));
            }
            if let Some(p) = pad
                .iter()
                .find(|p| c.plane_distance(p).abs() > h_max + c.h + 1e-9)
            {
                return Err(format!(
                    "grasp {i}: pad point {p} is {} m off cluster {id}'s plane",
                    c.plane_distance(p)
                ));
            }
            if !inside_region(c, &centre) {
                return Err(format!("grasp {i}: grasp centre outside cluster {id}"));
            }
            // The pad faces the cluster: the closing axis points out of the cluster on its side.
            if (support::closing(g, gripper) * sign).dot(&c.normal) < 0.9 {
                return Err(format!("grasp {i}: pad does not face cluster {id}"));
            }
        }
        // A pad drawn back covers at least a fifth of its depth (THIN_MIN_DEPTH).
        let full = if g.quality.tip_shift > 0.0 { 0.2 } else { 1.0 };
        if g.quality.contact_area < options.min_contact_ratio * full * gripper.pad_area() - 1e-12 {
            return Err(format!("grasp {i}: contact {}", g.quality.contact_area));
        }
        for (k, body) in support::bodies(g, gripper, options.clearance)
            .iter()
            .enumerate()
        {
            if support::body_hits(mesh, body) {
                return Err(format!("grasp {i}: gripper body {k} intersects the object"));
            }
        }
    }
    Ok(())
}

#[test]
fn can_mug_and_box_grasps_satisfy_the_invariants() {
    let gripper = support::gripper();
    let options = GraspOptions::default();
    for builder in [
        objects::can_builder(),
        objects::mug_builder(),
        objects::object_box_builder(),
    ] {
        let planned = support::plan(builder.build().expect("valid"), &gripper, &options);
        assert!(!planned.set.grasps.is_empty());
        check(&planned, &gripper, &options).expect("invariants");
    }
}

#[test]
fn output_does_not_depend_on_the_thread_count() {
    let gripper = support::gripper();
    let mesh = objects::mug_builder().build().expect("valid");
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            format!(
                "{:?}",
                support::plan(mesh.clone(), &gripper, &GraspOptions::default()).set
            )
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn the_collider_sees_what_the_independent_check_sees() {
    // Without any clearance the fingers touch the cluster planes: every candidate collides
    // in the independent check once the fingers close 1 mm beyond the planes.
    let gripper = support::gripper();
    let options = GraspOptions {
        clearance: 0.0,
        ..Default::default()
    };
    let planned = support::plan(
        objects::object_box_builder().build().expect("valid"),
        &gripper,
        &options,
    );
    let g = planned.set.grasps.first().expect("grasps");
    let pressed = gripper
        .fingers(g.width - 0.002)
        .map(|f| support::obb(&g.object_from_tcp, &f));
    assert!(pressed.iter().all(|f| support::body_hits(&planned.mesh, f)));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn random_boxes_and_options(
        hx in 0.01..0.06f64, hy in 0.01..0.06f64, hz in 0.005..0.06f64,
        step in 0.006..0.02f64, approaches in 1usize..10, flip in any::<bool>(), clearance in 0.0..0.004f64,
    ) {
        let gripper = support::gripper();
        let options = GraspOptions { grid_step: step, approach_count: approaches, flip_closing: flip, clearance, ..Default::default() };
        let planned = support::plan(shapes::box_mesh([hx, hy, hz]), &gripper, &options);
        prop_assert!(check(&planned, &gripper, &options).is_ok(), "{:?}", check(&planned, &gripper, &options));
        let fits = [hx, hy, hz].iter().filter(|h| 2.0 * **h <= gripper.opening_max - 2.0 * clearance).count();
        prop_assert_eq!(planned.set.rejected.pair_width, 3 - fits);
    }
}
