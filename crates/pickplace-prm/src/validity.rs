//! Validity checking: the only link between the planners and the world.

use crate::space::JointSpace;

/// The default `resolution` of every planner in this crate ([`crate::RoadmapOptions`],
/// [`crate::RrtOptions`], [`crate::ShortcutOptions`]): 1° (π/180 rad).
///
/// It equals the project validator's joint step (`pickplace::validate::MAX_JOINT_STEP`, 1° per
/// joint between checked states; this crate cannot depend on the façade, so the value is
/// repeated here). With it, consecutive states that [`motion_valid_by_interpolation`] checks
/// along a segment are at most 1° apart in every joint (max-norm): the density at which the
/// validator re-checks a plan.
pub const DEFAULT_MAX_JOINT_STEP: f64 = std::f64::consts::PI / 180.0;

/// Decides whether states and straight-line motions are valid (collision-free, within limits).
///
/// Implemented for every `Fn(&[f64]) -> bool + Sync` closure. Checkers are shared by the threads
/// of parallel roadmap construction, hence `Sync`.
///
/// The default [`ValidityChecker::is_motion_valid`] samples the segment at a resolution; a checker
/// with a continuous test (swept volumes, conservative advancement) can override it.
pub trait ValidityChecker: Sync {
    /// Whether `state` is valid. `state` has the space's dimension and lies within its bounds.
    fn is_state_valid(&self, state: &[f64]) -> bool;

    /// Whether the straight segment from `from` to `to` is valid. Both ends are assumed to have
    /// been checked already.
    ///
    /// # Arguments
    /// * `resolution` — largest distance between two consecutive checked states (`> 0`), both
    ///   as the space's weighted distance and per joint (max-norm, in the joints' units): see
    ///   [`motion_valid_by_interpolation`]. An override must check at least that densely (or
    ///   continuously) for the planners' guarantees to hold.
    /// * `scratch` — a buffer of the space's dimension, owned by the caller.
    fn is_motion_valid(
        &self,
        space: &JointSpace,
        from: &[f64],
        to: &[f64],
        resolution: f64,
        scratch: &mut [f64],
    ) -> bool {
        motion_valid_by_interpolation(self, space, from, to, resolution, scratch)
    }
}

impl<F> ValidityChecker for F
where
    F: Fn(&[f64]) -> bool + Sync,
{
    #[inline]
    fn is_state_valid(&self, state: &[f64]) -> bool {
        self(state)
    }
}

/// A checker that accepts everything: builds roadmaps for lazy use in any environment.
#[derive(Clone, Copy, Debug, Default)]
pub struct AlwaysValid;

impl ValidityChecker for AlwaysValid {
    #[inline]
    fn is_state_valid(&self, _state: &[f64]) -> bool {
        true
    }

    #[inline]
    fn is_motion_valid(&self, _: &JointSpace, _: &[f64], _: &[f64], _: f64, _: &mut [f64]) -> bool {
        true
    }
}

