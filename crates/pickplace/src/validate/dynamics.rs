//! The robot at rest at every event, and velocities and accelerations against the joints'
//! limits between samples.

use super::*;

/// `value` with 4 decimals, or in scientific notation from 1e6 on (1e300 is not 301 digits).
pub(super) fn short_number(value: Real) -> String {
    fmt_real_fixed(value, 4)
}

/// The robot is at rest at every grasp and release (docs/plan-format.md): an event is at a
/// trajectory sample, and from rest a joint whose acceleration is at most its limit `a`
/// ([`Setup::timing`]) moves at most `a h² / 2` in the time `h` to the sample before or
/// after it (5 % and 1e-9 of slack for rounding); where the plan has velocities, they are 0
/// there. Key poses are at trajectory samples; the robot may pass through them moving (a
/// blend between two motions, docs/trajectories.md).
pub(super) fn at_rest_at_events(v: &mut Validator<'_>, plan: &Plan, names: &[&str]) {
    let samples = &plan.trajectory;
    for k in &plan.key_poses {
        if !samples
            .iter()
            .any(|p| (p.time_from_start - k.time).abs() <= 1e-6)
        {
            v.problem(
                k.time,
                format!("key pose {:?} is at no trajectory sample", k.name),
            );
        }
    }
    let stops = plan.events.iter().map(|e| {
        let what = match e.kind {
            EventKind::Grasp => "grasp",
            EventKind::Release => "release",
        };
        (e.time, format!("the {} hand's {what}", e.arm))
    });
    for (time, what) in stops {
        let Some(i) = samples
            .iter()
            .position(|p| (p.time_from_start - time).abs() <= 1e-6)
        else {
            v.problem(time, format!("{what} is at no trajectory sample"));
            continue;
        };
        if let Some((j, speed)) = samples[i]
            .velocities
            .iter()
            .enumerate()
            .map(|(j, s)| (j, s.abs()))
            .find(|&(_, s)| s > 1e-9)
        {
            v.problem(
                time,
                format!(
                    "the robot is not at rest at {what}: {} has velocity {}",
                    names.get(j).copied().unwrap_or("?"),
                    short_number(speed)
                ),
            );
            continue;
        }
        let neighbours = [i.checked_sub(1), Some(i + 1)];
        'sides: for n in neighbours.into_iter().flatten() {
            let Some(other) = samples.get(n) else {
                continue;
            };
            let h = (other.time_from_start - samples[i].time_from_start).abs();
            for (j, (a, b)) in samples[i]
                .positions
                .iter()
                .zip(&other.positions)
                .enumerate()
            {
                let acc = v.setup.timing.get(j).map_or(0.0, |l| l.acceleration);
                let bound = 0.5 * acc * h * h * 1.05 + 1e-9;
                if (a - b).abs() > bound {
                    v.problem(
                        time,
                        format!(
                            "the robot is not at rest at {what}: {} moves {} in the {} s to trajectory[{n}] (at most {} from rest at {} rad/s²)",
                            names.get(j).copied().unwrap_or("?"),
                            short_number((a - b).abs()),
                            short_time(h),
                            short_number(bound),
                            short_number(acc)
                        ),
                    );
                    break 'sides;
                }
            }
        }
    }
}

/// Relative slack of the velocity and acceleration checks (the timing meets its limits at
/// grid points; between them, and through rounding, a little more).
pub const LIMIT_SLACK: Real = 0.02;

/// Velocities and accelerations against the joints' limits ([`Setup::timing`]), where the
/// plan has them (format 2): each sample's values, and between samples the velocity change
/// (`|Δv| / h` at most the acceleration limit) and the position change (the trapezoid rule:
/// `|Δq − h (v₀ + v₁) / 2|` at most `a h² / 4`, exact for piecewise-constant acceleration
/// within one phase and bounded by it across phases). One problem per joint and kind.
pub(super) fn dynamics(v: &mut Validator<'_>, plan: &Plan, names: &[&str]) {
    let timing = v.setup.timing.clone();
    let mut reported = vec![[false; 4]; timing.len()];
    let mut report = |v: &mut Validator<'_>, t: Real, j: usize, kind: usize, what: String| {
        if let Some(r) = reported.get_mut(j)
            && !r[kind]
        {
            r[kind] = true;
            v.problem(
                t,
                format!("{} {what}", names.get(j).copied().unwrap_or("?")),
            );
        }
    };
    let n = timing.len();
    for (i, p) in plan.trajectory.iter().enumerate() {
        if p.velocities.len() != n || p.accelerations.len() != n {
            continue;
        }
        let t = p.time_from_start;
        for (j, l) in timing.iter().enumerate() {
            let (vel, acc) = (p.velocities[j].abs(), p.accelerations[j].abs());
            if vel > l.velocity * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    0,
                    format!(
                        "velocity {} over its limit {}",
                        short_number(vel),
                        short_number(l.velocity)
                    ),
                );
            }
            if acc > l.acceleration * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    1,
                    format!(
                        "acceleration {} over its limit {}",
                        short_number(acc),
                        short_number(l.acceleration)
                    ),
                );
            }
        }
        let Some(next) = plan.trajectory.get(i + 1) else {
            continue;
        };
        if next.velocities.len() != n {
            continue;
        }
        let h = next.time_from_start - t;
        if h <= 0.0 {
            continue;
        }
        for (j, l) in timing.iter().enumerate() {
            let dv = (next.velocities[j] - p.velocities[j]).abs();
            // Times are rounded to the microsecond: h may be 2 µs off.
            if dv > l.acceleration * (h + 2e-6) * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    2,
                    format!(
                        "changes velocity by {} in {} s: more than its acceleration limit {} allows",
                        short_number(dv),
                        short_time(h),
                        short_number(l.acceleration)
                    ),
                );
            }
            let dq = next.positions[j] - p.positions[j];
            let mean = 0.5 * h * (p.velocities[j] + next.velocities[j]);
            let bound =
                0.25 * l.acceleration * h * h * (1.0 + LIMIT_SLACK) + l.velocity * 2e-6 + 1e-7;
            if (dq - mean).abs() > bound {
                report(
                    v,
                    t,
                    j,
                    3,
                    format!(
                        "moves {} in {} s while its velocities say {}: positions and velocities disagree",
                        short_number(dq),
                        short_time(h),
                        short_number(mean)
                    ),
                );
            }
        }
    }
}

/// A time (s) from a plan with 3 decimals, compact when huge (`fmt_real_fixed`).
pub(super) fn short_time(t: Real) -> String {
    fmt_real_fixed(t, 3)
}
