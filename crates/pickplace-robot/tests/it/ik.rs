//! IK round trips: FK of random configurations, solved back.

use crate::common::{nx, random_configuration};
use pickplace_geometry::math::{UnitVector3, Vector3};
use pickplace_robot::rng::Rng;
use pickplace_robot::{IkOptions, IkSolver};

#[test]
fn right_arm_with_waist_round_trips_from_a_far_seed() {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "right_arm_waist").expect("group");
    let mut rng = Rng::new(11);
    let mut home = vec![0.0; model.variable_count()];
    semantics
        .apply_state(model, "home", &mut home)
        .expect("state");
    let options = IkOptions::default();
    // The bar (99.5 %) on 1 000 poses here; 10 000 in the release bench.
    let trials = 1_000;
    let mut solved = 0;
    for _ in 0..trials {
        let q = random_configuration(model, &mut rng);
        let target = solver.chain().pose(&q);
        let solution = solver.solve(&target, &home, &options).expect("valid input");
        if solution.success {
            solved += 1;
            // The solution satisfies FK and the limits, and leaves other variables alone.
            let reached = solver.chain().pose(&solution.positions);
            assert!(
                (reached.translation.vector - target.translation.vector).norm()
                    <= options.position_tolerance
            );
            assert!(reached.rotation.angle_to(&target.rotation) <= options.orientation_tolerance);
            model
                .check_configuration(&solution.positions)
                .expect("within limits");
            for (v, (got, seed)) in solution.positions.iter().zip(&home).enumerate() {
                if !solver.chain().variables().contains(&v) {
                    assert_eq!(got, seed);
                }
            }
        }
    }
    assert!(
        solved as f64 >= 0.995 * trials as f64,
        "solved {solved}/{trials}"
    );
}

#[test]
fn a_seed_at_the_solution_returns_it() {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "left_arm").expect("group");
    let mut home = vec![0.0; model.variable_count()];
    semantics
        .apply_state(model, "home", &mut home)
        .expect("state");
    let target = solver.chain().pose(&home);
    let solution = solver
        .solve(&target, &home, &IkOptions::default())
        .expect("valid");
    assert!(solution.success);
    assert_eq!(solution.attempts, 1);
    assert_eq!(solution.iterations, 0);
    assert_eq!(solution.positions, home);
}

#[test]
fn unreachable_target_fails_with_the_best_error() {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "right_arm").expect("group");
    let seed = vec![0.0; model.variable_count()];
    let mut target = solver.chain().pose(&seed);
    target.translation.vector += Vector3::new(2.0, 0.0, 0.0);
    let options = IkOptions {
        max_restarts: 3,
        ..IkOptions::default()
    };
    let solution = solver.solve(&target, &seed, &options).expect("valid");
    assert!(!solution.success);
    assert_eq!(solution.attempts, 4);
    assert!(solution.position_error > 1.0);
}

#[test]
fn free_axis_ignores_rotation_about_the_approach() {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "right_arm_waist").expect("group");
    let mut rng = Rng::new(5);
    let mut home = vec![0.0; model.variable_count()];
    semantics
        .apply_state(model, "home", &mut home)
        .expect("state");
    let axis = UnitVector3::new_normalize(Vector3::z());
    let options = IkOptions {
        free_axis: Some(axis),
        ..IkOptions::default()
    };
    let mut solved = 0;
    for _ in 0..50 {
        let q = random_configuration(model, &mut rng);
        let reachable = solver.chain().pose(&q);
        // Spin the target about its approach axis: unreachable in full, reachable modulo z.
        let spin = pickplace_geometry::math::UnitQuaternion::from_axis_angle(
            &axis,
            rng.uniform(-3.0, 3.0),
        );
        let mut target = reachable;
        target.rotation *= spin;
        let s = solver.solve(&target, &home, &options).expect("valid");
        if s.success {
            solved += 1;
            let reached = solver.chain().pose(&s.positions);
            let a = reached.rotation * Vector3::z();
            let b = target.rotation * Vector3::z();
            assert!(a.angle(&b) <= options.orientation_tolerance + 1e-12);
            assert!(
                (reached.translation.vector - target.translation.vector).norm()
                    <= options.position_tolerance
            );
        }
    }
    assert!(solved >= 48, "solved {solved}/50");
}

#[test]
fn same_seed_same_answer_and_bad_input_is_an_error() {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "right_arm_waist").expect("group");
    let mut rng = Rng::new(9);
    let q = random_configuration(model, &mut rng);
    let target = solver.chain().pose(&q);
    let seed = vec![0.0; model.variable_count()];
    let a = solver
        .solve(&target, &seed, &IkOptions::default())
        .expect("valid");
    let b = solver
        .solve(&target, &seed, &IkOptions::default())
        .expect("valid");
    assert_eq!(a, b);
    assert!(
        solver
            .solve(&target, &[0.0; 3], &IkOptions::default())
            .is_err()
    );
    let mut nan = target;
    nan.translation.vector.x = f64::NAN;
    assert!(solver.solve(&nan, &seed, &IkOptions::default()).is_err());
    assert!(
        IkSolver::for_group(model, semantics, "both_arms").is_err(),
        "no single tip"
    );
    assert!(IkSolver::for_group(model, semantics, "tail").is_err());
}