/// Checks the interior of a segment at `resolution` in bisection (van der Corput) order.
///
/// The segment is cut into `n = max(ceil(distance / resolution), ceil(max_i |to_i - from_i| /
/// resolution))` equal steps, `distance` being the space's weighted distance: consecutive
/// checked states are at most `resolution` apart both in the weighted distance and in every
/// joint (max-norm). For unit weights the weighted bound implies the per-joint one; for a
/// joint of weight `w < 1` the per-joint bound is the tighter (the weighted one alone would let
/// it move `resolution / sqrt(w)`). The `n - 1` interior states are checked coarse to fine (the
/// midpoint first), which finds a collision in a few calls when the segment crosses an
/// obstacle. The ends are not checked. No allocation.
///
/// What is proved is only what was sampled: an obstacle thinner than `resolution` can lie
/// between two checked states. Give the checker a margin (or override
/// [`ValidityChecker::is_motion_valid`] with a continuous test) for more.
///
/// # Performance
/// At most `n - 1` calls of [`ValidityChecker::is_state_valid`]; zero for a segment shorter than
/// `resolution` in both measures.
pub fn motion_valid_by_interpolation<C: ValidityChecker + ?Sized>(
    checker: &C,
    space: &JointSpace,
    from: &[f64],
    to: &[f64],
    resolution: f64,
    scratch: &mut [f64],
) -> bool {
    let distance = space.distance(from, to);
    let joint_step = from
        .iter()
        .zip(to)
        .map(|(a, b)| (b - a).abs())
        .fold(0.0, f64::max);
    if resolution.is_nan() || resolution <= 0.0 || !distance.is_finite() || !joint_step.is_finite()
    {
        return false;
    }
    let steps = (distance / resolution)
        .ceil()
        .max((joint_step / resolution).ceil());
    if steps <= 1.0 {
        return true;
    }
    // Steps beyond u32 would be a misuse (resolution far below the space size): refuse.
    if steps > f64::from(u32::MAX) {
        return false;
    }
    let n = steps as u64;
    let inv = 1.0 / steps;
    let mut stride = n.next_power_of_two() / 2;
    while stride >= 1 {
        let mut k = stride;
        while k < n {
            space.interpolate_into(from, to, k as f64 * inv, scratch);
            if !checker.is_state_valid(scratch) {
                return false;
            }
            k += 2 * stride;
        }
        stride /= 2;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn interpolation_checks_every_interior_state_once() {
        let space = JointSpace::with_unit_weights(vec![0.0], vec![10.0]).expect("space");
        for n in 1..40u64 {
            let seen = std::sync::Mutex::new(Vec::new());
            let checker = |q: &[f64]| {
                seen.lock().expect("lock").push(q[0]);
                true
            };
            let mut scratch = [0.0];
            let to = n as f64 * 0.1;
            assert!(motion_valid_by_interpolation(
                &checker,
                &space,
                &[0.0],
                &[to],
                0.1 + 1e-9,
                &mut scratch
            ));
            let mut seen = seen.into_inner().expect("lock");
            seen.sort_by(f64::total_cmp);
            let expected: Vec<f64> = (1..n).map(|k| k as f64 * to / n as f64).collect();
            assert_eq!(seen.len(), expected.len(), "n = {n}");
            for (a, b) in seen.iter().zip(&expected) {
                assert!((a - b).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn default_step_is_the_validators_degree() {
        assert_eq!(DEFAULT_MAX_JOINT_STEP, std::f64::consts::PI / 180.0);
    }

    /// Counts the interior states checked on `from → to` and returns the largest per-joint
    /// gap between consecutive checked states (ends included).
    fn checked_states(
        space: &JointSpace,
        from: &[f64],
        to: &[f64],
        resolution: f64,
    ) -> (usize, f64) {
        let seen = std::sync::Mutex::new(vec![from.to_vec(), to.to_vec()]);
        let checker = |q: &[f64]| {
            seen.lock().expect("lock").push(q.to_vec());
            true
        };
        let mut scratch = vec![0.0; from.len()];
        assert!(motion_valid_by_interpolation(
            &checker,
            space,
            from,
            to,
            resolution,
            &mut scratch
        ));
        let mut seen = seen.into_inner().expect("lock");
        let count = seen.len() - 2;
        // Order along the segment by the parameter of the joint that moves most.
        let j = (0..from.len())
            .max_by(|&a, &b| (to[a] - from[a]).abs().total_cmp(&(to[b] - from[b]).abs()))
            .expect("joints");
        let sign = (to[j] - from[j]).signum();
        seen.sort_by(|a, b| (sign * a[j]).total_cmp(&(sign * b[j])));
        let gap = seen
            .windows(2)
            .flat_map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| (b - a).abs()))
            .fold(0.0, f64::max);
        (count, gap)
    }

    #[test]
    fn a_light_joint_moves_at_most_the_resolution_between_checked_states() {
        // Weight 0.25: the weighted distance is half the joint's motion.
        let space = JointSpace::new(vec![0.0, 0.0], vec![1.0; 2], vec![1.0, 0.25]).expect("space");
        let (count, gap) = checked_states(&space, &[0.5, 0.0], &[0.5, 1.0], 0.1);
        assert_eq!(count, 9, "ten steps of 0.1 rad, not five of 0.2");
        assert!(gap <= 0.1 + 1e-12, "{gap}");
        // A heavy joint is bounded by the weighted distance, as before.
        let heavy = JointSpace::new(vec![0.0], vec![1.0], vec![4.0]).expect("space");
        assert_eq!(checked_states(&heavy, &[0.0], &[1.0], 0.1).0, 19);
    }

    #[test]
    fn unit_weights_check_what_the_weighted_distance_alone_checked() {
        // For unit weights the per-joint bound never adds a state (the façade's roadmaps).
        let space = JointSpace::with_unit_weights(vec![-3.0; 7], vec![3.0; 7]).expect("space");
        let mut rng = crate::rng::Rng::derive(7, 0, 0);
        let (mut from, mut to) = (vec![0.0; 7], vec![0.0; 7]);
        for _ in 0..200 {
            space.sample_into(&mut rng, &mut from);
            space.sample_into(&mut rng, &mut to);
            for resolution in [0.05, DEFAULT_MAX_JOINT_STEP] {
                let weighted = (space.distance(&from, &to) / resolution).ceil() as usize;
                let (count, gap) = checked_states(&space, &from, &to, resolution);
                assert_eq!(count, weighted.max(1) - 1);
                assert!(gap <= resolution * (1.0 + 1e-12), "{gap} > {resolution}");
            }
        }
    }

    #[test]
    fn coarsest_state_is_checked_first() {
        let space = JointSpace::with_unit_weights(vec![0.0], vec![10.0]).expect("space");
        let calls = AtomicUsize::new(0);
        let checker = |q: &[f64]| {
            calls.fetch_add(1, Ordering::Relaxed);
            (q[0] - 5.12).abs() > 1e-6
        };
        let mut scratch = [0.0];
        assert!(!motion_valid_by_interpolation(
            &checker,
            &space,
            &[0.0],
            &[10.0],
            0.01,
            &mut scratch
        ));
        assert_eq!(calls.load(Ordering::Relaxed), 1);
    }
}
