//! Robot model benchmarks (issue 4): forward kinematics, Jacobians, IK (ours and the `k`
//! crate's Jacobian IK on the same URDF and targets) and the collision check of the full
//! NX-HIRO against the pallet scene.
//!
//! Before the criterion groups run, the IK success rate and per-solve median over 10 000
//! random reachable poses (FK of random configurations) of the right arm with the waist are
//! measured for both solvers and printed (this is the acceptance check).

use criterion::{Criterion, criterion_group, criterion_main};
use k::InverseKinematicsSolver as _;
use pickplace_benches::{add_pallet_scene, nx_hiro, repo};
use pickplace_geometry::math::{Isometry3, Point3};
use pickplace_prm::rng::Rng;
use pickplace_robot::collision::{
    AllowedCollisionMatrix, CheckOptions, CollisionScratch, CollisionWorld,
};
use pickplace_robot::kinematics::Jacobian;
use pickplace_robot::{IkOptions, IkSolver, RobotModel, Semantics};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

const GROUP: &str = "right_arm_waist";
const POSES: usize = 10_000;

fn urdf_path() -> PathBuf {
    repo().join("robots/nx-hiro/nx-hiro.urdf")
}

fn load() -> (RobotModel, Semantics) {
    nx_hiro()
}

fn random_configurations(model: &RobotModel, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| {
            model
                .variable_limits()
                .map(|l| rng.uniform(l.lower, l.upper))
                .collect()
        })
        .collect()
}

fn home(model: &RobotModel, semantics: &Semantics) -> Vec<f64> {
    let mut q = model.zero_configuration();
    semantics
        .apply_state(model, "home", &mut q)
        .expect("home exists");
    q
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The pallet scene: a table top box and `meshes/pallet.stl` on it in front of the robot.
fn pallet_world(model: &RobotModel, semantics: &Semantics) -> CollisionWorld {
    let mut world = CollisionWorld::new(model, AllowedCollisionMatrix::from_srdf(semantics.srdf()))
        .expect("valid robot shapes");
    add_pallet_scene(&mut world);
    world
}

/// The solver's chain variables of the full configuration `seed`, in chain order (the `k`
/// chain's joint order).
fn chain_seed(solver: &IkSolver, seed: &[f64]) -> Vec<f64> {
    solver
        .chain()
        .variables()
        .iter()
        .map(|&v| seed[v])
        .collect()
}

/// The `k` crate's chain for the same group: from `RARM_TCP_JOINT` to the root (7 joints,
/// waist first).
struct KArm {
    arm: k::SerialChain<f64>,
    solver: k::JacobianIkSolver<f64>,
}

impl KArm {
    fn new() -> Self {
        let chain = k::Chain::<f64>::from_urdf_file(urdf_path()).expect("k reads the URDF");
        let end = chain.find("RARM_TCP_JOINT").expect("TCP joint");
        let arm = k::SerialChain::from_end(end);
        // Same tolerances as ours (1e-4 m, 1e-3 rad); k's step multiplier 0.5, 100 iterations.
        let solver = k::JacobianIkSolver::new(1e-4, 1e-3, 0.5, 100);
        Self { arm, solver }
    }

    fn target(pose: &Isometry3) -> k::Isometry3<f64> {
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        k::Isometry3::from_parts(
            k::Translation3::new(t.x, t.y, t.z),
            k::UnitQuaternion::from_quaternion(k::nalgebra::Quaternion::new(q.w, q.x, q.y, q.z)),
        )
    }

    fn solve(&self, seed: &[f64], target: &k::Isometry3<f64>) -> bool {
        self.arm.set_joint_positions_clamped(seed);
        self.solver.solve(&self.arm, target).is_ok()
    }
}

/// The acceptance check, printed: success rate and per-solve median of both solvers.
fn ik_acceptance(model: &RobotModel, semantics: &Semantics) {
    let solver = IkSolver::for_group(model, semantics, GROUP).expect("group");
    let seed = home(model, semantics);
    let targets: Vec<Isometry3> = random_configurations(model, POSES, 7)
        .iter()
        .map(|q| solver.chain().pose(q))
        .collect();
    let options = IkOptions::default();
    let (mut ok, mut times) = (0, Vec::with_capacity(POSES));
    for target in &targets {
        let start = Instant::now();
        let s = solver.solve(target, &seed, &options).expect("valid input");
        times.push(start.elapsed().as_secs_f64());
        ok += usize::from(s.success);
    }
    let ours = median(times);
    let k_arm = KArm::new();
    let k_seed = chain_seed(&solver, &seed);
    let (mut k_ok, mut k_times) = (0, Vec::with_capacity(POSES));
    for target in &targets {
        let t = KArm::target(target);
        let start = Instant::now();
        let success = k_arm.solve(&k_seed, &t);
        k_times.push(start.elapsed().as_secs_f64());
        k_ok += usize::from(success);
    }
    let theirs = median(k_times);
    println!(
        "IK {GROUP}, {POSES} random reachable poses from home: pickplace {:.2}% solved, median \
         {:.1} µs; k JacobianIkSolver {:.2}% solved, median {:.1} µs; k/pickplace median ratio {:.2}",
        100.0 * ok as f64 / POSES as f64,
        ours * 1e6,
        100.0 * k_ok as f64 / POSES as f64,
        theirs * 1e6,
        theirs / ours
    );
}

fn bench_kinematics(c: &mut Criterion) {
    let (model, semantics) = load();
    let configurations = random_configurations(&model, 1024, 1);
    let mut poses = vec![Isometry3::identity(); model.links().len()];
    let mut i = 0;
    c.bench_function("robot/fk_all_links", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            model
                .forward_kinematics(black_box(&configurations[i]), &mut poses)
                .expect("lengths match");
            black_box(&poses);
        });
    });
    let chain = semantics.chain(&model, GROUP).expect("group");
    let mut jacobian = Jacobian::zeros(chain.variables().len());
    c.bench_function("robot/jacobian_tcp_right_arm_waist", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            black_box(chain.pose_and_jacobian(black_box(&configurations[i]), &mut jacobian));
        });
    });
    let tip = chain.tip_link();
    let variables = chain.variables().to_vec();
    c.bench_function("robot/jacobian_model_any_link", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            model
                .jacobian(
                    black_box(&configurations[i]),
                    tip,
                    &Point3::origin(),
                    &variables,
                    &mut jacobian,
                )
                .expect("valid");
        });
    });
    let k_arm = KArm::new();
    let k_configurations: Vec<Vec<f64>> = configurations
        .iter()
        .map(|q| variables.iter().map(|&v| q[v]).collect())
        .collect();
    c.bench_function("robot/k_fk_and_jacobian_right_arm_waist", |b| {
        b.iter(|| {
            i = (i + 1) % k_configurations.len();
            k_arm
                .arm
                .set_joint_positions_unchecked(&k_configurations[i]);
            black_box(k::jacobian(&k_arm.arm));
        });
    });
}

