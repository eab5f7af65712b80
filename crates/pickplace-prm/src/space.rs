//! The configuration space: joint bounds and a weighted Euclidean distance.

use crate::error::{Error, Result};
use crate::nn::MAX_DIMENSION;
use crate::rng::Rng;

/// A box-shaped joint space with per-joint distance weights.
///
/// The distance between two states `a` and `b` is `sqrt(Σ w_i (a_i - b_i)²)`, in the units of the
/// joints (radians or metres) scaled by `sqrt(w_i)`. Straight lines in joint space are the local
/// paths of every planner in this crate.
///
/// This is the only thing the planners know of a robot: a planning group's joint limits and how
/// much each joint counts in the distance (e.g. larger weights for shoulder joints).
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpace {
    lower: Vec<f64>,
    upper: Vec<f64>,
    weights: Vec<f64>,
}

impl JointSpace {
    /// Creates a space from joint bounds and distance weights.
    ///
    /// # Errors
    /// [`Error::EmptySpace`], [`Error::SpaceLengths`], [`Error::DimensionTooLarge`] (more than 16
    /// joints), [`Error::InvalidBounds`] (non-finite or `lower > upper`), [`Error::InvalidWeight`]
    /// (non-finite or not positive).
    pub fn new(lower: Vec<f64>, upper: Vec<f64>, weights: Vec<f64>) -> Result<Self> {
        if lower.len() != upper.len() || lower.len() != weights.len() {
            return Err(Error::SpaceLengths {
                lower: lower.len(),
                upper: upper.len(),
                weights: weights.len(),
            });
        }
        if lower.is_empty() {
            return Err(Error::EmptySpace);
        }
        if lower.len() > MAX_DIMENSION {
            return Err(Error::DimensionTooLarge {
                dimension: lower.len(),
                max: MAX_DIMENSION,
            });
        }
        for (joint, (&lo, &hi)) in lower.iter().zip(&upper).enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(Error::InvalidBounds {
                    joint,
                    lower: lo,
                    upper: hi,
                });
            }
        }
        for (joint, &weight) in weights.iter().enumerate() {
            if !(weight.is_finite() && weight > 0.0) {
                return Err(Error::InvalidWeight { joint, weight });
            }
        }
        Ok(Self {
            lower,
            upper,
            weights,
        })
    }

    /// Creates a space with all distance weights equal to one.
    ///
    /// # Errors
    /// As [`JointSpace::new`].
    pub fn with_unit_weights(lower: Vec<f64>, upper: Vec<f64>) -> Result<Self> {
        let weights = vec![1.0; lower.len()];
        Self::new(lower, upper, weights)
    }

    /// Number of joints.
    pub fn dimension(&self) -> usize {
        self.lower.len()
    }

    /// Lower joint bounds.
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper joint bounds.
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// Per-joint distance weights.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Squared weighted distance between two states of this space's dimension.
    #[inline]
    pub fn distance_squared(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.weights)
            .map(|((x, y), w)| w * (x - y) * (x - y))
            .sum()
    }

    /// Weighted distance `sqrt(Σ w_i (a_i - b_i)²)`.
    #[inline]
    pub fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        self.distance_squared(a, b).sqrt()
    }

    /// Writes `a + t (b - a)` into `out`.
    #[inline]
    pub fn interpolate_into(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
            *o = x + t * (y - x);
        }
    }

    /// Whether `state` has the right dimension, is finite and lies within the bounds.
    pub fn contains(&self, state: &[f64]) -> bool {
        self.check_state(state).is_ok()
    }

    /// Checks that `state` has the right dimension, is finite and lies within the bounds.
    ///
    /// # Errors
    /// [`Error::StateDimension`] or [`Error::StateOutOfBounds`].
    pub fn check_state(&self, state: &[f64]) -> Result<()> {
        if state.len() != self.dimension() {
            return Err(Error::StateDimension {
                expected: self.dimension(),
                found: state.len(),
            });
        }
        for (joint, ((&value, &lower), &upper)) in
            state.iter().zip(&self.lower).zip(&self.upper).enumerate()
        {
            if !(value >= lower && value <= upper) {
                return Err(Error::StateOutOfBounds {
                    joint,
                    value,
                    lower,
                    upper,
                });
            }
        }
        Ok(())
    }

    /// Draws a uniform state into `out`.
    #[inline]
    pub(crate) fn sample_into(&self, rng: &mut Rng, out: &mut [f64]) {
        for ((o, lo), hi) in out.iter_mut().zip(&self.lower).zip(&self.upper) {
            *o = lo + rng.next_f64() * (hi - lo);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_distance() {
        let space = JointSpace::new(vec![-1.0; 2], vec![1.0; 2], vec![4.0, 1.0]).expect("space");
        assert!((space.distance(&[0.0, 0.0], &[0.5, 0.0]) - 1.0).abs() < 1e-12);
        assert!((space.distance(&[0.0, 0.0], &[0.0, 0.5]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_spaces() {
        assert!(matches!(
            JointSpace::new(vec![], vec![], vec![]),
            Err(Error::EmptySpace)
        ));
        assert!(matches!(
            JointSpace::new(vec![1.0], vec![0.0], vec![1.0]),
            Err(Error::InvalidBounds { joint: 0, .. })
        ));
        assert!(matches!(
            JointSpace::new(vec![0.0, 0.0], vec![1.0, 1.0], vec![1.0, 0.0]),
            Err(Error::InvalidWeight { joint: 1, .. })
        ));
        assert!(matches!(
            JointSpace::new(vec![0.0], vec![1.0, 1.0], vec![1.0]),
            Err(Error::SpaceLengths { .. })
        ));
        assert!(matches!(
            JointSpace::with_unit_weights(vec![0.0; 17], vec![1.0; 17]),
            Err(Error::DimensionTooLarge { dimension: 17, .. })
        ));
    }

    #[test]
    fn state_checks() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space");
        assert!(space.contains(&[0.5, 1.0]));
        assert!(!space.contains(&[0.5, f64::NAN]));
        assert!(matches!(
            space.check_state(&[0.5]),
            Err(Error::StateDimension {
                expected: 2,
                found: 1
            })
        ));
        assert!(matches!(
            space.check_state(&[1.5, 0.0]),
            Err(Error::StateOutOfBounds { joint: 0, .. })
        ));
    }
}
