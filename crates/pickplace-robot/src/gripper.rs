//! Parallel-gripper parameters, read from a small TOML file beside the URDF
//! (`robots/nx-hiro/gripper.toml`).
//!
//! The grasp planner treats the gripper as plain parameters (Harada et al., §III-C: two
//! parallel fingers whose pads must both lie on a pair of parallel clusters).

use crate::error::{Error, Result, memory_path};
use pickplace_geometry::math::Real;
use std::path::Path;

/// A box given by its minimum and maximum corners in the TCP frame (m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxBounds {
    /// Minimum corner.
    pub min: [Real; 3],
    /// Maximum corner.
    pub max: [Real; 3],
}

/// Parameters of a parallel gripper. Frames: the TCP frame sits midway between the finger
/// pads, at the pads' centre.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GripperConfig {
    /// Smallest distance between the pads (m).
    pub opening_min: Real,
    /// Largest distance between the pads (m).
    pub opening_max: Real,
    /// Pad width, across the closing direction and the approach (m).
    pub pad_width: Real,
    /// Pad depth, along the approach (m).
    pub pad_depth: Real,
    /// Finger length from the palm to the finger tip, along the approach (m).
    pub finger_length: Real,
    /// Finger thickness along the closing direction (m).
    pub finger_thickness: Real,
    /// The palm (hand body) in the TCP frame.
    pub palm: BoxBounds,
    /// Approach direction in the TCP frame (unit vector, points from the palm to the finger
    /// tips).
    pub approach_axis: [Real; 3],
    /// Closing direction in the TCP frame (unit vector, along which the fingers move).
    pub closing_axis: [Real; 3],
}

impl GripperConfig {
    /// Reads and validates a gripper file.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::GripperConfig`] (unknown key, missing key, bad value).
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates TOML text.
    ///
    /// # Errors
    /// [`Error::GripperConfig`] with the path `<memory>`.
    pub fn from_toml_str(text: &str) -> Result<Self> {
        Self::parse(text, &memory_path())
    }

    fn parse(text: &str, path: &Path) -> Result<Self> {
        let config: Self = toml::from_str(text).map_err(|e| Error::GripperConfig {
            path: path.to_path_buf(),
            detail: e.to_string(),
        })?;
        config.validate().map_err(|detail| Error::GripperConfig {
            path: path.to_path_buf(),
            detail: detail.to_owned(),
        })?;
        Ok(config)
    }

    fn validate(&self) -> std::result::Result<(), &'static str> {
        let all = [
            self.opening_min,
            self.opening_max,
            self.pad_width,
            self.pad_depth,
            self.finger_length,
            self.finger_thickness,
        ];
        if all
            .iter()
            .chain(self.palm.min.iter())
            .chain(self.palm.max.iter())
            .any(|v| !v.is_finite())
        {
            return Err("every value must be finite");
        }
        if self.opening_min < 0.0 || self.opening_min > self.opening_max {
            return Err("need 0 <= opening_min <= opening_max");
        }
        if self.pad_width <= 0.0
            || self.pad_depth <= 0.0
            || self.finger_length <= 0.0
            || self.finger_thickness <= 0.0
        {
            return Err("pad and finger sizes must be positive");
        }
        if (0..3).any(|i| self.palm.min[i] >= self.palm.max[i]) {
            return Err("palm min must be below palm max on every axis");
        }
        let norm = |v: &[Real; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let dot = |a: &[Real; 3], b: &[Real; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        if (norm(&self.approach_axis) - 1.0).abs() > 1e-6
            || (norm(&self.closing_axis) - 1.0).abs() > 1e-6
        {
            return Err("approach_axis and closing_axis must be unit vectors");
        }
        if dot(&self.approach_axis, &self.closing_axis).abs() > 1e-6 {
            return Err("approach_axis and closing_axis must be perpendicular");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NX: &str = include_str!("../../../robots/nx-hiro/gripper.toml");

    #[test]
    fn shipped_gripper_file_parses() {
        let g = GripperConfig::from_toml_str(NX).expect("shipped file is valid");
        assert_eq!(g.opening_max, 0.08);
        assert_eq!(g.approach_axis, [0.0, 0.0, 1.0]);
    }

    #[test]
    fn unknown_keys_and_bad_values_are_errors() {
        let extra = format!("{NX}\nwheels = 4\n");
        let e = GripperConfig::from_toml_str(&extra).expect_err("unknown key");
        assert!(e.to_string().contains("wheels"), "{e}");
        let inverted = NX.replace("opening_min = 0.0", "opening_min = 0.09");
        let e = GripperConfig::from_toml_str(&inverted).expect_err("min > max");
        assert!(e.to_string().contains("opening_min"), "{e}");
    }
}
