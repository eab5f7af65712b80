//! The range of every number a user gives the planner: a scene's fields, the command line's
//! flags, the Python package's keywords and [`crate::PlanOptions`] (issue 33). Each is
//! checked where it enters, against the one constant here, and refused with a message that
//! names the field; a value in range can neither overflow a conversion (a time budget of
//! `1e300` s is no [`std::time::Duration`]) nor underflow a computation (a squared velocity
//! limit of `1e-300`).
//!
//! The bounds are generous: they refuse only what no robot cell needs (a plan budget over a
//! week, a pose 10 km from the origin, a mesh scaled by more than a million).

use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::Real;
use std::fmt;

/// A closed or half-open interval of allowed values, with its unit for messages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// The smallest value (allowed unless `min_excluded`).
    pub min: Real,
    /// The largest allowed value.
    pub max: Real,
    /// Whether `min` itself is refused (`(min, max]`).
    pub min_excluded: bool,
    /// The unit, `""` for a pure number.
    pub unit: &'static str,
}

impl Range {
    /// `[min, max]`.
    pub const fn closed(min: Real, max: Real, unit: &'static str) -> Self {
        Self {
            min,
            max,
            min_excluded: false,
            unit,
        }
    }

    /// `(min, max]`.
    pub const fn above(min: Real, max: Real, unit: &'static str) -> Self {
        Self {
            min,
            max,
            min_excluded: true,
            unit,
        }
    }

    /// Whether `value` lies in the range (NaN never does).
    pub fn contains(&self, value: Real) -> bool {
        let low = if self.min_excluded {
            value > self.min
        } else {
            value >= self.min
        };
        low && value <= self.max
    }

    /// `Ok` when `value` lies in the range.
    ///
    /// # Errors
    /// [`OutOfRange`]: the value (printed compactly) and the range.
    pub fn check(&self, value: Real) -> Result<(), OutOfRange> {
        if self.contains(value) {
            Ok(())
        } else {
            Err(OutOfRange {
                value,
                range: *self,
            })
        }
    }

    /// As [`Range::check`] for a count.
    ///
    /// # Errors
    /// [`OutOfRange`].
    pub fn check_count(&self, value: usize) -> Result<(), OutOfRange> {
        self.check(value as Real)
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let open = if self.min_excluded { '(' } else { '[' };
        write!(f, "{open}{}, {}]", fmt_real(self.min), fmt_real(self.max))?;
        if !self.unit.is_empty() {
            write!(f, " {}", self.unit)?;
        }
        Ok(())
    }
}

/// A value outside its [`Range`].
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("{} is not in {range}", fmt_real(*value))]
pub struct OutOfRange {
    /// The value given.
    pub value: Real,
    /// Where it must lie.
    pub range: Range,
}

/// Reads a command-line flag's number and checks its range (for `clap`'s `value_parser`).
///
/// # Errors
/// [`FlagError`]: not a number, or out of range.
pub fn parse_flag(text: &str, range: Range) -> Result<Real, FlagError> {
    let value: Real = text
        .trim()
        .parse()
        .map_err(|_| FlagError::NotANumber(text.chars().take(40).collect()))?;
    range.check(value)?;
    Ok(value)
}

/// Why a flag's value was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlagError {
    /// The text is no number.
    #[error("{0:?} is not a number")]
    NotANumber(String),
    /// The number is out of range.
    #[error(transparent)]
    OutOfRange(#[from] OutOfRange),
}

/// A plan's wall-clock budget (s): from nothing (plan nothing, say so) to a week.
pub const TIME_BUDGET: Range = Range::closed(0.0, 604_800.0, "s");
/// A velocity or acceleration scaling factor (MoveIt's; slower than a thousandth of the
/// limits is no motion a cell waits for).
pub const SCALING: Range = Range::closed(0.001, 1.0, "");
/// A trajectory's sampling period (s): finer would make huge files, coarser would hide
/// motion.
pub const SAMPLE_PERIOD: Range = Range::closed(0.001, 1.0, "s");
/// A coordinate of a position or point (m).
pub const COORDINATE: Range = Range::closed(-10_000.0, 10_000.0, "m");
/// A primitive's size (box side, radius, length).
pub const SHAPE_SIZE: Range = Range::above(0.0, 1e4, "m");
/// A mesh's scale factor (0.001 for millimetres).
pub const MESH_SCALE: Range = Range::closed(1e-6, 1e6, "");
/// An object's mass (kg).
pub const MASS: Range = Range::above(0.0, 1e6, "kg");
/// The clusters' thickness h_max (m) (the paper's 1 mm and 5 mm lie well inside).
pub const H_MAX: Range = Range::closed(1e-6, 0.5, "m");
/// How far from the target point a placement may lie (m).
pub const TARGET_TOLERANCE: Range = Range::above(0.0, 100.0, "m");
/// A joint's velocity limit (rad/s or m/s): below the minimum, its square underflows the
/// time-optimal parameterization and no motion could be sampled within
/// [`pickplace_prm::MAX_TRAJECTORY_SAMPLES`] samples anyway.
pub const JOINT_VELOCITY: Range = Range::closed(1e-4, 1e7, "rad/s or m/s");
/// A joint's acceleration limit (rad/s² or m/s²).
pub const JOINT_ACCELERATION: Range = Range::closed(1e-4, 1e6, "rad/s² or m/s²");
/// Configurations sampled for a collision matrix.
pub const MATRIX_SAMPLES: Range = Range::closed(1.0, 10_000_000.0, "samples");
/// The "usually in collision" fraction of a sampled collision matrix.
pub const COLLISION_FRACTION: Range = Range::above(0.0, 1.0, "");
/// A joint value of a start state (rad or m).
pub const JOINT_VALUE: Range = Range::closed(-1e4, 1e4, "rad or m");
/// A planner distance option (m): approach distance, lift height, margins, steps.
pub const PLANNER_DISTANCE: Range = Range::closed(0.0, 10.0, "m");
/// A planner angle option (rad): joint steps, blend tolerance.
pub const PLANNER_ANGLE: Range = Range::closed(0.0, std::f64::consts::PI, "rad");

/// The grasp planner's grid of grasp centres (m).
pub const GRID_STEP: Range = Range::closed(1e-4, 1.0, "m");
/// The grasp planner's clearance between the gripper and the object (m).
pub const CLEARANCE: Range = Range::closed(0.0, 0.1, "m");
/// Approach directions about each grasp axis.
pub const APPROACHES: Range = Range::closed(1.0, 360.0, "");
/// Threads of a batch.
pub const THREADS: Range = Range::closed(1.0, 4096.0, "threads");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_and_messages() {
        assert!(TIME_BUDGET.contains(0.0) && TIME_BUDGET.contains(604_800.0));
        assert!(!TIME_BUDGET.contains(1e300) && !TIME_BUDGET.contains(Real::NAN));
        assert!(!SCALING.contains(0.0) && SCALING.contains(1.0));
        assert!(!TIME_BUDGET.contains(-0.0 - 1e-300));
        let e = TIME_BUDGET.check(1e300).unwrap_err().to_string();
        assert_eq!(e, "1e300 is not in [0, 604800] s");
        let e = SCALING.check(5e-320).unwrap_err().to_string();
        assert_eq!(e, "5e-320 is not in [0.001, 1]");
        let e = MASS.check(0.0).unwrap_err().to_string();
        assert_eq!(e, "0 is not in (0, 1e6] kg");
        assert!(parse_flag(" 0.5 ", SCALING).is_ok());
        assert_eq!(
            parse_flag("x", SCALING).unwrap_err().to_string(),
            "\"x\" is not a number"
        );
    }
}
