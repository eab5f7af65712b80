//! Parsing of the command line's values that more than one command takes: poses and points.
//!
//! One pose syntax for every option that takes a pose (`placements --env-pose`,
//! `robot ik --pose`):
//! - `x,y,z`: a position (m), no rotation;
//! - `x,y,z,qx,qy,qz,qw`: a position and a quaternion in ROS order (normalised);
//! - `{"position":[x,y,z],"orientation":[qx,qy,qz,qw]}`: the pose object of every pickplace
//!   JSON document.

use anyhow::{Context as _, bail};
use pickplace_geometry::math::nalgebra::Quaternion;
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion};

/// Parses comma-separated finite numbers; `option` names the option in errors.
pub fn parse_numbers(text: &str, option: &str) -> anyhow::Result<Vec<Real>> {
    text.split(',')
        .map(|s| {
            let v: Real = s
                .trim()
                .parse()
                .with_context(|| format!("{option} `{text}`: `{s}` is not a number"))?;
            if !v.is_finite() {
                bail!("{option} `{text}`: `{s}` is not finite");
            }
            Ok(v)
        })
        .collect()
}

/// Parses a pose in any of the three forms of the module doc; `option` names the option in errors.
///
/// # Errors
/// A number that does not parse or is not finite, a count other than 3 or 7, a zero
/// quaternion, a JSON object of another shape.
pub fn parse_pose(text: &str, option: &str) -> anyhow::Result<Isometry3> {
    let numbers = if text.trim_start().starts_with('{') {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Pose {
            position: [Real; 3],
            orientation: [Real; 4],
        }
        let p: Pose = serde_json::from_str(text).with_context(|| {
            format!(
                "{option} `{text}` is not {{\"position\":[x,y,z],\"orientation\":[qx,qy,qz,qw]}}"
            )
        })?;
        let numbers: Vec<Real> = p.position.iter().chain(&p.orientation).copied().collect();
        if numbers.iter().any(|x| !x.is_finite()) {
            bail!("{option} `{text}`: every number must be finite");
        }
        numbers
    } else {
        parse_numbers(text, option)?
    };
    let rotation = match numbers.len() {
        3 => UnitQuaternion::identity(),
        7 => {
            let q = Quaternion::new(numbers[6], numbers[3], numbers[4], numbers[5]);
            if q.norm() < 1e-9 {
                bail!("{option} `{text}`: the quaternion is zero");
            }
            UnitQuaternion::from_quaternion(q)
        }
        n => {
            bail!("{option} `{text}`: expected 3 numbers (x,y,z) or 7 (x,y,z,qx,qy,qz,qw), got {n}")
        }
    };
    Ok(Isometry3::from_parts(
        Translation3::new(numbers[0], numbers[1], numbers[2]),
        rotation,
    ))
}

/// Parses a point `x,y,z` (m); `option` names the option in errors.
pub fn parse_point(text: &str, option: &str) -> anyhow::Result<Point3> {
    let v = parse_numbers(text, option)?;
    if v.len() != 3 {
        bail!(
            "{option} `{text}`: expected 3 numbers X,Y,Z, got {}",
            v.len()
        );
    }
    Ok(Point3::new(v[0], v[1], v[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::Vector3;

    fn error(text: &str) -> String {
        format!("{:#}", parse_pose(text, "--pose").expect_err(text))
    }

    #[test]
    fn the_three_spellings_give_the_same_pose() {
        let json = parse_pose(
            r#"{"position":[0.1,0.2,0.3],"orientation":[0,0,0.6,0.8]}"#,
            "--pose",
        )
        .expect("json");
        let list = parse_pose("0.1, 0.2, 0.3, 0, 0, 0.6, 0.8", "--pose").expect("list");
        assert_eq!(json, list);
        assert_eq!(list.translation.vector, Vector3::new(0.1, 0.2, 0.3));
        assert!((list.rotation.quaternion().k - 0.6).abs() < 1e-12);
        let position = parse_pose("-1,2,3", "--pose").expect("position only");
        assert_eq!(position, Isometry3::translation(-1.0, 2.0, 3.0));
    }

    #[test]
    fn quaternions_are_normalised() {
        let p = parse_pose("0,0,0,0,0,2,0", "--pose").expect("valid");
        assert!((p.rotation.quaternion().k - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_poses_say_what_is_wrong() {
        for (text, needle) in [
            ("1,2", "expected 3 numbers"),
            ("1,2,3,4", "got 4"),
            ("1,2,3,0,0,0,0", "quaternion is zero"),
            ("1,2,NaN", "not finite"),
            ("1,2,x", "`x` is not a number"),
            (r#"{"position":[1,2,3]}"#, "is not {"),
            (
                r#"{"position":[1,2,3],"orientation":[0,0,0,1],"x":1}"#,
                "is not {",
            ),
        ] {
            let message = error(text);
            assert!(message.starts_with("--pose"), "{text}: {message}");
            assert!(message.contains(needle), "{text}: {message}");
        }
    }

    #[test]
    fn points_need_three_numbers() {
        assert_eq!(
            parse_point("1, -2, 3", "--target").expect("point"),
            Point3::new(1.0, -2.0, 3.0)
        );
        let e = format!("{:#}", parse_point("1,2", "--target").expect_err("two"));
        assert!(e.contains("--target") && e.contains("got 2"), "{e}");
        assert!(parse_point("a,b,c", "--target").is_err());
    }
}
