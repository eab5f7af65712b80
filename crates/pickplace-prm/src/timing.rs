//! Time parameterization: synchronised trapezoidal velocity profiles, one per segment.
//!
//! Each straight segment is traversed from rest to rest along `q(s) = a + s (b - a)`, with
//! `s(t)` a trapezoidal (or triangular) profile. The profile's limits are the tightest of the
//! joints' (`v_i / |Δ_i|`, `a_i / |Δ_i|`), so all joints start and stop together, the robot stays
//! exactly on the checked straight segment, and no joint exceeds its velocity or acceleration
//! limit. The robot stops at every waypoint (no blending): this keeps the executed motion on the
//! validated path at the cost of time; shortcut the path first to keep waypoints few.

use crate::error::{Error, Result};
use crate::path::Path;

/// Most samples [`time_parameterize`] returns (a million: 2.8 hours of motion at the default
/// period of 0.01 s, some 200 MB for 6 joints). A longer trajectory (a velocity limit of 1e-6
/// rad/s, a tiny period) is refused with [`Error::TooManySamples`] before it is allocated.
pub const MAX_TRAJECTORY_SAMPLES: usize = 1_000_000;

/// Options of [`time_parameterize`].
#[derive(Clone, Debug, PartialEq)]
pub struct TimingOptions {
    /// Per-joint velocity limits, rad/s or m/s (default: empty; must be given, one per joint).
    pub max_velocities: Vec<f64>,
    /// Per-joint acceleration limits, rad/s² or m/s² (default: empty; must be given, one per joint).
    pub max_accelerations: Vec<f64>,
    /// Sampling period of the trajectory, s; waypoints are added between samples (default: 0.01).
    pub sample_period: f64,
}

impl Default for TimingOptions {
    fn default() -> Self {
        Self {
            max_velocities: Vec::new(),
            max_accelerations: Vec::new(),
            sample_period: 0.01,
        }
    }
}

/// One sample of a joint trajectory (as ROS `trajectory_msgs/JointTrajectoryPoint`).
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectoryPoint {
    /// Time since the start of the trajectory, s.
    pub time_from_start: f64,
    /// Joint positions.
    pub positions: Vec<f64>,
    /// Joint velocities.
    pub velocities: Vec<f64>,
    /// Joint accelerations (the value of the phase that begins at this time; at the final point,
    /// of the phase that ends).
    pub accelerations: Vec<f64>,
}

/// A timed joint trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Samples in increasing time, starting at 0 and ending at [`Trajectory::duration`]; every
    /// waypoint of the path appears as a sample.
    pub points: Vec<TrajectoryPoint>,
}

impl Trajectory {
    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p.time_from_start)
    }
}

/// Rest-to-rest profile of `s` from 0 to 1.
#[derive(Clone, Copy, Debug)]
struct Profile {
    start_time: f64,
    accel: f64,
    peak: f64,
    ramp: f64,
    cruise: f64,
}

impl Profile {
    fn new(start_time: f64, v: f64, a: f64) -> Self {
        // Triangle when the peak velocity would be reached after half the distance.
        let (peak, ramp, cruise) = if v * v / a >= 1.0 {
            let ramp = (1.0 / a).sqrt();
            (a * ramp, ramp, 0.0)
        } else {
            let ramp = v / a;
            (v, ramp, (1.0 - v * ramp) / v)
        };
        Self {
            start_time,
            accel: a,
            peak,
            ramp,
            cruise,
        }
    }

    fn duration(&self) -> f64 {
        2.0 * self.ramp + self.cruise
    }

    /// `(s, ds/dt, d²s/dt²)` at local time `t` (the phase that begins at `t`, except at the end).
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        let t = t.clamp(0.0, self.duration());
        let (r, c, a, v) = (self.ramp, self.cruise, self.accel, self.peak);
        if t < r {
            (0.5 * a * t * t, a * t, a)
        } else if t < r + c {
            let s_ramp = 0.5 * a * r * r;
            (s_ramp + v * (t - r), v, 0.0)
        } else {
            let u = (2.0 * r + c - t).max(0.0);
            (1.0 - 0.5 * a * u * u, a * u, -a)
        }
    }
}

