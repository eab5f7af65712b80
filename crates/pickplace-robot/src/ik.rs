//! Inverse kinematics of a group's TCP: damped least squares with adaptive
//! (Levenberg–Marquardt) damping, joint limits (clamping plus an active set: a joint held at
//! a limit leaves the system), a per-step trust region, seeded random restarts and an optional free
//! rotation about a tool axis (a parallel gripper's symmetry).
//!
//! The pick-and-place planner (Harada et al., §IV: "the inverse kinematics is solved for
//! each candidate grasp and placement") calls this for every key pose, so one solve must be
//! cheap: the update works on the 6 × 6 system `(J Jᵀ + λ I) y = e`, `Δq = Jᵀ y`, which is on
//! the stack whatever the group's size.

use crate::error::{Error, Result};
use crate::kinematics::{Jacobian, KinematicChain};
use crate::model::RobotModel;
use crate::rng::Rng;
use crate::srdf::Semantics;
use pickplace_geometry::math::nalgebra::{Matrix6, Vector6};
use pickplace_geometry::math::{Isometry3, Matrix3, Real, UnitVector3, Vector3};

/// Options of [`IkSolver::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Largest accepted TCP position error (m) (default: 1e-4).
    pub position_tolerance: Real,
    /// Largest accepted TCP orientation error (rad) (default: 1e-3).
    pub orientation_tolerance: Real,
    /// Iterations per attempt (default: 60).
    pub max_iterations: usize,
    /// Random restarts after the attempt from the seed (default: 100).
    pub max_restarts: usize,
    /// Seed of the random restarts (default: 0).
    pub seed: u64,
    /// Weight of the orientation error against the position error (m/rad) (default: 0.3).
    pub orientation_weight: Real,
    /// When set, rotation about this axis of the TCP frame is free: only the axis' direction
    /// must match the target's (default: None).
    pub free_axis: Option<UnitVector3>,
    /// When the attempt from the seed fails, how many restart solutions to collect before
    /// returning the one nearest the seed (default: 1).
    pub restart_candidates: usize,
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-4,
            orientation_tolerance: 1e-3,
            max_iterations: 60,
            max_restarts: 100,
            seed: 0,
            orientation_weight: 0.3,
            free_axis: None,
            restart_candidates: 1,
        }
    }
}

/// The result of an IK solve.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    /// True when both tolerances are met.
    pub success: bool,
    /// All variables of the model (those outside the group as in the seed): the solution,
    /// or the best configuration found when `success` is false.
    pub positions: Vec<Real>,
    /// TCP position error (m).
    pub position_error: Real,
    /// TCP orientation error (rad); with a free axis, the angle between the axes.
    pub orientation_error: Real,
    /// Attempts made (1 + restarts).
    pub attempts: usize,
    /// Iterations summed over attempts.
    pub iterations: usize,
}

/// An IK solver for one chain (a group and its TCP). Immutable and `Send + Sync`.
#[derive(Debug, Clone)]
pub struct IkSolver {
    chain: KinematicChain,
    /// (lower, upper) of each chain variable; continuous joints have ±∞.
    limits: Vec<(Real, Real)>,
    variable_count: usize,
}

impl IkSolver {
    /// A solver for `chain`.
    pub fn new(model: &RobotModel, chain: KinematicChain) -> Self {
        let limits = chain
            .variables()
            .iter()
            .map(|&v| {
                let l = model.variable_joint(v).limits;
                (l.lower, l.upper)
            })
            .collect();
        Self {
            chain,
            limits,
            variable_count: model.variable_count(),
        }
    }

    /// A solver for an SRDF group's tip link (its TCP link).
    ///
    /// # Errors
    /// [`Error::UnknownGroup`] or [`Error::GroupWithoutTip`].
    pub fn for_group(model: &RobotModel, semantics: &Semantics, group: &str) -> Result<Self> {
        Ok(Self::new(model, semantics.chain(model, group)?))
    }

    /// The chain solved for.
    pub fn chain(&self) -> &KinematicChain {
        &self.chain
    }

