//! Paths: sequences of waypoints joined by straight segments in joint space.

use crate::error::{Error, Result};
use crate::space::JointSpace;
use crate::validity::ValidityChecker;

/// A piecewise-linear path in joint space, stored flat (`dimension` coordinates per waypoint).
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    dimension: usize,
    states: Vec<f64>,
}

impl Path {
    /// An empty path in a space of `dimension` joints.
    pub fn new(dimension: usize) -> Self {
        Self {
            dimension,
            states: Vec::new(),
        }
    }

    /// A path through `waypoints`.
    ///
    /// # Errors
    /// [`Error::StateDimension`] when a waypoint does not have `dimension` coordinates.
    pub fn from_waypoints<I, W>(dimension: usize, waypoints: I) -> Result<Self>
    where
        I: IntoIterator<Item = W>,
        W: AsRef<[f64]>,
    {
        let mut path = Self::new(dimension);
        for waypoint in waypoints {
            let waypoint = waypoint.as_ref();
            if waypoint.len() != dimension {
                return Err(Error::StateDimension {
                    expected: dimension,
                    found: waypoint.len(),
                });
            }
            path.states.extend_from_slice(waypoint);
        }
        Ok(path)
    }

    /// Appends a waypoint of the path's dimension (caller guarantees the length).
    pub(crate) fn push_unchecked(&mut self, state: &[f64]) {
        debug_assert_eq!(state.len(), self.dimension);
        self.states.extend_from_slice(state);
    }

    /// Number of joints.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// Number of waypoints.
    pub fn len(&self) -> usize {
        self.states.len().checked_div(self.dimension).unwrap_or(0)
    }

    /// Whether the path has no waypoint.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// Waypoint `i` (panics when `i >= len()`, like slice indexing).
    pub fn waypoint(&self, i: usize) -> &[f64] {
        &self.states[i * self.dimension..(i + 1) * self.dimension]
    }

    /// Iterator over the waypoints.
    pub fn waypoints(&self) -> std::slice::ChunksExact<'_, f64> {
        self.states.chunks_exact(self.dimension.max(1))
    }

    /// All coordinates, waypoint after waypoint.
    pub fn as_flat(&self) -> &[f64] {
        &self.states
    }

    /// Sum of the weighted lengths of the segments.
    pub fn length(&self, space: &JointSpace) -> f64 {
        self.waypoints()
            .zip(self.waypoints().skip(1))
            .map(|(a, b)| space.distance(a, b))
            .sum()
    }

    /// Whether every waypoint is in bounds and valid and every segment is valid at `resolution`.
    ///
    /// Used to re-check plans (e.g. at a finer resolution than the planner's).
    pub fn is_valid<C: ValidityChecker + ?Sized>(
        &self,
        space: &JointSpace,
        checker: &C,
        resolution: f64,
    ) -> bool {
        if self.dimension != space.dimension() || self.is_empty() {
            return false;
        }
        if !self
            .waypoints()
            .all(|w| space.contains(w) && checker.is_state_valid(w))
        {
            return false;
        }
        let mut scratch = vec![0.0; self.dimension];
        self.waypoints()
            .zip(self.waypoints().skip(1))
            .all(|(a, b)| checker.is_motion_valid(space, a, b, resolution, &mut scratch))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_and_access() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![10.0; 2]).expect("space");
        let path = Path::from_waypoints(2, [[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]).expect("path");
        assert_eq!(path.len(), 3);
        assert_eq!(path.waypoint(1), &[3.0, 4.0]);
        assert!((path.length(&space) - 6.0).abs() < 1e-12);
        assert!(matches!(
            Path::from_waypoints(2, [vec![0.0]]),
            Err(Error::StateDimension {
                expected: 2,
                found: 1
            })
        ));
    }

    #[test]
    fn validity_recheck_detects_a_blocked_segment() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![10.0; 2]).expect("space");
        let wall = |q: &[f64]| !(4.9..5.1).contains(&q[0]);
        let through = Path::from_waypoints(2, [[0.0, 0.0], [10.0, 0.0]]).expect("path");
        let beside = Path::from_waypoints(2, [[0.0, 0.0], [4.0, 9.0]]).expect("path");
        assert!(!through.is_valid(&space, &wall, 0.05));
        assert!(beside.is_valid(&space, &wall, 0.05));
    }
}
