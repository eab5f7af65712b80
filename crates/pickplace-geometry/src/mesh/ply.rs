//! PLY reading (ASCII, binary little- and big-endian) through `ply-rs-bw`.
//!
//! Reads the `vertex` element's `x`, `y`, `z` (any scalar type) and the `face` element's
//! `vertex_indices` (or `vertex_index`) list (any integer type). Other elements and properties
//! are skipped. A face with more than three corners is fan-triangulated (`a b c`, `a c d`, …),
//! so "the file's triangle order" is the order of faces with each polygon replaced by its fan.

use super::{MAX_MESH_TRIANGLES, MAX_MESH_VERTICES, Soup, check_limit, fan_triangulate};
use crate::error::MeshErrorKind;
use crate::math::{Point3, Real};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};

fn malformed(detail: String) -> MeshErrorKind {
    MeshErrorKind::Malformed {
        format: "PLY",
        detail,
    }
}

fn scalar(p: &Property) -> Option<Real> {
    Some(match *p {
        Property::Char(v) => Real::from(v),
        Property::UChar(v) => Real::from(v),
        Property::Short(v) => Real::from(v),
        Property::UShort(v) => Real::from(v),
        Property::Int(v) => Real::from(v),
        Property::UInt(v) => Real::from(v),
        Property::Float(v) => Real::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// The integer list of a face, as `i64` (negative values kept, to be reported).
fn index_list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        _ => return None,
    })
}

/// Refuses a header that declares more vertices than [`MAX_MESH_VERTICES`], more faces than
/// [`MAX_MESH_TRIANGLES`], more elements than both together, or more elements than bytes
/// follow it.
///
/// Every element takes at least one byte of the body (binary: its first property; ASCII: its
/// line), so a larger count can only be a damaged or hostile file. `ply-rs-bw` would otherwise
/// read an element without properties `count` times from no data at all, and a count of
/// billions exhausts the memory (found by the `mesh_ply` fuzz target; see
/// `tests/fuzz-regressions/`). A header that cannot be split off is left to `ply-rs-bw` to
/// report.
fn check_declared_counts(bytes: &[u8]) -> std::result::Result<(), MeshErrorKind> {
    let mut offset = 0;
    let mut declared: u128 = 0;
    // The first count over a limit; reported after the comparison with the body's size.
    let mut over: std::result::Result<(), MeshErrorKind> = Ok(());
    for line in bytes.split_inclusive(|&b| b == b'\n') {
        offset += line.len();
        let text = String::from_utf8_lossy(line);
        let mut words = text.split_ascii_whitespace();
        match words.next() {
            Some("end_header") => {
                let body = bytes.len() - offset;
                if declared > body as u128 {
                    return Err(malformed(format!(
                        "the header declares {declared} elements but only {body} bytes follow it"
                    )));
                }
                return over;
            }
            Some("element") => {
                let name = words.next().unwrap_or("");
                if let Some(count) = words.next().and_then(|c| c.parse::<u64>().ok()) {
                    declared += u128::from(count);
                    // Limits from the header, before ply-rs-bw allocates the elements.
                    let check = match name {
                        "vertex" => check_limit(
                            "vertices declared in the PLY header",
                            count,
                            MAX_MESH_VERTICES,
                        ),
                        "face" => check_limit(
                            "faces declared in the PLY header",
                            count,
                            MAX_MESH_TRIANGLES,
                        ),
                        _ => Ok(()),
                    }
                    .and_then(|()| {
                        check_limit(
                            "elements declared in the PLY header",
                            u64::try_from(declared).unwrap_or(u64::MAX),
                            MAX_MESH_VERTICES + MAX_MESH_TRIANGLES,
                        )
                    });
                    over = over.and(check);
                }
            }
            _ => {}
        }
    }
    over
}

