//! The grasp planner's options and their checks.

use crate::error::{Error, Result};
use pickplace_geometry::math::Real;

/// Options of the grasp planner.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GraspOptions {
    /// Spacing of the grid of grasp centres over each pair's overlap region (m)
    /// (default: 0.01; the paper's ref. \[15\] used 0.02).
    pub grid_step: Real,
    /// Number of approach directions, evenly spaced about the grasp axis (default: 8, i.e.
    /// every 45°).
    pub approach_count: usize,
    /// Also try every pose turned by 180° about the approach axis, which swaps the fingers and
    /// mirrors an asymmetric palm (default: true).
    pub flip_closing: bool,
    /// Clearance the gripper keeps from the object (m): the fingers are checked open by this
    /// much on each side and grown by it along their other axes, the palm grown by it on every
    /// side; the opening must reach `width + 2 · clearance` (default: 0.002).
    pub clearance: Real,
    /// Smallest fraction of the pad area that must lie on both clusters (default: 0.5).
    pub min_contact_ratio: Real,
    /// The boundary margin at which the margin term of the score saturates (m)
    /// (default: 0.01).
    pub margin_scale: Real,
    /// Weight of the contact term in the score (default: 0.5).
    pub contact_weight: Real,
    /// Weight of the torque term in the score (default: 0.3).
    pub torque_weight: Real,
    /// Weight of the margin term in the score (default: 0.2).
    pub margin_weight: Real,
}

impl Default for GraspOptions {
    fn default() -> Self {
        Self {
            grid_step: 0.01,
            approach_count: 8,
            flip_closing: true,
            clearance: 0.002,
            min_contact_ratio: 0.5,
            margin_scale: 0.01,
            contact_weight: 0.5,
            torque_weight: 0.3,
            margin_weight: 0.2,
        }
    }
}

impl GraspOptions {
    /// Checks every value.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        let check = |name: &'static str, value: Real, ok: bool, reason: &'static str| {
            if ok {
                Ok(())
            } else {
                Err(Error::InvalidOption {
                    name,
                    value,
                    reason,
                })
            }
        };
        check(
            "grid_step",
            self.grid_step,
            self.grid_step.is_finite() && self.grid_step >= 1e-4,
            "must be at least 0.1 mm",
        )?;
        check(
            "approach_count",
            self.approach_count as Real,
            (1..=360).contains(&self.approach_count),
            "must be in 1..=360",
        )?;
        check(
            "clearance",
            self.clearance,
            self.clearance.is_finite() && self.clearance >= 0.0,
            "must be finite and non-negative",
        )?;
        check(
            "min_contact_ratio",
            self.min_contact_ratio,
            (0.0..=1.0).contains(&self.min_contact_ratio),
            "must be in [0, 1]",
        )?;
        check(
            "margin_scale",
            self.margin_scale,
            self.margin_scale.is_finite() && self.margin_scale > 0.0,
            "must be positive",
        )?;
        for (name, w) in [
            ("contact_weight", self.contact_weight),
            ("torque_weight", self.torque_weight),
            ("margin_weight", self.margin_weight),
        ] {
            check(
                name,
                w,
                w.is_finite() && w >= 0.0,
                "must be finite and non-negative",
            )?;
        }
        let sum = self.contact_weight + self.torque_weight + self.margin_weight;
        check(
            "contact_weight",
            self.contact_weight,
            sum > 0.0,
            "the three weights must not all be zero",
        )
    }
}
