//! The suite's scanned-like objects (issue 31): solids of [`crate::scanned`] (the generator of
//! `cargo xtask stability`) with its 1 mm of seeded noise, 10 000 to 20 000 triangles each, in
//! their own frame (base at z = 0, not a scanner's), some written in millimetres; and their
//! scenes, after the suite's own kinds: on the table, on a side or an end, in clutter, onto
//! shelves, box tops and a dent, into gaps, handovers, regrasps, and physically impossible ones.
//!
//! Every start puts a flat face down (a box's face, a solid of revolution's or a cut blob's
//! base), where a scan flat to 1 mm rests; positions are copied from the suite's scenes that
//! plan.

use super::{
    Expect, Part, Spec, SuiteMesh, TABLE_TOP, Tilt, base, gap_blocks, on_table, pallet, part, shelf,
};
use crate::scanned::{blob, boxed, can_profile, noisy, revolved, rounded_box};
use pickplace_geometry::math::Real;
use pickplace_geometry::shapes::MeshBuilder;
use pickplace_objects as objects;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, FRAC_PI_6};

/// The objects and the environment parts of the scanned scenes.
pub(super) fn meshes() -> Vec<SuiteMesh> {
    let object = |key, path, builder: MeshBuilder, seed, scale| SuiteMesh {
        key,
        path,
        builder: noisy(builder, seed),
        written: true,
        scale,
    };
    let part = |key, path, builder| SuiteMesh {
        key,
        path,
        builder,
        written: true,
        scale: 1.0,
    };
    let mm = 0.001;
    vec![
        // 6 x 4 x 10 cm: the paper's box, scanned.
        object(
            "scan-box",
            "meshes/suite/scan-box.stl",
            boxed([0.06, 0.04, 0.10], 14_000),
            31,
            1.0,
        ),
        // 15 x 5 x 3 cm, lying flat; in millimetres.
        object(
            "scan-brick",
            "meshes/suite/scan-brick-mm.stl",
            boxed([0.15, 0.05, 0.03], 12_000),
            32,
            mm,
        ),
        // A bar of soap: 8 x 6 x 5 cm, edges rounded to 8 mm.
        object(
            "scan-soap",
            "meshes/suite/scan-soap.stl",
            rounded_box([0.08, 0.06, 0.05], 0.008, 14_000),
            33,
            1.0,
        ),
        // A bottle-like cylinder: 5 cm across, 15 cm tall; in millimetres.
        object(
            "scan-bottle",
            "meshes/suite/scan-bottle-mm.stl",
            revolved(
                &[[0.0, 0.0], [0.025, 0.0], [0.025, 0.15], [0.0, 0.15]],
                14_000,
            ),
            34,
            mm,
        ),
        // A soup can with rims: 6.6 cm across, 12 cm tall.
        object(
            "scan-can",
            "meshes/suite/scan-can.stl",
            revolved(&can_profile(0.033, 0.12), 16_000),
            35,
            1.0,
        ),
        // A cone frustum: 8 cm base, 4 cm top, 10 cm tall; in millimetres.
        object(
            "scan-cone",
            "meshes/suite/scan-cone-mm.stl",
            revolved(
                &[[0.0, 0.0], [0.04, 0.0], [0.02, 0.10], [0.0, 0.10]],
                14_000,
            ),
            36,
            mm,
        ),
        // A stone: a lobed ellipsoid 8 x 6 cm, cut flat 6 mm up (4.4 cm tall).
        object(
            "scan-stone",
            "meshes/suite/scan-stone.stl",
            blob([0.04, 0.03, 0.025], 0.006, 3, 0.08, 14_000),
            37,
            1.0,
        ),
        // A 10 cm cube: wider than the 8 cm opening every way.
        object(
            "scan-big-box",
            "meshes/suite/scan-big-box.stl",
            boxed([0.10, 0.10, 0.10], 12_000),
            38,
            1.0,
        ),
        // A die: a 2 cm cube with edges rounded to 2 mm, scanned finer (0.3 mm of noise on
        // 4 000 triangles): 1 mm of noise on 0.7 mm triangles would be no surface at all.
        SuiteMesh {
            key: "scan-die",
            path: "meshes/suite/scan-die.stl",
            builder: objects::jittered(rounded_box([0.02, 0.02, 0.02], 0.002, 4_000), 0.0003, 40),
            written: true,
            scale: 1.0,
        },
        // Environment.
        part(
            "crate",
            "meshes/suite/crate.stl",
            objects::box_on_base_builder([0.14, 0.14, 0.06]),
        ),
        part(
            "low-shelf",
            "meshes/suite/low-shelf.stl",
            objects::shelf_builder([0.20, 0.30], 0.07),
        ),
    ]
}