pub(crate) fn parse(bytes: &[u8]) -> std::result::Result<Soup, MeshErrorKind> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(MeshErrorKind::Empty);
    }
    check_declared_counts(bytes)?;
    let parser = Parser::<DefaultElement>::new();
    let mut reader = bytes;
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|e| malformed(e.to_string()))?;
    let vertices = ply.payload.get("vertex").map(Vec::as_slice).unwrap_or(&[]);
    let faces = ply.payload.get("face").map(Vec::as_slice).unwrap_or(&[]);
    if faces.is_empty() {
        return Err(MeshErrorKind::Empty);
    }
    if vertices.len() > u32::MAX as usize {
        return Err(malformed(format!(
            "{} vertices do not fit 32-bit indices",
            vertices.len()
        )));
    }
    let mut soup = Soup::with_capacity(vertices.len(), faces.len());
    for (vertex, element) in vertices.iter().enumerate() {
        let mut xyz = [0.0; 3];
        for (c, name) in xyz.iter_mut().zip(["x", "y", "z"]) {
            let p = element.get(name).ok_or_else(|| {
                malformed(format!("vertex {vertex} has no scalar property `{name}`"))
            })?;
            *c = scalar(p).ok_or_else(|| {
                malformed(format!(
                    "vertex property `{name}` is a list, expected a number"
                ))
            })?;
        }
        soup.positions.push(Point3::new(xyz[0], xyz[1], xyz[2]));
    }
    let vertex_count = soup.positions.len();
    let mut polygon = Vec::new();
    for (face, element) in faces.iter().enumerate() {
        let list = element
            .get("vertex_indices")
            .or_else(|| element.get("vertex_index"))
            .ok_or_else(|| malformed(format!("face {face} has no `vertex_indices` list")))?;
        let list = index_list(list)
            .ok_or_else(|| malformed("`vertex_indices` must be a list of integers".to_string()))?;
        if list.len() < 3 {
            return Err(malformed(format!(
                "face {face} has {} corners, at least 3 are needed",
                list.len()
            )));
        }
        let triangle = soup.triangles.len();
        polygon.clear();
        for index in list {
            let Ok(index) = u64::try_from(index) else {
                return Err(malformed(format!(
                    "face {face} has the negative vertex index {index}"
                )));
            };
            if index >= vertex_count as u64 {
                return Err(MeshErrorKind::IndexOutOfRange {
                    triangle,
                    index,
                    vertex_count,
                });
            }
            polygon.push(index as u32);
        }
        fan_triangulate(&polygon, &mut soup.triangles);
        check_limit("triangles", soup.triangles.len() as u64, MAX_MESH_TRIANGLES)?;
    }
    Ok(soup)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = "ply\nformat ascii 1.0\ncomment unit square\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n4 0 1 2 3\n";

    #[test]
    fn element_counts_beyond_the_body_are_refused() {
        // An element without properties reads no bytes: without the check, ply-rs-bw would
        // build a billion empty elements.
        let hostile = b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float z\nelement face 1211\nend_header\n\0\0\0\0";
        let e = parse(hostile).expect_err("refused");
        assert!(
            e.to_string()
                .contains("declares 1212 elements but only 4 bytes"),
            "{e}"
        );
        // Exactly one byte per element is still accepted by the check (the parser decides).
        let tight = b"ply\nformat binary_little_endian 1.0\nelement v 2\nproperty uchar a\nend_header\n\x01\x02";
        assert!(check_declared_counts(tight).is_ok());
        assert!(check_declared_counts(&tight[..tight.len() - 1]).is_err());
        // No end_header: left to ply-rs-bw.
        assert!(check_declared_counts(b"ply\nelement vertex 99\n").is_ok());
        // The shipped square passes.
        assert!(check_declared_counts(SQUARE.as_bytes()).is_ok());
    }

    #[test]
    fn header_counts_over_the_limits_are_refused() {
        // Regression (issue 18): a header claiming 1e12 vertices, refused from the header:
        // first by the file's size, then by the limits when the bytes are there.
        let hostile = b"ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nend_header\n0\n";
        let e = parse(hostile).expect_err("refused");
        assert!(
            e.to_string()
                .contains("declares 1000000000000 elements but only 2 bytes"),
            "{e}"
        );
        let mut padded = b"ply\nformat binary_little_endian 1.0\nelement vertex 6000001\nproperty uchar x\nend_header\n".to_vec();
        padded.resize(padded.len() + 6_000_001, 0);
        assert_eq!(
            parse(&padded).expect_err("refused"),
            MeshErrorKind::OverLimit {
                what: "vertices declared in the PLY header",
                count: 6_000_001,
                limit: MAX_MESH_VERTICES as u64
            }
        );
        let pad = |text: String| text + &" ".repeat(8_000_010);
        let faces = pad(SQUARE.replace("element face 1", "element face 2000001"));
        let e = parse(faces.as_bytes()).expect_err("refused");
        assert!(
            e.to_string()
                .contains("2000001 faces declared in the PLY header, over the limit of 2000000"),
            "{e}"
        );
        let other = pad(SQUARE.replace(
            "element face 1",
            "element face 1\nelement edge 8000000\nproperty uchar a",
        ));
        let e = parse(other.as_bytes()).expect_err("refused");
        assert!(
            e.to_string()
                .contains("elements declared in the PLY header"),
            "{e}"
        );
    }

    #[test]
    fn ascii_quad_is_fanned() {
        let soup = parse(SQUARE.as_bytes()).expect("valid PLY");
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn binary_big_endian_reads() {
        let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
        for v in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]] {
            for c in v {
                bytes.extend_from_slice(&c.to_be_bytes());
            }
        }
        bytes.push(3);
        for i in [0u32, 1, 2] {
            bytes.extend_from_slice(&i.to_be_bytes());
        }
        let soup = parse(&bytes).expect("valid binary PLY");
        assert_eq!(soup.positions[2], Point3::new(0.0, 2.0, 0.0));
        assert_eq!(soup.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn errors_say_what_is_wrong() {
        let bad = SQUARE.replace("4 0 1 2 3", "4 0 1 2 9");
        let err = parse(bad.as_bytes()).unwrap_err();
        assert_eq!(
            err,
            MeshErrorKind::IndexOutOfRange {
                triangle: 0,
                index: 9,
                vertex_count: 4
            }
        );
        let err = parse(SQUARE.replace("1 1 0 3\n", "").as_bytes()).unwrap_err();
        assert!(err.to_string().starts_with("malformed PLY file"), "{err}");
        assert_eq!(parse(b"").unwrap_err(), MeshErrorKind::Empty);
        let err = parse(b"not a ply").unwrap_err();
        assert!(err.to_string().starts_with("malformed PLY file"), "{err}");
    }
}
