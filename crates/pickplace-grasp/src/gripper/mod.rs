//! The parallel gripper as plain parameters, read from the robot's `gripper.toml`.
//!
//! Frames: the tool centre point (TCP) sits midway between the two finger pads, at the pads'
//! centre. Its `approach_axis` points from the palm to the finger tips and its `closing_axis`
//! along the line joining the pads. Inside this crate the gripper is described in its
//! *canonical* frame `G` = (lateral, closing, approach), with lateral = closing × approach, so
//! that `tcp_from_canonical` maps it to the TCP frame of the file.
//!
//! The gripper bodies (all boxes, axis-aligned in `G` except the palm, axis-aligned in TCP):
//! - each finger is `pad_width` (lateral) × `finger_thickness` (closing) × `finger_length`
//!   (approach); its inner face carries the pad, `pad_width` × `pad_depth`, centred on the TCP
//!   along the approach axis, so the finger tips are `pad_depth / 2` beyond the TCP and the
//!   finger roots `finger_length − pad_depth / 2` behind it;
//! - at opening `w` the inner faces are at `±w/2` along the closing axis;
//! - the palm is the box `[palm.min, palm.max]` in TCP coordinates.

mod file;

pub use file::GripperFile;

use crate::error::{Error, Result};
use pickplace_geometry::math::{Matrix3, Point3, Real, Vector3};
use std::path::{Path, PathBuf};

/// A gripper file (`gripper.toml`, or a scene's gripper overrides); default limit 1 MiB.
pub const GRIPPER_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("a gripper file", pickplace_geometry::io::MIB);

/// The palm: an axis-aligned box in the TCP frame.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PalmBox {
    /// Lower corner in the TCP frame (m).
    pub min: Point3,
    /// Upper corner in the TCP frame (m).
    pub max: Point3,
}

impl PalmBox {
    /// Centre in the TCP frame (m).
    pub fn center(&self) -> Point3 {
        nalgebra_center(&self.min, &self.max)
    }

    /// Half side lengths (m).
    pub fn half_extents(&self) -> Vector3 {
        (self.max - self.min) * 0.5
    }
}

fn nalgebra_center(a: &Point3, b: &Point3) -> Point3 {
    Point3::from((a.coords + b.coords) * 0.5)
}

/// A parallel two-finger gripper (the paper's NX-HIRO hand, §III-B.1), in the format of the
/// robot's `gripper.toml` ([`GripperFile`] reads it). All lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GripperParams {
    /// Smallest distance between the pads (m).
    pub opening_min: Real,
    /// Largest distance between the pads (m).
    pub opening_max: Real,
    /// Pad size across the finger, along the lateral axis (m); also the finger's width.
    pub pad_width: Real,
    /// Pad size along the approach axis (m).
    pub pad_depth: Real,
    /// Finger length along the approach axis, from the palm side to the tip (m).
    pub finger_length: Real,
    /// Finger thickness along the closing axis (m).
    pub finger_thickness: Real,
    /// Approach direction (palm to finger tips) in the TCP frame; normalised on use.
    pub approach_axis: Vector3,
    /// Closing direction (the line joining the pads) in the TCP frame; normalised on use.
    pub closing_axis: Vector3,
    /// The palm box in the TCP frame.
    pub palm: PalmBox,
}

/// An oriented box of the gripper, in the TCP frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperBox {
    /// Centre (m).
    pub center: Point3,
    /// Rotation from the box's own axes to the TCP frame (orthonormal, determinant 1).
    pub tcp_from_box: Matrix3,
    /// Half side lengths along the box's own axes (m).
    pub half_extents: Vector3,
}

impl GripperParams {
    /// Parses a full gripper file ([`GripperFile`], the one reader of gripper files);
    /// `path` only names the source in errors.
    ///
    /// # Errors
    /// [`Error::GripperSyntax`] for malformed TOML or unknown keys; [`Error::InvalidGripper`]
    /// for a value missing or out of range (see [`GripperParams::validate`]).
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self> {
        GripperFile::parse(text, path)?.params(path)
    }

    /// Reads and checks a full gripper file.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read, then as [`GripperParams::from_toml_str`].
    pub fn load(path: &Path) -> Result<Self> {
        GripperFile::read(path)?.0.params(path)
    }

    /// Checks every value: finite numbers, `0 ≤ opening_min < opening_max`, positive pad and
    /// finger sizes, `finger_length ≥ pad_depth`, non-zero orthogonal axes, `palm.min < palm.max`.
    ///
    /// # Errors
    /// [`Error::InvalidGripper`] naming the first bad parameter (path `<memory>`).
    pub fn validate(&self) -> Result<()> {
        self.validate_for(Path::new("<memory>"))
    }