/// Times a path with synchronised trapezoidal profiles and samples it.
///
/// # Arguments
/// * `path` — waypoints joined by straight segments (e.g. from [`crate::shortcut()`]).
///
/// # Returns
/// Samples every `sample_period` plus one at each waypoint, with velocities and accelerations.
///
/// # Errors
/// [`Error::EmptyPath`]; [`Error::JointCount`] when a limit list has the wrong length;
/// [`Error::InvalidLimit`] for a non-positive or non-finite limit; [`Error::InvalidOption`] for
/// a non-positive sample period; [`Error::TooManySamples`] when the trajectory would have more
/// than [`MAX_TRAJECTORY_SAMPLES`] samples (checked before any is made).
pub fn time_parameterize(path: &Path, options: &TimingOptions) -> Result<Trajectory> {
    let d = path.dimension();
    if path.is_empty() {
        return Err(Error::EmptyPath);
    }
    check_limits(d, &options.max_velocities, &options.max_accelerations)?;
    if !(options.sample_period > 0.0 && options.sample_period.is_finite()) {
        return Err(Error::InvalidOption {
            name: "sample_period",
            value: options.sample_period,
            expected: "a finite positive period",
        });
    }

    // One profile per segment with motion; zero-length segments take no time.
    let mut segments: Vec<(usize, Profile)> = Vec::new();
    let mut time = 0.0;
    // The joint that sets the pace of the longest segment, for the error message.
    let (mut longest, mut slowest_joint) = (0.0, 0);
    for i in 0..path.len().saturating_sub(1) {
        let (a, b) = (path.waypoint(i), path.waypoint(i + 1));
        let mut v = f64::INFINITY;
        let mut acc = f64::INFINITY;
        let mut pace = 0;
        for j in 0..d {
            let delta = (b[j] - a[j]).abs();
            if delta > 0.0 {
                if options.max_velocities[j] / delta < v {
                    pace = j;
                }
                v = v.min(options.max_velocities[j] / delta);
                acc = acc.min(options.max_accelerations[j] / delta);
            }
        }
        if v.is_finite() {
            let profile = Profile::new(time, v, acc);
            if profile.duration() > longest {
                (longest, slowest_joint) = (profile.duration(), pace);
            }
            time += profile.duration();
            segments.push((i, profile));
        }
    }
    // One sample per period, one per waypoint and the first: bounded before any is made.
    let samples = time / options.sample_period + segments.len() as f64 + 1.0;
    if samples.is_nan() || samples > MAX_TRAJECTORY_SAMPLES as f64 {
        return Err(Error::TooManySamples {
            samples,
            limit: MAX_TRAJECTORY_SAMPLES,
            duration: time,
            sample_period: options.sample_period,
            joint: slowest_joint,
            velocity: options.max_velocities[slowest_joint],
        });
    }

    let point = |time_from_start: f64, segment: Option<&(usize, Profile)>| match segment {
        None => TrajectoryPoint {
            time_from_start,
            positions: path.waypoint(0).to_vec(),
            velocities: vec![0.0; d],
            accelerations: vec![0.0; d],
        },
        Some(&(i, profile)) => {
            let (a, b) = (path.waypoint(i), path.waypoint(i + 1));
            let (s, ds, dds) = profile.eval(time_from_start - profile.start_time);
            TrajectoryPoint {
                time_from_start,
                positions: a.iter().zip(b).map(|(x, y)| x + s * (y - x)).collect(),
                velocities: a.iter().zip(b).map(|(x, y)| ds * (y - x)).collect(),
                accelerations: a.iter().zip(b).map(|(x, y)| dds * (y - x)).collect(),
            }
        }
    };

    let period = options.sample_period;
    let mut points = Vec::with_capacity(samples as usize);
    points.push(point(0.0, segments.first()));
    if segments.is_empty() {
        return Ok(Trajectory { points });
    }
    let epsilon = 1e-9 * period;
    let mut k = 1u64;
    for (index, segment) in segments.iter().enumerate() {
        let end = segment.1.start_time + segment.1.duration();
        loop {
            let t = k as f64 * period;
            if t >= end - epsilon {
                break;
            }
            points.push(point(t, Some(segment)));
            k += 1;
        }
        if (k as f64 * period - end).abs() <= epsilon {
            k += 1;
        }
        // The waypoint at the segment's end: exact position, at rest.
        let mut waypoint = point(end, Some(segment));
        waypoint.positions = path.waypoint(segment.0 + 1).to_vec();
        waypoint.velocities.fill(0.0);
        if let Some(next) = segments.get(index + 1) {
            waypoint.accelerations = point(end, Some(next)).accelerations;
            waypoint.positions = path.waypoint(next.0).to_vec();
        }
        points.push(waypoint);
    }
    Ok(Trajectory { points })
}

