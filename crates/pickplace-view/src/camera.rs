//! Cameras: look-at pose, perspective or orthographic projection, and framing of bounds.

use crate::error::{Error, Result};
use pickplace_geometry::math::{Point3, Real, Vector3};

/// How a camera projects the scene onto the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Pinhole projection.
    Perspective {
        /// Vertical field of view (rad), in (0, π).
        fov_y: Real,
    },
    /// Parallel projection.
    Orthographic {
        /// Half the height of the visible region (m).
        half_height: Real,
    },
}

/// A camera looking from `eye` at `target`, with `up` giving the image's upward direction.
///
/// The camera frame is x to the right of the image, y up, z towards the viewer (OpenGL
/// convention); the camera looks along -z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Position of the eye in the world (m).
    pub eye: Point3,
    /// Point looked at, in the world (m); it appears at the image centre.
    pub target: Point3,
    /// World direction that appears upwards; need not be orthogonal to the view direction. When
    /// parallel to it, world +z is used, or +y if that is parallel too.
    pub up: Vector3,
    /// The projection.
    pub projection: Projection,
    /// Distance from the eye (m) in front of which nothing is drawn; triangles crossing it are
    /// clipped.
    pub near: Real,
}

/// Vertical field of view of the cameras made by [`Camera::look_at`] and [`Camera::fit`]
/// (rad): 40°.
pub const DEFAULT_FOV_Y: Real = 40.0 * std::f64::consts::PI / 180.0;

/// A view direction from the front-right and above (world z up), good for objects on a table
/// in front of a robot looking along +x.
pub const OBLIQUE_VIEW: Vector3 = Vector3::new(-0.62, -0.55, -0.56);

impl Camera {
    /// A perspective camera with a [`DEFAULT_FOV_Y`] field of view and `near` a thousandth of
    /// the eye–target distance.
    pub fn look_at(eye: Point3, target: Point3, up: Vector3) -> Self {
        let near = ((target - eye).norm() * 1e-3).max(1e-6);
        Self {
            eye,
            target,
            up,
            projection: Projection::Perspective {
                fov_y: DEFAULT_FOV_Y,
            },
            near,
        }
    }

    /// A perspective camera looking along `view_direction` that shows the whole box
    /// `bounds = (min, max)` in an image at least as wide as it is tall (for taller images use
    /// [`Camera::fit_with_aspect`]). Up is world +z (+y when looking along z).
    pub fn fit(bounds: (Point3, Point3), view_direction: Vector3) -> Self {
        Self::fit_with_aspect(bounds, view_direction, 1.0)
    }

    /// As [`Camera::fit`] for images of `aspect = width / height`. A zero or non-finite
    /// `view_direction` is replaced by [`OBLIQUE_VIEW`].
    pub fn fit_with_aspect(
        bounds: (Point3, Point3),
        view_direction: Vector3,
        aspect: Real,
    ) -> Self {
        let (lo, hi) = bounds;
        let centre = Point3::from((lo.coords + hi.coords) * 0.5);
        let radius = ((hi - lo).norm() * 0.5).max(1e-6);
        let direction = view_direction
            .try_normalize(1e-12)
            .filter(|d| d.iter().all(|c| c.is_finite()))
            .unwrap_or_else(|| OBLIQUE_VIEW.normalize());
        let half_y = DEFAULT_FOV_Y * 0.5;
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect.min(1.0)
        } else {
            1.0
        };
        let half_x = (aspect * half_y.tan()).atan();
        let half = half_y.min(half_x);
        let distance = radius / half.sin() * 1.05;
        let up = if direction.cross(&Vector3::z()).norm() > 1e-6 {
            Vector3::z()
        } else {
            Vector3::y()
        };
        Self {
            eye: centre - direction * distance,
            target: centre,
            up,
            projection: Projection::Perspective {
                fov_y: DEFAULT_FOV_Y,
            },
            near: 0.5 * (distance - radius),
        }
    }

    /// The same view with an orthographic projection that keeps the target's neighbourhood at
    /// the same size on the image.
    pub fn to_orthographic(&self) -> Self {
        let half_height = match self.projection {
            Projection::Perspective { fov_y } => {
                (self.target - self.eye).norm() * (fov_y * 0.5).tan()
            }
            Projection::Orthographic { half_height } => half_height,
        };
        Self {
            projection: Projection::Orthographic { half_height },
            ..*self
        }
    }

    /// Checks the camera and returns its orthonormal frame.
    pub(crate) fn view(&self) -> Result<ViewTransform> {
        let finite = |v: &Vector3| v.iter().all(|c| c.is_finite());
        if !finite(&self.eye.coords) || !finite(&self.target.coords) || !finite(&self.up) {
            return Err(Error::InvalidParameter {
                name: "camera",
                value: f64::NAN,
                reason: "eye, target and up must be finite",
            });
        }
        let forward =
            (self.target - self.eye)
                .try_normalize(1e-12)
                .ok_or(Error::InvalidParameter {
                    name: "camera eye-target distance",
                    value: (self.target - self.eye).norm(),
                    reason: "eye and target must differ",
                })?;
        let right = [self.up, Vector3::z(), Vector3::y()]
            .iter()
            .find_map(|up| forward.cross(up).try_normalize(1e-9))
            .expect("forward is a unit vector, so it is not parallel to both z and y");
        let up = right.cross(&forward);
        if !(self.near.is_finite() && self.near > 0.0) {
            return Err(Error::InvalidParameter {
                name: "camera near",
                value: self.near,
                reason: "must be positive and finite",
            });
        }
        match self.projection {
            Projection::Perspective { fov_y } if !(fov_y > 0.0 && fov_y < std::f64::consts::PI) => {
                return Err(Error::InvalidParameter {
                    name: "camera fov_y",
                    value: fov_y,
                    reason: "must be in (0, pi)",
                });
            }
            Projection::Orthographic { half_height }
                if !(half_height.is_finite() && half_height > 0.0) =>
            {
                return Err(Error::InvalidParameter {
                    name: "camera half_height",
                    value: half_height,
                    reason: "must be positive and finite",
                });
            }
            _ => {}
        }
        Ok(ViewTransform {
            eye: self.eye,
            right,
            up,
            forward,
            projection: self.projection,
            near: self.near,
        })
    }
}

