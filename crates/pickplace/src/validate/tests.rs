//! Unit tests of the validator.

use super::*;
use pickplace_geometry::math::Translation3;

#[test]
fn every_grasp_and_release_of_either_hand_has_its_touch_window() {
    // A synthetic handover followed by a regrasp: the right hand picks, the left takes
    // the object over, the right lets go, the left puts it down and grasps it again.
    // Each hand may touch the object from the start of its closing (its arm at rest) to
    // the grasp, and from a release to the end of its opening.
    let setup = crate::testing::setup("fig9-near.toml");
    let r = setup.arm(Arm::Right).variables[0];
    let l = setup.arm(Arm::Left).variables[0];
    let rf = setup.arm(Arm::Right).finger_variables[0];
    let lf = setup.arm(Arm::Left).finger_variables[0];
    // (right arm, left arm, right fingers, left fingers) per second.
    let samples = [
        (0.0, 0.0, 0.0, 0.0),
        (0.1, 0.0, 0.0, 0.0),
        (0.2, 0.0, 0.0, 0.0),  // the right arm arrives
        (0.2, 0.0, 0.01, 0.0), // its fingers close
        (0.2, 0.0, 0.02, 0.0), // grasp (right)
        (0.3, 0.0, 0.02, 0.0),
        (0.3, 0.1, 0.02, 0.0),
        (0.3, 0.2, 0.02, 0.0),  // the left arm arrives
        (0.3, 0.2, 0.02, 0.01), // its fingers close
        (0.3, 0.2, 0.02, 0.02), // grasp (left)
        (0.3, 0.2, 0.02, 0.02), // release (right)
        (0.3, 0.2, 0.0, 0.02),  // the right fingers open
        (0.4, 0.2, 0.0, 0.02),  // the right arm leaves
        (0.4, 0.3, 0.0, 0.02),  // the left arm places
        (0.4, 0.3, 0.0, 0.02),  // release (left)
        (0.4, 0.3, 0.0, 0.0),   // its fingers open
        (0.4, 0.3, 0.0, 0.02),  // regrasp (left), fingers closed again
        (0.4, 0.4, 0.0, 0.02),
    ];
    let traj: Vec<TrajectoryPoint> = samples
        .iter()
        .enumerate()
        .map(|(i, &(qr, ql, fr, fl))| {
            let mut q = setup.start.clone();
            q[r] += qr;
            q[l] += ql;
            q[rf] += fr;
            q[lf] += fl;
            TrajectoryPoint::positions_only(i as Real, q)
        })
        .collect();
    let ev = |time: Real, kind: EventKind, arm: Arm| Ev {
        time,
        kind,
        arm,
        link_from_object: Isometry3::identity(),
    };
    let events = [
        ev(4.0, EventKind::Grasp, Arm::Right),
        ev(9.0, EventKind::Grasp, Arm::Left),
        ev(10.0, EventKind::Release, Arm::Right),
        ev(14.0, EventKind::Release, Arm::Left),
        ev(16.0, EventKind::Grasp, Arm::Left),
    ];
    let windows = closing_windows(setup, &traj, &events);
    assert_eq!(
        windows,
        [
            (Arm::Right, 2.0, 4.0),
            (Arm::Left, 7.0, 9.0),
            (Arm::Right, 10.0, 11.0),
            (Arm::Left, 14.0, 16.0),
            (Arm::Left, 13.0, 16.0),
        ]
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, ..Default::default() })]

    /// A touch window runs exactly over the samples where the hand's arm stands where it
    /// is at the event: it ends (grasp) or starts (release) at the event, and the sample
    /// just outside it has the arm elsewhere.
    #[test]
    fn a_touch_window_spans_exactly_the_arm_at_rest(
        moves in proptest::collection::vec(proptest::bool::ANY, 2..40),
        at in 0usize..40,
        grasp in proptest::bool::ANY,
        left in proptest::bool::ANY,
    ) {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = if left { Arm::Left } else { Arm::Right };
        let v = setup.arm(arm).variables[0];
        let mut value = 0.0;
        let traj: Vec<TrajectoryPoint> = moves
            .iter()
            .enumerate()
            .map(|(i, &m)| {
                if m {
                    value += 0.01;
                }
                let mut q = setup.start.clone();
                q[v] += value;
                TrajectoryPoint::positions_only(i as Real * 0.5, q)
            })
            .collect();
        let k = at % traj.len();
        let kind = if grasp { EventKind::Grasp } else { EventKind::Release };
        let event = Ev {
            time: traj[k].time_from_start,
            kind,
            arm,
            link_from_object: Isometry3::identity(),
        };
        let windows = closing_windows(setup, &traj, &[event]);
        proptest::prop_assert_eq!(windows.len(), 1);
        let (w, t0, t1) = windows[0];
        proptest::prop_assert_eq!(w, arm);
        proptest::prop_assert!(t0 <= t1);
        let at_event = if grasp { t1 } else { t0 };
        proptest::prop_assert_eq!(at_event, event.time);
        let here = traj[k].positions[v];
        for p in &traj {
            let inside = p.time_from_start >= t0 && p.time_from_start <= t1;
            if inside {
                proptest::prop_assert_eq!(p.positions[v], here);
            }
        }
        let before = traj.iter().rposition(|p| p.time_from_start < t0);
        let after = traj.iter().position(|p| p.time_from_start > t1);
        if let Some(b) = before.filter(|_| grasp) {
            proptest::prop_assert!(traj[b].positions[v] != here);
        }
        if let Some(a) = after.filter(|_| !grasp) {
            proptest::prop_assert!(traj[a].positions[v] != here);
        }
    }
}

/// The can upright with its base centre at `(x, y, z)`.
fn can_at(setup: &Setup, x: Real, y: Real, z: Real) -> Isometry3 {
    let start = setup.object_start;
    let t = start.translation.vector;
    Translation3::new(x - t.x, y - t.y, z - t.z) * start
}

fn rest_problems(x: Real, z: Real) -> (Vec<String>, Option<Real>) {
    let setup = crate::testing::setup("fig9-near.toml");
    let mut v = Validator::new(setup).expect("validator");
    let margin = v.rest_check(1.0, &can_at(setup, x, -0.25, z), "the placed object");
    (v.problems, margin)
}

#[test]
fn a_resting_pose_must_stand_on_a_support_without_penetrating_or_tipping() {
    // The pallet's top is at z = 0.76, its edge at x = 0.30.
    let (problems, margin) = rest_problems(0.36, 0.76);
    assert!(problems.is_empty(), "{problems:?}");
    assert!(margin.is_some_and(|m| m > 0.02), "{margin:?}");
    // Overhanging the edge: the CoG 1 cm beyond it.
    let (problems, margin) = rest_problems(0.29, 0.76);
    assert!(margin.is_some_and(|m| m < 0.0), "{margin:?}");
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(
        problems[0].contains("the placed object is unstable"),
        "{problems:?}"
    );
    // In mid-air.
    let (problems, margin) = rest_problems(0.36, 0.80);
    assert_eq!(margin, None);
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(
        problems[0].contains("does not rest on a support"),
        "{problems:?}"
    );
    // Sunk 5 mm into the pallet.
    let (problems, _) = rest_problems(0.36, 0.755);
    assert!(
        problems
            .iter()
            .any(|p| p.contains("penetrates the environment")),
        "{problems:?}"
    );
}
