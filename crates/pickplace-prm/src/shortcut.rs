//! Path shortcutting: seeded random shortcuts, then removal of redundant waypoints.

use crate::error::{Error, Result};
use crate::path::Path;
use crate::rng::{Rng, stream};
use crate::space::JointSpace;
use crate::validity::{DEFAULT_MAX_JOINT_STEP, ValidityChecker};

/// Options of [`shortcut`].
#[derive(Clone, Debug, PartialEq)]
pub struct ShortcutOptions {
    /// Random shortcut attempts (default: 100).
    pub attempts: usize,
    /// Largest distance between two consecutive checked states on a shortcut, both as a
    /// weighted distance and per joint (max-norm, joint units; see
    /// [`crate::motion_valid_by_interpolation`]) (default: [`DEFAULT_MAX_JOINT_STEP`], 1°,
    /// the validator's joint step). A coarser value is faster but proves only the states
    /// sampled that far apart on the new segments.
    pub resolution: f64,
    /// Seed of the random shortcut choices (default: 0).
    pub seed: u64,
}

impl Default for ShortcutOptions {
    fn default() -> Self {
        Self {
            attempts: 100,
            resolution: DEFAULT_MAX_JOINT_STEP,
            seed: 0,
        }
    }
}

/// Shortens a valid path by random shortcuts.
///
/// Each attempt picks two random points along the path (by arc length, on different segments)
/// and replaces the part between them by a straight segment when that segment is valid and
/// shorter. A final pass drops every waypoint whose neighbours can be joined directly. The
/// metric is a norm, so no step lengthens the path; the ends never move.
///
/// # Guarantee
/// Every new segment (a shortcut, or a join of the final pass) was accepted by
/// [`ValidityChecker::is_motion_valid`] at `options.resolution`, every new waypoint by
/// [`ValidityChecker::is_state_valid`]. A shortcut's end splits one of `path`'s segments: the
/// piece kept is not checked again, its checked states are the old segment's plus the new end,
/// so they are as far apart as `path`'s were. With the defaults ([`DEFAULT_MAX_JOINT_STEP`])
/// and a path from [`crate::rrt_connect`] or [`crate::PrmPlanner::query`] at their default
/// resolution, the checked states along every segment of the result are at most 1° apart per
/// joint (max-norm). (Sampling the piece afresh, e.g. by [`Path::is_valid`], puts samples
/// elsewhere: it can find an obstacle thinner than the resolution that both sets straddle.)
///
/// # Errors
/// [`Error::StateDimension`] when the path's dimension is not the space's; [`Error::EmptyPath`];
/// [`Error::InvalidOption`] for a non-positive resolution.
pub fn shortcut<C: ValidityChecker + ?Sized>(
    space: &JointSpace,
    checker: &C,
    path: &Path,
    options: &ShortcutOptions,
) -> Result<Path> {
    let d = space.dimension();
    if path.dimension() != d {
        return Err(Error::StateDimension {
            expected: d,
            found: path.dimension(),
        });
    }
    if path.is_empty() {
        return Err(Error::EmptyPath);
    }
    if !(options.resolution > 0.0 && options.resolution.is_finite()) {
        return Err(Error::InvalidOption {
            name: "resolution",
            value: options.resolution,
            expected: "a finite positive distance",
        });
    }
    let mut states: Vec<f64> = path.as_flat().to_vec();
    let mut next: Vec<f64> = Vec::with_capacity(states.len());
    let mut cumulative: Vec<f64> = Vec::new();
    let mut scratch = vec![0.0; d];
    let mut p1 = vec![0.0; d];
    let mut p2 = vec![0.0; d];
    let mut rng = Rng::derive(options.seed, stream::SHORTCUT, 0);
    let wp = |i: usize| -> std::ops::Range<usize> { i * d..(i + 1) * d };

    for _ in 0..options.attempts {
        let count = states.len() / d;
        if count < 3 {
            break;
        }
        cumulative.clear();
        cumulative.push(0.0);
        for i in 1..count {
            let step = space.distance(&states[wp(i - 1)], &states[wp(i)]);
            cumulative.push(cumulative[i - 1] + step);
        }
        let total = cumulative[count - 1];
        let (mut s1, mut s2) = (rng.next_f64() * total, rng.next_f64() * total);
        if s1 > s2 {
            std::mem::swap(&mut s1, &mut s2);
        }
        // Segment i spans cumulative[i]..cumulative[i + 1].
        let segment = |s: f64| cumulative[1..].partition_point(|&c| c < s).min(count - 2);
        let (i1, i2) = (segment(s1), segment(s2));
        if i1 == i2 {
            continue;
        }
        let point = |i: usize, s: f64, out: &mut [f64]| {
            let length = cumulative[i + 1] - cumulative[i];
            let t = if length > 0.0 {
                ((s - cumulative[i]) / length).clamp(0.0, 1.0)
            } else {
                0.0
            };
            space.interpolate_into(&states[wp(i)], &states[wp(i + 1)], t, out);
        };
        point(i1, s1, &mut p1);
        point(i2, s2, &mut p2);
        let direct = space.distance(&p1, &p2);
        if direct >= (s2 - s1) - 1e-12 {
            continue;
        }
        if !(checker.is_state_valid(&p1)
            && checker.is_state_valid(&p2)
            && checker.is_motion_valid(space, &p1, &p2, options.resolution, &mut scratch))
        {
            continue;
        }
        next.clear();
        next.extend_from_slice(&states[..(i1 + 1) * d]);
        next.extend_from_slice(&p1);
        next.extend_from_slice(&p2);
        next.extend_from_slice(&states[(i2 + 1) * d..]);
        dedup_consecutive(&mut next, d);
        std::mem::swap(&mut states, &mut next);
    }

    // Drop waypoints whose neighbours see each other.
    let mut i = 1;
    while (i + 1) * d < states.len() {
        let (a, b) = (&states[wp(i - 1)], &states[wp(i + 1)]);
        if checker.is_motion_valid(space, a, b, options.resolution, &mut scratch) {
            states.drain(i * d..(i + 1) * d);
        } else {
            i += 1;
        }
    }
    Path::from_waypoints(d, states.chunks_exact(d))
}

