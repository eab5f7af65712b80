//! The robot's `gripper.toml` as written: the workspace's one reader of gripper files.
//!
//! Every field is optional. A full file (the grasp model's nine values: openings, pads,
//! fingers, axes, palm) is a [`GripperParams`] ([`GripperFile::params`]; `pickplace grasps
//! --gripper`); a scene's `robot.gripper` names the same kind of file, whose values override
//! what the façade measures on the URDF, with `squeeze` and `tool_offset` for that
//! measuring.

use super::{GRIPPER_FILE, GripperParams, PalmBox};
use crate::error::{Error, Result};
use pickplace_geometry::math::{Real, Vector3};
use serde::de::Deserializer;
use std::path::Path;

/// A gripper file's values, each `None` when the file does not give it.
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GripperFile {
    /// Smallest distance between the pads the grasp planner uses (m).
    pub opening_min: Option<Real>,
    /// Largest distance between the pads (m).
    pub opening_max: Option<Real>,
    /// Pad size across the finger (m).
    pub pad_width: Option<Real>,
    /// Pad size along the approach axis (m): the distal part of the fingers.
    pub pad_depth: Option<Real>,
    /// Finger length for the grasp planner's model (m).
    pub finger_length: Option<Real>,
    /// Finger thickness for the grasp planner's model (m).
    pub finger_thickness: Option<Real>,
    /// Approach direction (palm to finger tips) in the tool frame.
    #[serde(default, deserialize_with = "approach_axis")]
    pub approach_axis: Option<[Real; 3]>,
    /// Closing direction (the line joining the pads) in the tool frame.
    #[serde(default, deserialize_with = "closing_axis")]
    pub closing_axis: Option<[Real; 3]>,
    /// The palm box in the tool frame.
    pub palm: Option<PalmBox>,
    /// Squeeze (m): how much narrower than the grasp width the pads are commanded (a robot's
    /// measured gripper only).
    pub squeeze: Option<Real>,
    /// The tool point's offset in the measured tool frame (m) (a robot's measured gripper
    /// only).
    #[serde(default, deserialize_with = "tool_offset")]
    pub tool_offset: Option<[Real; 3]>,
}

fn approach_axis<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
    pickplace_geometry::exact::optional_xyz(d, "approach_axis")
}

fn closing_axis<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
    pickplace_geometry::exact::optional_xyz(d, "closing_axis")
}

fn tool_offset<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
    pickplace_geometry::exact::optional_xyz(d, "tool_offset")
}

impl GripperFile {
    /// Parses a gripper file's text; `path` only names the source in errors.
    ///
    /// # Errors
    /// [`Error::GripperSyntax`] for malformed TOML, unknown keys and arrays of the wrong length
    /// (line and column, never a quoted line of the file).
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        toml::from_str(text).map_err(|e| Error::GripperSyntax {
            path: path.to_path_buf(),
            message: pickplace_geometry::io::parse_error(
                text,
                e.span().map(|s| s.start),
                e.message(),
            ),
        })
    }

    /// Reads a gripper file (at most [`GRIPPER_FILE`]'s limit); its text is returned too, for
    /// messages that point at a line.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read, then as [`GripperFile::parse`].
    pub fn read(path: &Path) -> Result<(Self, String)> {
        let text =
            pickplace_geometry::io::read_text(path, GRIPPER_FILE).map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Ok((Self::parse(&text, path)?, text))
    }

    /// The grasp model of a full file, checked ([`GripperParams::validate_for`]).
    ///
    /// # Errors
    /// [`Error::InvalidGripper`] naming `path` and the first value missing or out of range.
    pub fn params(&self, path: &Path) -> Result<GripperParams> {
        let missing = |field: &'static str| Error::InvalidGripper {
            path: path.to_path_buf(),
            field,
            reason: "is missing: a gripper file for the grasp planner gives every value of the model",
        };
        let given = |v: Option<Real>, field: &'static str| v.ok_or_else(|| missing(field));
        let axis = |v: Option<[Real; 3]>, field: &'static str| {
            v.map(Vector3::from).ok_or_else(|| missing(field))
        };
        let params = GripperParams {
            opening_min: given(self.opening_min, "opening_min")?,
            opening_max: given(self.opening_max, "opening_max")?,
            pad_width: given(self.pad_width, "pad_width")?,
            pad_depth: given(self.pad_depth, "pad_depth")?,
            finger_length: given(self.finger_length, "finger_length")?,
            finger_thickness: given(self.finger_thickness, "finger_thickness")?,
            approach_axis: axis(self.approach_axis, "approach_axis")?,
            closing_axis: axis(self.closing_axis, "closing_axis")?,
            palm: self.palm.ok_or_else(|| missing("palm"))?,
        };
        params.validate_for(path)?;
        Ok(params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NX_HIRO: &str = include_str!("../../tests/data/gripper.toml");

    #[test]
    fn a_partial_file_reads_and_a_full_one_is_the_model() {
        let path = Path::new("g.toml");
        let f = GripperFile::parse("squeeze = 0.002\ntool_offset = [0, 0, 0.01]\n", path)
            .expect("partial");
        assert_eq!(f.squeeze, Some(0.002));
        assert_eq!(f.tool_offset, Some([0.0, 0.0, 0.01]));
        assert!(f.params(path).is_err());
        let full = GripperFile::parse(NX_HIRO, path).expect("full");
        assert_eq!(full.params(path).expect("model").opening_max, 0.08);
    }

    #[test]
    fn arrays_of_the_wrong_length_and_missing_values_are_named() {
        let path = Path::new("g.toml");
        let e = GripperFile::parse("tool_offset = [0, 0, 0.01, 5]\n", path).expect_err("4");
        assert!(e.to_string().contains("tool_offset"), "{e}");
        let text = NX_HIRO.replace("pad_width = 0.02\n", "");
        let e = GripperFile::parse(&text, path)
            .expect("parses")
            .params(path)
            .expect_err("missing");
        assert!(
            matches!(
                e,
                Error::InvalidGripper {
                    field: "pad_width",
                    ..
                }
            ),
            "{e}"
        );
    }
}