/// A closed box (0.14 square, 0.06 high) at `(x, y)`, and the point on its top.
fn crate_top(x: Real, y: Real) -> (Part, [Real; 3]) {
    (part("crate", "crate", x, y), [x, y, TABLE_TOP + 0.06])
}

/// The scanned scenes, feasible first.
pub(super) fn scenes() -> Vec<Spec> {
    let mut s = Vec::new();
    let mut add = |mut sc: Spec, tags: &[&'static str]| {
        sc.tags = std::iter::once("scanned")
            .chain(tags.iter().copied())
            .collect();
        s.push(sc);
    };
    let right = ([0.40, -0.20], on_table(0.47, -0.06));
    let left = ([0.40, 0.20], on_table(0.46, 0.06));

    // --- Table to table, standing on the base.
    for (name, about, object, (start, target), tags) in [
        (
            "scan-box-right",
            "a scanned box (6 x 4 x 10 cm, 1 mm noise) standing, near the right hand",
            "scan-box",
            right,
            &["table", "right"][..],
        ),
        (
            "scan-box-left",
            "the scanned box near the left hand",
            "scan-box",
            left,
            &["table", "left"][..],
        ),
        (
            "scan-brick-right",
            "a scanned brick (15 x 5 x 3 cm, millimetre file) lying flat",
            "scan-brick",
            right,
            &["table", "right", "millimetres"][..],
        ),
        (
            "scan-soap-left",
            "a scanned bar of soap (rounded edges)",
            "scan-soap",
            left,
            &["table", "left", "curved"][..],
        ),
        (
            "scan-bottle-right",
            "a scanned cylinder 5 cm across and 15 cm tall (millimetre file), standing",
            "scan-bottle",
            // Not at `right`: 15 cm tall there, it would reach into the right hand's home pose.
            ([0.50, -0.20], on_table(0.42, -0.04)),
            &["table", "right", "millimetres"][..],
        ),
        (
            "scan-can-left",
            "a scanned soup can with rims, standing on its rim",
            "scan-can",
            left,
            &["table", "left"][..],
        ),
        (
            "scan-can-right",
            "the scanned soup can near the right hand",
            "scan-can",
            right,
            &["table", "right"][..],
        ),
        (
            "scan-cone-right",
            "a scanned cone frustum (8 cm base, 4 cm top; millimetre file)",
            "scan-cone",
            right,
            &["table", "right", "millimetres"][..],
        ),
        (
            "scan-stone-left",
            "a scanned stone (a lobed ellipsoid cut flat) on its flat",
            "scan-stone",
            left,
            &["table", "left", "curved"][..],
        ),
    ] {
        add(base(name, about, object, start, target), tags);
    }
    let mut sc = base(
        "scan-stone-right-turned",
        "the scanned stone turned 45° on the table",
        "scan-stone",
        right.0,
        right.1,
    );
    sc.yaw = FRAC_PI_4;
    add(sc, &["table", "right", "curved"]);

    // --- A small object: the pads' tips stop short of the table (tip shift).
    add(
        base(
            "scan-die-left",
            "a scanned 2 cm die",
            "scan-die",
            [0.40, 0.20],
            on_table(0.40, 0.12),
        ),
        &["table", "left", "small"],
    );
    let mut sc = base(
        "scan-die-right-on-side",
        "the scanned die on another face, turned 30°",
        "scan-die",
        [0.40, -0.20],
        on_table(0.42, -0.12),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_6;
    add(sc, &["table", "right", "small", "on-side"]);

    // --- On a side, on an end, upside down.
    let mut sc = base(
        "scan-box-on-side",
        "the scanned box lying on a long side",
        "scan-box",
        [0.42, -0.18],
        on_table(0.47, -0.04),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    add(sc, &["table", "on-side"]);
    let mut sc = base(
        "scan-box-on-end",
        "the scanned box on its 4 x 10 cm end face",
        "scan-box",
        [0.42, 0.18],
        on_table(0.46, 0.02),
    );
    sc.tilt = Tilt::OnEnd;
    add(sc, &["table", "on-side"]);
    let mut sc = base(
        "scan-brick-on-edge",
        "the scanned brick standing on its 15 x 3 cm edge",
        "scan-brick",
        right.0,
        right.1,
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    add(sc, &["table", "on-side", "thin", "millimetres"]);
    let mut sc = base(
        "scan-soap-on-side",
        "the scanned soap on its 8 x 5 cm side",
        "scan-soap",
        [0.42, -0.18],
        on_table(0.47, -0.04),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    add(sc, &["table", "on-side", "curved"]);
    let mut sc = base(
        "scan-box-upside-down",
        "the scanned box upside down",
        "scan-box",
        left.0,
        left.1,
    );
    sc.tilt = Tilt::UpsideDown;
    add(sc, &["table", "upside-down"]);

    // --- Clutter (the suite's clutter scenes with scanned objects).
    let mut sc = base(
        "scan-can-clutter-start",
        "the scanned can boxed in by three obstacles, to an open spot",
        "scan-can",
        [0.42, -0.20],
        on_table(0.45, 0.0),
    );
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.52, -0.20),
        part("obstacle-b", "obstacle", 0.42, -0.30),
        part("obstacle-c", "low-box", 0.42, -0.10),
    ]);
    add(sc, &["clutter"]);
    let mut sc = base(
        "scan-soap-clutter-target",
        "the scanned soap to a spot among three obstacles",
        "scan-soap",
        [0.38, 0.05],
        on_table(0.46, -0.22),
    );
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.57, -0.22),
        part("obstacle-b", "obstacle", 0.46, -0.34),
        part("obstacle-c", "low-box", 0.36, -0.22),
    ]);
    add(sc, &["clutter", "curved"]);
    let mut sc = base(
        "scan-bottle-before-wall",
        "the scanned cylinder set down 8 cm in front of a wall",
        "scan-bottle",
        [0.40, 0.0],
        on_table(0.50, -0.15),
    );
    sc.parts.push(part("wall", "wall", 0.60, -0.15));
    add(sc, &["clutter", "millimetres"]);
    let mut sc = base(
        "scan-box-clutter-both",
        "the scanned box from among obstacles to a spot before a wall",
        "scan-box",
        [0.50, -0.22],
        on_table(0.44, 0.02),
    );
    sc.yaw = FRAC_PI_2;
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.50, -0.36),
        part("obstacle-b", "low-box", 0.60, -0.22),
        part("obstacle-c", "low-box", 0.50, -0.06),
        part("wall", "wall", 0.58, 0.02),
    ]);
    add(sc, &["clutter"]);

    // --- Shelves.
    let (sh, top) = shelf(0.55, -0.20);
    for (name, about, object, tags) in [
        (
            "scan-box-onto-shelf",
            "the scanned box onto a shelf board 15 cm above the table",
            "scan-box",
            &["shelf"][..],
        ),
        (
            "scan-can-onto-shelf",
            "the scanned can onto the shelf",
            "scan-can",
            &["shelf"][..],
        ),
        (
            "scan-brick-onto-shelf",
            "the scanned brick (millimetre file) onto the shelf",
            "scan-brick",
            &["shelf", "millimetres"][..],
        ),
    ] {
        let mut sc = base(name, about, object, [0.38, 0.0], top);
        sc.parts.push(sh.clone());
        add(sc, tags);
    }
    let (shl, topl) = shelf(0.55, 0.20);
    let mut sc = base(
        "scan-cone-onto-left-shelf",
        "the scanned cone frustum onto a shelf on the left",
        "scan-cone",
        [0.38, 0.0],
        topl,
    );
    sc.parts.push(shl);
    add(sc, &["shelf", "left", "millimetres"]);

    // --- Box tops: a closed box 14 cm square and 6 cm high.
    let (cr, crt) = crate_top(0.48, -0.12);
    for (name, about, object, tags) in [
        (
            "scan-can-onto-box-top",
            "the scanned can onto the top of a closed box 6 cm high",
            "scan-can",
            &["box-top"][..],
        ),
        (
            "scan-stone-onto-box-top",
            "the scanned stone onto the box top",
            "scan-stone",
            &["box-top", "curved"][..],
        ),
    ] {
        let mut sc = base(name, about, object, [0.38, 0.05], crt);
        sc.parts.push(cr.clone());
        add(sc, tags);
    }
    let (crl, crlt) = crate_top(0.48, 0.12);
    let mut sc = base(
        "scan-soap-onto-left-box-top",
        "the scanned soap onto a box top on the left",
        "scan-soap",
        [0.38, -0.05],
        crlt,
    );
    sc.parts.push(crl);
    add(sc, &["box-top", "left", "curved"]);

    // --- Gaps and a dent.
    let gap_target = on_table(0.48, -0.18);
    for (name, about, object) in [
        (
            "scan-box-into-gap",
            "the scanned box upright into the 7 cm gap between two blocks",
            "scan-box",
        ),
        (
            "scan-can-into-gap",
            "the scanned can (6.6 cm) into the 7 cm gap",
            "scan-can",
        ),
    ] {
        let mut sc = base(name, about, object, [0.38, 0.05], gap_target);
        sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
        add(sc, &["gap"]);
    }
    let (p, dents) = pallet(0.48, -0.20);
    let mut sc = base(
        "scan-can-into-large-dent",
        "the scanned can into the pallet's large dent (9 cm square, 15 mm deep)",
        "scan-can",
        [0.38, 0.02],
        dents[0],
    );
    sc.parts.push(p);
    add(sc, &["dent"]);

    // --- Handovers: start far on one side, target far on the other.
    for (name, about, object, start, target) in [
        (
            "scan-can-handover-left-to-right",
            "the scanned can from far left to far right",
            "scan-can",
            [0.46, 0.34],
            on_table(0.44, -0.34),
        ),
        (
            "scan-box-handover-right-to-left",
            "the scanned box from far right to far left",
            "scan-box",
            [0.46, -0.34],
            on_table(0.44, 0.34),
        ),
        (
            "scan-stone-handover",
            "the scanned stone from far left to far right",
            "scan-stone",
            [0.46, 0.34],
            on_table(0.44, -0.34),
        ),
    ] {
        let sc = base(name, about, object, start, target);
        add(sc, &["handover"]);
    }
    // The same move from within reach: only grasps from above clear the table under the
    // 4.4 cm stone, and a handover would need two of them at once, so the arms pass it by
    // putting it down between them.
    let sc = base(
        "scan-stone-left-to-right",
        "the scanned stone from the left to the right: only grasps from above clear the table, so it is put down between the arms and picked again",
        "scan-stone",
        [0.40, 0.28],
        on_table(0.40, -0.28),
    );
    add(sc, &["handover", "regrasp"]);

    // --- Regrasp: one arm, the box lying, upright only into the gap.
    let mut sc = base(
        "scan-box-on-side-into-gap-right-arm-only",
        "one arm: the scanned box lies on its side; it fits the gap upright, which no grasp that picks it lying gives, so it is put down upright and picked again",
        "scan-box",
        [0.40, -0.02],
        gap_target,
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.left_arm = Some("");
    add(sc, &["regrasp", "gap", "on-side"]);
    let mut sc = base(
        "scan-box-on-side-into-gap-left-arm-only",
        "the same, mirrored, with the left arm only",
        "scan-box",
        [0.40, 0.02],
        on_table(0.48, 0.18),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, 0.18, 0.07));
    sc.right_arm = Some("");
    add(sc, &["regrasp", "gap", "on-side"]);

    // --- No solution, for physical reasons.
    let infeasible = |stage, reason| Expect::Infeasible { stage, reason };
    let mut sc = base(
        "scan-big-box-no-grasp",
        "a scanned 10 cm cube: wider than the 8 cm opening every way",
        "scan-big-box",
        [0.42, -0.20],
        on_table(0.46, -0.02),
    );
    sc.expect = infeasible("grasp", "no grasp");
    add(sc, &["no-solution"]);
    for (name, about, object, gap, tags) in [
        (
            "scan-can-into-narrow-gap",
            "the scanned can (6.6 cm) into a 5 cm gap",
            "scan-can",
            0.05,
            &["no-solution", "gap"][..],
        ),
        (
            "scan-box-into-narrow-gap",
            "the scanned box (4 cm at its thinnest) into a 3 cm gap",
            "scan-box",
            0.03,
            &["no-solution", "gap"][..],
        ),
        (
            "scan-brick-into-narrow-gap",
            "the scanned brick (3 cm at its thinnest) into a 2.5 cm gap",
            "scan-brick",
            0.025,
            &["no-solution", "gap", "millimetres"][..],
        ),
    ] {
        let mut sc = base(name, about, object, [0.38, 0.05], gap_target);
        sc.parts.extend(gap_blocks(0.48, -0.18, gap));
        sc.expect = infeasible("placement", "no stable placement");
        add(sc, tags);
    }
    let mut sc = base(
        "scan-can-under-low-shelf",
        "the scanned can (6.6 cm across, 12 cm tall) onto the table under a shelf board whose underside is 5 cm up",
        "scan-can",
        [0.38, 0.05],
        gap_target,
    );
    sc.parts.push(part("low-shelf", "low-shelf", 0.48, -0.18));
    sc.expect = infeasible("placement", "no stable placement");
    add(sc, &["no-solution", "shelf"]);
    let far_table = Part {
        name: "far-table",
        mesh: "table",
        at: [1.45, 0.0, TABLE_TOP - 0.70],
        yaw: 0.0,
    };
    let mut sc = base(
        "scan-can-target-out-of-reach",
        "the scanned can to a second table 1.35 m in front: no hand reaches it",
        "scan-can",
        [0.40, -0.20],
        on_table(1.35, -0.10),
    );
    sc.parts.push(far_table.clone());
    sc.expect = infeasible("place", "out of reach");
    add(sc, &["no-solution"]);
    let (far_shelf, far_top) = shelf(1.35, -0.10);
    let mut sc = base(
        "scan-box-onto-far-shelf",
        "the scanned box onto a shelf on the second table: no hand reaches it",
        "scan-box",
        [0.40, -0.20],
        far_top,
    );
    sc.parts.extend([far_table, far_shelf]);
    sc.expect = infeasible("place", "out of reach");
    add(sc, &["no-solution", "shelf"]);
    for (name, about, object, tags) in [
        (
            "scan-soap-on-ramp",
            "the scanned soap onto a 45° ramp, where nothing stays without friction",
            "scan-soap",
            &["no-solution", "curved"][..],
        ),
        (
            "scan-cone-on-ramp",
            "the scanned cone frustum onto the 45° ramp",
            "scan-cone",
            &["no-solution", "millimetres"][..],
        ),
    ] {
        let mut sc = base(
            name,
            about,
            object,
            [0.40, 0.10],
            [0.46, -0.20, TABLE_TOP + 0.06],
        );
        sc.parts.push(part("ramp", "ramp", 0.46, -0.20));
        sc.expect = infeasible("target", "too steep");
        add(sc, tags);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What issue 31 asks: scanned-like objects of modest size that fit the gripper's 8 cm
    /// opening some way (but the cube that must not), some in millimetres, and at least 8
    /// scenes with no solution.
    #[test]
    fn scanned_objects_and_scenes_are_what_issue_31_asks() {
        let meshes = meshes();
        let objects: Vec<&SuiteMesh> = meshes
            .iter()
            .filter(|m| m.key.starts_with("scan-"))
            .collect();
        assert!(objects.iter().any(|m| m.scale == 0.001));
        for m in &objects {
            let n = m.builder.triangles.len();
            // The 2 cm die is scanned finer and coarser (0.3 mm noise, 4 000 triangles): at
            // 10 000 its triangles would be smaller than the noise.
            let range = if m.key == "scan-die" {
                3_000..=5_000
            } else {
                10_000..=20_000
            };
            assert!(range.contains(&n), "{}: {n} triangles", m.key);
            // Fits one way: 7.5 cm or less across, in z or across x or y in some tenth of its
            // height (a frustum fits at its narrow end).
            let z = |p: &pickplace_geometry::math::Point3| p.z;
            let (z0, z1) = m
                .builder
                .positions
                .iter()
                .map(z)
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            let fits = z1 - z0 < 0.075
                || (0..10).any(|k| {
                    let (a, b) = (
                        z0 + (z1 - z0) * k as Real / 10.0,
                        z0 + (z1 - z0) * (k + 1) as Real / 10.0,
                    );
                    let slice: Vec<_> = m
                        .builder
                        .positions
                        .iter()
                        .filter(|p| (a..=b).contains(&p.z))
                        .collect();
                    (0..2).any(|i| {
                        let (lo, hi) = slice
                            .iter()
                            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| {
                                (lo.min(p[i]), hi.max(p[i]))
                            });
                        hi - lo < 0.075
                    })
                });
            assert_eq!(fits, m.key != "scan-big-box", "{}", m.key);
        }
        let specs = scenes();
        assert!(specs.len() >= 40, "{}", specs.len());
        let infeasible = specs
            .iter()
            .filter(|s| matches!(s.expect, Expect::Infeasible { .. }))
            .count();
        assert!(infeasible >= 8, "{infeasible}");
        for s in &specs {
            assert!(
                s.name.starts_with("scan-") && s.tags.contains(&"scanned"),
                "{}",
                s.name
            );
            assert!(objects.iter().any(|m| m.key == s.object), "{}", s.name);
        }
    }
}