/// Removes consecutive duplicate waypoints.
fn dedup_consecutive(states: &mut Vec<f64>, d: usize) {
    let mut write = 1usize;
    let count = states.len() / d;
    for read in 1..count {
        if states[read * d..(read + 1) * d] != states[(write - 1) * d..write * d] {
            if read != write {
                states.copy_within(read * d..(read + 1) * d, write * d);
            }
            write += 1;
        }
    }
    states.truncate(write * d);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zigzag_in_free_space_becomes_straight() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space");
        let path = Path::from_waypoints(
            2,
            [
                [0.0, 0.0],
                [0.2, 0.5],
                [0.4, 0.0],
                [0.6, 0.5],
                [0.8, 0.0],
                [1.0, 0.5],
            ],
        )
        .expect("path");
        let free = |_: &[f64]| true;
        let short = shortcut(&space, &free, &path, &ShortcutOptions::default()).expect("shortcut");
        assert_eq!(short.len(), 2);
        assert_eq!(short.waypoint(0), path.waypoint(0));
        assert_eq!(short.waypoint(1), path.waypoint(5));
    }

    #[test]
    fn keeps_the_corner_around_an_obstacle() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space");
        let block = |q: &[f64]| !((0.4..0.6).contains(&q[0]) && q[1] < 0.7);
        let path = Path::from_waypoints(
            2,
            [[0.1, 0.1], [0.1, 0.9], [0.5, 0.9], [0.9, 0.9], [0.9, 0.1]],
        )
        .expect("path");
        let options = ShortcutOptions {
            resolution: 0.001,
            ..ShortcutOptions::default()
        };
        let short = shortcut(&space, &block, &path, &options).expect("shortcut");
        assert!(short.length(&space) < path.length(&space));
        assert!(short.len() >= 3);
        assert!(short.is_valid(&space, &block, 0.001));
    }

    #[test]
    fn dedup_removes_repeats() {
        let mut states = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 2.0];
        dedup_consecutive(&mut states, 2);
        assert_eq!(states, vec![0.0, 0.0, 1.0, 1.0, 2.0, 2.0]);
    }
}