/// A validated camera: world to camera coordinates.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ViewTransform {
    pub eye: Point3,
    pub right: Vector3,
    pub up: Vector3,
    pub forward: Vector3,
    pub projection: Projection,
    pub near: Real,
}

impl ViewTransform {
    /// `(x right, y up, depth in front of the eye)` of a world point.
    pub fn to_view(self, p: &Point3) -> [Real; 3] {
        let d = p - self.eye;
        [self.right.dot(&d), self.up.dot(&d), self.forward.dot(&d)]
    }

    /// A world direction in the camera frame (x right, y up, z towards the viewer).
    pub fn direction_to_camera(&self, v: &Vector3) -> Vector3 {
        Vector3::new(self.right.dot(v), self.up.dot(v), -self.forward.dot(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_sees_every_corner_in_front_and_inside_the_field_of_view() {
        let bounds = (Point3::new(-1.0, 0.0, 2.0), Point3::new(3.0, 0.5, 2.5));
        for dir in [
            OBLIQUE_VIEW,
            -Vector3::z(),
            Vector3::x(),
            Vector3::new(0.0, 0.0, 1.0),
        ] {
            for aspect in [0.5, 1.0, 2.0] {
                let cam = Camera::fit_with_aspect(bounds, dir, aspect);
                let view = cam.view().expect("fitted camera is valid");
                let Projection::Perspective { fov_y } = cam.projection else {
                    panic!("perspective")
                };
                let t = (fov_y * 0.5).tan();
                for i in 0..8 {
                    let p = Point3::new(
                        if i & 1 == 0 { bounds.0.x } else { bounds.1.x },
                        if i & 2 == 0 { bounds.0.y } else { bounds.1.y },
                        if i & 4 == 0 { bounds.0.z } else { bounds.1.z },
                    );
                    let [x, y, d] = view.to_view(&p);
                    assert!(d > cam.near, "corner behind the near plane");
                    assert!(y.abs() / d <= t, "corner outside vertically");
                    assert!(
                        x.abs() / d <= t * aspect,
                        "corner outside horizontally (aspect {aspect})"
                    );
                }
            }
        }
    }

    #[test]
    fn frame_is_orthonormal_and_up_falls_back() {
        let cam = Camera::look_at(Point3::new(0.0, 0.0, 5.0), Point3::origin(), Vector3::z());
        let v = cam.view().expect("parallel up falls back");
        assert!(
            (v.right.cross(&v.up) + v.forward).norm() < 1e-12,
            "right-handed, looking along -z"
        );
        let same = Camera::look_at(Point3::origin(), Point3::origin(), Vector3::z());
        assert!(same.view().is_err());
        let mut bad = Camera::look_at(Point3::new(1.0, 0.0, 0.0), Point3::origin(), Vector3::z());
        bad.near = 0.0;
        assert!(bad.view().is_err());
        bad.near = 0.1;
        bad.projection = Projection::Perspective { fov_y: 4.0 };
        assert!(bad.view().is_err());
        let ortho = cam.to_orthographic();
        let Projection::Orthographic { half_height } = ortho.projection else {
            panic!("orthographic")
        };
        assert!((half_height - 5.0 * (DEFAULT_FOV_Y * 0.5).tan()).abs() < 1e-12);
        assert!(ortho.view().is_ok());
    }
}