fn bench_ik(c: &mut Criterion) {
    let (model, semantics) = load();
    ik_acceptance(&model, &semantics);
    let solver = IkSolver::for_group(&model, &semantics, GROUP).expect("group");
    let seed = home(&model, &semantics);
    let targets: Vec<Isometry3> = random_configurations(&model, 1024, 9)
        .iter()
        .map(|q| solver.chain().pose(q))
        .collect();
    let options = IkOptions::default();
    let mut i = 0;
    let mut group = c.benchmark_group("robot/ik_right_arm_waist");
    group.bench_function("pickplace", |b| {
        b.iter(|| {
            i = (i + 1) % targets.len();
            black_box(solver.solve(&targets[i], &seed, &options).expect("valid"));
        });
    });
    let k_arm = KArm::new();
    let k_seed = chain_seed(&solver, &seed);
    let k_targets: Vec<_> = targets.iter().map(KArm::target).collect();
    group.bench_function("k_jacobian_ik", |b| {
        b.iter(|| {
            i = (i + 1) % k_targets.len();
            black_box(k_arm.solve(&k_seed, &k_targets[i]));
        });
    });
    group.finish();
}

fn bench_collision(c: &mut Criterion) {
    let (model, semantics) = load();
    let world = pallet_world(&model, &semantics);
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions { margin: 0.01 };
    // Random configurations, and the collision-free ones among them (the full check with
    // no early exit: the planner's common case).
    let all = random_configurations(&model, 4096, 3);
    let free: Vec<Vec<f64>> = all
        .iter()
        .filter(|q| {
            !world
                .in_collision(&model, q, &mut scratch, &options)
                .expect("valid")
        })
        .cloned()
        .collect();
    println!(
        "collision: {} of {} random configurations are free (margin 1 cm), {} self pairs \
         checked",
        free.len(),
        all.len(),
        world.self_pair_count()
    );
    let mut group = c.benchmark_group("robot/collision_pallet_scene");
    for (name, set) in [
        ("free_configurations", &free),
        ("random_configurations", &all),
    ] {
        let mut i = 0;
        group.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) % set.len();
                black_box(
                    world
                        .in_collision(&model, black_box(&set[i]), &mut scratch, &options)
                        .expect("valid"),
                )
            });
        });
    }
    let mut i = 0;
    let touching = CheckOptions { margin: 0.0 };
    group.bench_function("free_configurations_no_margin", |b| {
        b.iter(|| {
            i = (i + 1) % free.len();
            black_box(
                world
                    .in_collision(&model, black_box(&free[i]), &mut scratch, &touching)
                    .expect("valid"),
            )
        });
    });
    group.bench_function("min_distance_free", |b| {
        b.iter(|| {
            i = (i + 1) % free.len();
            black_box(
                world
                    .min_distance(&model, &free[i], &mut scratch)
                    .expect("valid"),
            )
        });
    });
    group.finish();
}

criterion_group!(benches, bench_kinematics, bench_ik, bench_collision);
criterion_main!(benches);
