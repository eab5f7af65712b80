//! The time-optimal timing of a path of waypoints under the joints' limits, shared by the
//! pick-and-place plan ([`crate::planner`]) and motion queries ([`crate::motion`]): the path
//! split where it turns back, its corners blended within a tolerance, each part timed by
//! TOPP-RA ([`pickplace_prm::toppra`]) from rest to rest and sampled; corners whose blends
//! do not hold are tightened and, at last, not blended (the robot stops there, on the path
//! exactly as it was checked).

use crate::error::Result;
use pickplace_geometry::math::Real;
use pickplace_prm::toppra::{self, BlendedPath, ToppraOptions};

/// Times a blend is tightened (the tolerance divided by 4) when what it changed collides or
/// leaves the line, before the segment is timed without blends (a stop at every waypoint).
pub(crate) const BLEND_ATTEMPTS: usize = 3;

/// Fewest grid stages of a timed part of a path.
const MIN_STAGES: Real = 32.0;

/// The plan's samples (times from its start) and, for each, the part of the path and the
/// arc length it is at.
pub(crate) struct Timed {
    /// The samples.
    pub points: Vec<pickplace_prm::TrajectoryPoint>,
    /// For each sample, its part and arc length.
    pub at: Vec<(usize, Real)>,
}

/// The timing's refusal as the façade's error: a trajectory too long to sample is the
/// input's fault ([`crate::Error::TrajectoryLimit`]); anything else is a defect.
pub(crate) fn timing_error(e: pickplace_prm::Error) -> crate::Error {
    match e {
        pickplace_prm::Error::TooManySamples { .. }
        | pickplace_prm::Error::TooManyPoints { .. } => crate::Error::TrajectoryLimit {
            reason: e.to_string(),
        },
        other => crate::error::internal("timing")(other),
    }
}

/// The parts timed one after the other, the robot at rest between them.
pub(crate) fn time_parts(
    parts: &[BlendedPath],
    limits: &ToppraOptions,
    first: Option<&Vec<Real>>,
    n: usize,
) -> Result<Timed> {
    let mut timed = Timed {
        points: Vec::new(),
        at: Vec::new(),
    };
    if let Some(q) = first {
        timed.points.push(pickplace_prm::TrajectoryPoint {
            time_from_start: 0.0,
            positions: q.clone(),
            velocities: vec![0.0; n],
            accelerations: vec![0.0; n],
        });
        timed.at.push((0, 0.0));
    }
    let mut offset = 0.0;
    for (k, part) in parts.iter().enumerate() {
        // At least MIN_STAGES stages on every part, however short (a gripper closing
        // by millimetres): TOPP-RA's speed lives between the grid points.
        let options = ToppraOptions {
            grid_step: limits.grid_step.min(part.length() / MIN_STAGES),
            ..limits.clone()
        };
        let timing = toppra::parameterize(part, &options).map_err(timing_error)?;
        let mut samples =
            toppra::sample(part, &timing, limits.sample_period).map_err(timing_error)?;
        // A last sample within a millisecond of the one before it is merged into it: the
        // times are rounded to the microsecond, which such a step would not survive.
        let m = samples.points.len();
        if m >= 3
            && samples.points[m - 1].time_from_start - samples.points[m - 2].time_from_start < 1e-3
        {
            samples.points.remove(m - 2);
        }
        // Each part's first sample is where the one before ended, at rest.
        for p in samples.points.into_iter().skip(1) {
            timed.at.push((k, timing.state(p.time_from_start).0));
            timed.points.push(pickplace_prm::TrajectoryPoint {
                time_from_start: offset + p.time_from_start,
                ..p
            });
        }
        offset += timing.duration();
    }
    Ok(timed)
}

/// Each part ends at rest exactly at its last waypoint (a grasp, a key pose, a goal), not
/// where the arc length's rounding puts it.
pub(crate) fn snap_part_ends(timed: &mut Timed, parts: &[BlendedPath], waypoints: &[Vec<Real>]) {
    for i in 0..timed.at.len() {
        let k = timed.at[i].0;
        let part_end = timed.at.get(i + 1).is_none_or(|&(next, _)| next != k);
        if part_end
            && let Some(part) = parts.get(k)
            && let (Some(p), Some(q)) = (timed.points.get_mut(i), waypoints.get(part.ends().1))
        {
            p.positions.clone_from(q);
            p.velocities.iter_mut().for_each(|v| *v = 0.0);
        }
    }
}

/// The corners in `failed` tightened: their tolerance divided by 4, or 0 (no blend) once
/// tightened more than [`BLEND_ATTEMPTS`] times.
pub(crate) fn tighten(
    tolerances: &mut [Real],
    tightened: &mut [usize],
    failed: impl IntoIterator<Item = usize>,
) {
    for c in failed {
        tightened[c] += 1;
        tolerances[c] = if tightened[c] > BLEND_ATTEMPTS {
            0.0
        } else {
            tolerances[c] / 4.0
        };
    }
}
