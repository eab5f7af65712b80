//! Validity checking: the only link between the planners and the world.

use crate::space::JointSpace;

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
    /// * `resolution` — largest weighted distance between two checked states (`> 0`).
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
/// The segment is cut into `n = ceil(distance / resolution)` equal steps; the `n - 1` interior
/// states are checked coarse to fine (the midpoint first), which finds a collision in a few calls
/// when the segment crosses an obstacle. The ends are not checked. No allocation.
///
/// # Performance
/// At most `n - 1` calls of [`ValidityChecker::is_state_valid`]; zero for a segment shorter than
/// `resolution`.
pub fn motion_valid_by_interpolation<C: ValidityChecker + ?Sized>(
    checker: &C,
    space: &JointSpace,
    from: &[f64],
    to: &[f64],
    resolution: f64,
    scratch: &mut [f64],
) -> bool {
    let distance = space.distance(from, to);
    if resolution.is_nan() || resolution <= 0.0 || !distance.is_finite() {
        return false;
    }
    let steps = (distance / resolution).ceil();
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