/// Checks one positive, finite velocity and acceleration limit per joint of `d`.
///
/// # Errors
/// [`Error::JointCount`] when a list has the wrong length; [`Error::InvalidLimit`] for a
/// non-positive or non-finite limit.
pub(crate) fn check_limits(d: usize, velocities: &[f64], accelerations: &[f64]) -> Result<()> {
    for (what, limits, name) in [
        ("max_velocities", velocities, "velocity"),
        ("max_accelerations", accelerations, "acceleration"),
    ] {
        if limits.len() != d {
            return Err(Error::JointCount {
                what,
                expected: d,
                found: limits.len(),
            });
        }
        if let Some((joint, &value)) = limits
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v > 0.0))
        {
            return Err(Error::InvalidLimit {
                joint,
                limit: name,
                value,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(v: f64, a: f64) -> TimingOptions {
        TimingOptions {
            max_velocities: vec![v; 2],
            max_accelerations: vec![a; 2],
            sample_period: 0.01,
        }
    }

    #[test]
    fn trapezoid_duration_matches_the_formula() {
        // 1 rad at 0.5 rad/s, 1 rad/s²: ramp 0.5 s (0.125 rad each), cruise 1.5 s.
        let path = Path::from_waypoints(2, [[0.0, 0.0], [1.0, 0.0]]).expect("path");
        let trajectory = time_parameterize(&path, &options(0.5, 1.0)).expect("timing");
        assert!((trajectory.duration() - 2.5).abs() < 1e-12);
        let last = trajectory.points.last().expect("points");
        assert_eq!(last.positions, vec![1.0, 0.0]);
        assert_eq!(last.velocities, vec![0.0, 0.0]);
        let middle = &trajectory.points[125];
        assert!((middle.time_from_start - 1.25).abs() < 1e-12);
        assert!((middle.velocities[0] - 0.5).abs() < 1e-12);
        assert!((middle.positions[0] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn triangle_profile_and_synchronised_joints() {
        // Joint 1 moves twice as far: it sets the pace, joint 0 follows at half speed.
        let path = Path::from_waypoints(2, [[0.0, 0.0], [0.1, 0.2]]).expect("path");
        let trajectory = time_parameterize(&path, &options(10.0, 1.0)).expect("timing");
        // Triangle: 2 sqrt(0.2 / 1).
        assert!((trajectory.duration() - 2.0 * 0.2f64.sqrt()).abs() < 1e-12);
        for p in &trajectory.points {
            assert!((p.velocities[1] - 2.0 * p.velocities[0]).abs() < 1e-12);
            assert!(p.accelerations[1].abs() <= 1.0 + 1e-12);
        }
    }

    #[test]
    fn waypoints_are_samples_and_bad_limits_are_rejected() {
        let path = Path::from_waypoints(2, [[0.0, 0.0], [0.3, 0.0], [0.3, 0.0], [0.3, 0.4]])
            .expect("path");
        let trajectory = time_parameterize(&path, &options(1.0, 2.0)).expect("timing");
        for w in [[0.3, 0.0], [0.3, 0.4]] {
            assert!(
                trajectory
                    .points
                    .iter()
                    .any(|p| p.positions == w && p.velocities == [0.0; 2])
            );
        }
        assert!(
            trajectory
                .points
                .windows(2)
                .all(|w| w[1].time_from_start > w[0].time_from_start)
        );
        let bad = TimingOptions {
            max_velocities: vec![1.0, 0.0],
            ..options(1.0, 1.0)
        };
        assert!(matches!(
            time_parameterize(&path, &bad),
            Err(Error::InvalidLimit {
                joint: 1,
                limit: "velocity",
                ..
            })
        ));
        let short = TimingOptions {
            max_accelerations: vec![1.0],
            ..options(1.0, 1.0)
        };
        assert!(matches!(
            time_parameterize(&path, &short),
            Err(Error::JointCount {
                what: "max_accelerations",
                ..
            })
        ));
    }

    #[test]
    fn a_trajectory_beyond_the_sample_limit_is_refused_before_it_is_made() {
        // 1 rad at 1e-6 rad/s: 1e6 s, 1e8 samples (the 2.6 GB of issue 18).
        let path = Path::from_waypoints(2, [[0.0, 0.0], [0.0, 1.0]]).expect("path");
        let slow = TimingOptions {
            max_velocities: vec![1.0, 1e-6],
            ..options(1.0, 1.0)
        };
        let e = time_parameterize(&path, &slow).expect_err("too long");
        assert!(
            matches!(
                e,
                Error::TooManySamples {
                    joint: 1,
                    limit: MAX_TRAJECTORY_SAMPLES,
                    ..
                }
            ),
            "{e:?}"
        );
        let message = e.to_string();
        assert!(message.contains("1000000"), "{message}");
        assert!(message.contains("joint 1"), "{message}");
        // Just under the limit: 9999.9 s at 0.01 s.
        let limit = TimingOptions {
            max_velocities: vec![1.0, 1.0 / 9_000.0],
            max_accelerations: vec![1.0; 2],
            sample_period: 0.01,
        };
        let t = time_parameterize(&path, &limit).expect("under the limit");
        assert!(t.points.len() <= MAX_TRAJECTORY_SAMPLES);
        assert!(t.points.len() > 900_000);
        // A tiny period counts as well.
        let fine = TimingOptions {
            sample_period: 1e-9,
            ..options(1.0, 1.0)
        };
        assert!(matches!(
            time_parameterize(&path, &fine),
            Err(Error::TooManySamples { .. })
        ));
    }
}