    /// Solves for `root_from_tcp = target`, starting from `seed`.
    ///
    /// # Arguments
    /// * `target`: the TCP pose in the root frame.
    /// * `seed`: all variables of the model; the group's are the starting point, the others
    ///   are held fixed.
    ///
    /// # Returns
    /// The solution nearest the seed among those found: the attempt from the seed is made
    /// first; when it fails, random restarts (seeded by `options.seed`) run until
    /// `options.restart_candidates` solutions are found or `options.max_restarts` are spent.
    /// `success` is false when no attempt met the tolerances.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for the seed, [`Error::InvalidParameter`] for a non-finite
    /// target or a non-positive tolerance.
    pub fn solve(
        &self,
        target: &Isometry3,
        seed: &[Real],
        options: &IkOptions,
    ) -> Result<IkSolution> {
        if seed.len() != self.variable_count {
            return Err(Error::WrongLength {
                what: "IK seed",
                expected: self.variable_count,
                found: seed.len(),
            });
        }
        let t = target.translation.vector;
        let r = target.rotation.coords;
        if !(t.iter().chain(r.iter()).all(|x| x.is_finite())) {
            return Err(Error::InvalidParameter {
                name: "IK target",
                value: Real::NAN,
                reason: "the target pose must be finite",
            });
        }
        for (name, value) in [
            ("position_tolerance", options.position_tolerance),
            ("orientation_tolerance", options.orientation_tolerance),
            ("orientation_weight", options.orientation_weight),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    reason: "must be positive and finite",
                });
            }
        }
        let mut workspace = Workspace {
            jacobian: Jacobian::zeros(self.chain.variables().len()),
            step: Vec::with_capacity(self.chain.variables().len()),
        };
        let mut q = seed.to_vec();
        let mut iterations = 0;
        let first = self.attempt(target, &mut q, options, &mut workspace, &mut iterations);
        if first.0 {
            return Ok(IkSolution {
                success: true,
                positions: q,
                position_error: first.1,
                orientation_error: first.2,
                attempts: 1,
                iterations,
            });
        }
        let mut best_failure = (
            first.1 + options.orientation_weight * first.2,
            q.clone(),
            first.1,
            first.2,
        );
        let mut best_success: Option<(Real, Vec<Real>, Real, Real)> = None;
        let mut found = 0;
        let mut rng = Rng::new(options.seed);
        let mut attempts = 1;
        for _ in 0..options.max_restarts {
            attempts += 1;
            q.copy_from_slice(seed);
            for (c, &v) in self.chain.variables().iter().enumerate() {
                let (lower, upper) = self.limits[c];
                let (lower, upper) = if lower.is_finite() && upper.is_finite() {
                    (lower, upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                q[v] = rng.uniform(lower, upper);
            }
            let (ok, pe, oe) =
                self.attempt(target, &mut q, options, &mut workspace, &mut iterations);
            if ok {
                let d = self.distance(&q, seed);
                if best_success.as_ref().is_none_or(|b| d < b.0) {
                    best_success = Some((d, q.clone(), pe, oe));
                }
                found += 1;
                if found >= options.restart_candidates.max(1) {
                    break;
                }
            } else {
                let score = pe + options.orientation_weight * oe;
                if score < best_failure.0 {
                    best_failure = (score, q.clone(), pe, oe);
                }
            }
        }
        Ok(match best_success {
            Some((_, positions, pe, oe)) => IkSolution {
                success: true,
                positions,
                position_error: pe,
                orientation_error: oe,
                attempts,
                iterations,
            },
            None => IkSolution {
                success: false,
                positions: best_failure.1,
                position_error: best_failure.2,
                orientation_error: best_failure.3,
                attempts,
                iterations,
            },
        })
    }

    fn distance(&self, q: &[Real], seed: &[Real]) -> Real {
        self.chain
            .variables()
            .iter()
            .map(|&v| (q[v] - seed[v]).powi(2))
            .sum()
    }

    /// The TCP errors of `q` against `target`: (position error, orientation error) and the
    /// weighted 6-vector (world frame).
    fn error(
        &self,
        tcp: &Isometry3,
        target: &Isometry3,
        options: &IkOptions,
    ) -> (Vector6<Real>, Real, Real, Option<Vector3>) {
        let dp = target.translation.vector - tcp.translation.vector;
        let (rot, angle, axis_now) = match options.free_axis {
            None => {
                let rot = (target.rotation * tcp.rotation.inverse()).scaled_axis();
                let angle = rot.norm();
                (rot, angle, None)
            }
            Some(axis) => {
                let now = tcp.rotation * axis.into_inner();
                let want = target.rotation * axis.into_inner();
                let cross = now.cross(&want);
                let sin = cross.norm();
                let cos = now.dot(&want);
                let angle = sin.atan2(cos);
                let rot = if sin > 1e-12 {
                    cross * (angle / sin)
                } else if cos > 0.0 {
                    Vector3::zeros()
                } else {
                    // Opposite axes: turn about any perpendicular.
                    let perpendicular = if now.x.abs() < 0.9 {
                        Vector3::x()
                    } else {
                        Vector3::y()
                    };
                    now.cross(&perpendicular).normalize() * angle
                };
                (rot, angle, Some(now))
            }
        };
        let w = options.orientation_weight;
        let e = Vector6::new(dp.x, dp.y, dp.z, w * rot.x, w * rot.y, w * rot.z);
        (e, dp.norm(), angle, axis_now)
    }

    /// One damped least-squares descent from `q`. Returns (converged, position error,
    /// orientation error).
    fn attempt(
        &self,
        target: &Isometry3,
        q: &mut [Real],
        options: &IkOptions,
        workspace: &mut Workspace,
        iterations: &mut usize,
    ) -> (bool, Real, Real) {
        let w = options.orientation_weight;
        let mut tcp = self.chain.pose_and_jacobian(q, &mut workspace.jacobian);
        let (mut e, mut pe, mut oe, mut axis_now) = self.error(&tcp, target, options);
        let mut best_norm = e.norm_squared();
        let mut since_improvement = 0;
        for _ in 0..options.max_iterations {
            if pe <= options.position_tolerance && oe <= options.orientation_tolerance {
                return (true, pe, oe);
            }
            *iterations += 1;
            let j = &mut workspace.jacobian;
            // Weight the angular rows; with a free axis, drop the component about it.
            let projector = axis_now.map(|a| Matrix3::identity() - a * a.transpose());
            for mut col in j.column_iter_mut() {
                let mut angular = Vector3::new(col[3], col[4], col[5]);
                if let Some(p) = &projector {
                    angular = p * angular;
                }
                col[3] = w * angular.x;
                col[4] = w * angular.y;
                col[5] = w * angular.z;
            }
            // Adaptive damping (Sugihara 2011): λ = ½‖e‖² + λ₀.
            let lambda = 0.5 * e.norm_squared() + 1e-6;
            // Active set: a joint at a limit whose step would push it further out is
            // taken out of the system (its column zeroed) and the step solved again, so
            // the other joints do the work instead of losing it to the clamp.
            let dq = &mut workspace.step;
            let mut solved = false;
            for _ in 0..3 {
                // J Jᵀ + λI and Jᵀ y by hand: a 6 x 6 product over a handful of columns,
                // where the general product's packing and allocations cost more than the
                // arithmetic.
                let mut a = Matrix6::<Real>::zeros();
                for col in j.column_iter() {
                    for r in 0..6 {
                        for c in 0..=r {
                            a[(r, c)] += col[r] * col[c];
                        }
                    }
                }
                for r in 0..6 {
                    a[(r, r)] += lambda;
                    for c in 0..r {
                        a[(c, r)] = a[(r, c)];
                    }
                }
                let Some(cholesky) = a.cholesky() else { break };
                let y = cholesky.solve(&e);
                dq.clear();
                dq.extend(j.column_iter().map(|col| col.dot(&y)));
                solved = true;
                let mut locked_any = false;
                for (c, &v) in self.chain.variables().iter().enumerate() {
                    let (lower, upper) = self.limits[c];
                    let outward = (q[v] <= lower && dq[c] < 0.0) || (q[v] >= upper && dq[c] > 0.0);
                    if outward && j.column(c).iter().any(|x| *x != 0.0) {
                        j.column_mut(c).fill(0.0);
                        locked_any = true;
                    }
                }
                if !locked_any {
                    break;
                }
            }
            if !solved {
                break;
            }
            // Keep each step within a trust region (rad or m per joint) so that a far
            // target does not throw the joints across their range in one step.
            let largest = dq.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
            if largest > MAX_STEP {
                let scale = MAX_STEP / largest;
                dq.iter_mut().for_each(|x| *x *= scale);
            }
            for (c, &v) in self.chain.variables().iter().enumerate() {
                let (lower, upper) = self.limits[c];
                q[v] = if lower.is_finite() || upper.is_finite() {
                    (q[v] + dq[c]).clamp(lower, upper)
                } else {
                    // A continuous joint: the angle wrapped into [−π, π), where the motion
                    // planner's joint space is.
                    wrap_angle(q[v] + dq[c])
                };
            }
            tcp = self.chain.pose_and_jacobian(q, &mut workspace.jacobian);
            (e, pe, oe, axis_now) = self.error(&tcp, target, options);
            let n = e.norm_squared();
            if n < best_norm * 0.98 {
                best_norm = n;
                since_improvement = 0;
            } else {
                since_improvement += 1;
                if since_improvement >= 8 {
                    break;
                }
            }
        }
        (
            pe <= options.position_tolerance && oe <= options.orientation_tolerance,
            pe,
            oe,
        )
    }
}

/// Largest change of one joint in one iteration (rad or m).
const MAX_STEP: Real = 0.5;

#[derive(Debug)]
struct Workspace {
    jacobian: Jacobian,
    /// The joint step of an iteration.
    step: Vec<Real>,
}

/// `angle` wrapped into [−π, π).
fn wrap_angle(angle: Real) -> Real {
    let tau = std::f64::consts::TAU;
    let wrapped = (angle + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
    if wrapped.is_finite() { wrapped } else { 0.0 }
}