    /// As [`GripperParams::validate`], naming `path` (the file the values came from).
    ///
    /// # Errors
    /// [`Error::InvalidGripper`] naming `path` and the first bad parameter.
    pub fn validate_for(&self, path: &Path) -> Result<()> {
        let bad = |field: &'static str, reason: &'static str| Error::InvalidGripper {
            path: PathBuf::from(path),
            field,
            reason,
        };
        let positive = |field: &'static str, v: Real| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(bad(field, "must be a finite positive length"))
            }
        };
        if !(self.opening_min.is_finite() && self.opening_min >= 0.0) {
            return Err(bad("opening_min", "must be finite and non-negative"));
        }
        if !(self.opening_max.is_finite() && self.opening_max > self.opening_min) {
            return Err(bad(
                "opening_max",
                "must be finite and larger than opening_min",
            ));
        }
        positive("pad_width", self.pad_width)?;
        positive("pad_depth", self.pad_depth)?;
        positive("finger_length", self.finger_length)?;
        positive("finger_thickness", self.finger_thickness)?;
        if self.finger_length < self.pad_depth {
            return Err(bad("finger_length", "must be at least pad_depth"));
        }
        for (field, axis) in [
            ("approach_axis", &self.approach_axis),
            ("closing_axis", &self.closing_axis),
        ] {
            if !axis.iter().all(|c| c.is_finite()) || axis.norm() < 1e-9 {
                return Err(bad(field, "must be a finite non-zero vector"));
            }
            // A length that overflows (components near 1e308) would normalise to zero.
            if !axis.norm().is_finite() {
                return Err(bad(field, "is too long: its length overflows"));
            }
        }
        let (a, c) = (
            self.approach_axis.normalize(),
            self.closing_axis.normalize(),
        );
        if a.dot(&c).abs() > 1e-6 {
            return Err(bad("closing_axis", "must be orthogonal to approach_axis"));
        }
        if !self
            .palm
            .min
            .iter()
            .chain(self.palm.max.iter())
            .all(|c| c.is_finite())
        {
            return Err(bad("palm", "corners must be finite"));
        }
        if (0..3).any(|k| self.palm.min[k] >= self.palm.max[k]) {
            return Err(bad("palm", "min must be below max on every axis"));
        }
        Ok(())
    }

    /// Unit approach axis in the TCP frame.
    #[inline]
    pub fn approach(&self) -> Vector3 {
        self.approach_axis.normalize()
    }

    /// Unit closing axis in the TCP frame (made exactly orthogonal to the approach axis).
    #[inline]
    pub fn closing(&self) -> Vector3 {
        let a = self.approach();
        (self.closing_axis - a * a.dot(&self.closing_axis)).normalize()
    }

    /// Unit lateral axis in the TCP frame: closing × approach.
    #[inline]
    pub fn lateral(&self) -> Vector3 {
        self.closing().cross(&self.approach())
    }

    /// Rotation from the canonical frame (lateral, closing, approach) to the TCP frame.
    #[inline]
    pub fn tcp_from_canonical(&self) -> Matrix3 {
        Matrix3::from_columns(&[self.lateral(), self.closing(), self.approach()])
    }

    /// Pad area (m²).
    pub fn pad_area(&self) -> Real {
        self.pad_width * self.pad_depth
    }

    /// The two finger boxes at opening `opening` (m), the first on the `+closing` side.
    #[inline]
    pub fn fingers(&self, opening: Real) -> [GripperBox; 2] {
        let r = self.tcp_from_canonical();
        let half = Vector3::new(
            0.5 * self.pad_width,
            0.5 * self.finger_thickness,
            0.5 * self.finger_length,
        );
        let along = 0.5 * self.pad_depth - 0.5 * self.finger_length;
        let side = 0.5 * opening + 0.5 * self.finger_thickness;
        [1.0, -1.0].map(|s| GripperBox {
            center: Point3::from(r * Vector3::new(0.0, s * side, along)),
            tcp_from_box: r,
            half_extents: half,
        })
    }

    /// The palm box.
    #[inline]
    pub fn palm_box(&self) -> GripperBox {
        GripperBox {
            center: self.palm.center(),
            tcp_from_box: Matrix3::identity(),
            half_extents: self.palm.half_extents(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NX_HIRO: &str = include_str!("../../tests/data/gripper.toml");

    #[test]
    fn parses_the_robot_file() {
        let g = GripperParams::from_toml_str(NX_HIRO, Path::new("gripper.toml")).expect("valid");
        assert_eq!(g.opening_max, 0.08);
        assert_eq!(g.palm.max.z, -0.0475);
        assert!((g.lateral() - Vector3::x()).norm() < 1e-12);
        // The finger roots meet the palm's front face.
        let [f, _] = g.fingers(0.04);
        let root = f.center.z - f.half_extents.z;
        assert!((root - g.palm.max.z).abs() < 1e-12);
        assert!((f.center.y - f.half_extents.y - 0.02).abs() < 1e-12);
    }

    #[test]
    fn unknown_key_and_bad_values_name_the_file_and_field() {
        let extra = format!("{NX_HIRO}\nwrist = 1.0\n").replace("[palm]", "wrist2 = 1\n[palm]");
        let e = GripperParams::from_toml_str(&extra, Path::new("g.toml")).expect_err("unknown key");
        assert!(e.to_string().starts_with("g.toml:"), "{e}");
        let bad = NX_HIRO.replace("opening_max = 0.08", "opening_max = -0.08");
        let e = GripperParams::from_toml_str(&bad, Path::new("g.toml")).expect_err("negative");
        assert!(
            matches!(
                e,
                Error::InvalidGripper {
                    field: "opening_max",
                    ..
                }
            ),
            "{e}"
        );
        let skew = NX_HIRO.replace(
            "closing_axis = [0.0, 1.0, 0.0]",
            "closing_axis = [0.0, 1.0, 1.0]",
        );
        let e = GripperParams::from_toml_str(&skew, Path::new("g.toml")).expect_err("skew");
        assert!(
            matches!(
                e,
                Error::InvalidGripper {
                    field: "closing_axis",
                    ..
                }
            ),
            "{e}"
        );
    }
}
