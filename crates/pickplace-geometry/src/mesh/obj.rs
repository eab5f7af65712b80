//! Wavefront OBJ reading: `v` and `f` statements.
//!
//! Parsed by hand rather than with `tobj`: `tobj` reports an out-of-range face index without the
//! index, the face or the line, and splits the geometry into models that would have to be
//! stitched back into the file's face order. Only geometry is read: `v x y z [w]` (extra values
//! such as vertex colours are ignored) and `f a b c …` with `a`, `a/t`, `a//n` or `a/t/n`
//! corners (1-based, negative = relative to the vertices defined so far). Texture coordinates,
//! normals, groups, materials, lines and points are skipped. A face with more than three
//! corners is fan-triangulated (`a b c`, `a c d`, …), so "the file's triangle order" is the
//! order of faces with each polygon replaced by its fan.

use super::{MAX_MESH_TRIANGLES, Soup, check_limit, fan_triangulate, push_text_vertex};
use crate::error::MeshErrorKind;

fn malformed(detail: String) -> MeshErrorKind {
    MeshErrorKind::Malformed {
        format: "OBJ",
        detail,
    }
}

/// A face corner before resolution: 1-based or negative relative index, and the number of
/// vertices defined before its line.
#[derive(Clone, Copy)]
struct Corner {
    index: i64,
    defined_before: usize,
}

pub(crate) fn parse(bytes: &[u8]) -> std::result::Result<Soup, MeshErrorKind> {
    let text = String::from_utf8_lossy(bytes);
    let mut soup = Soup::default();
    // Faces as ranges into `corners`; resolved after all vertices are known, so that a
    // positive index may refer to a vertex defined later (as most readers allow).
    let mut corners: Vec<Corner> = Vec::new();
    let mut faces: Vec<(usize, usize)> = Vec::new();
    let mut triangles: u64 = 0;
    for (line_index, line) in text.lines().enumerate() {
        let line_no = line_index + 1;
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_ascii_whitespace();
        match words.next() {
            Some("v") => {
                push_text_vertex(&mut words, ("OBJ", "v", line_no), &mut soup.positions)?;
            }
            Some("f") => {
                let start = corners.len();
                for word in words {
                    // Bounds the corners of one huge face too (n corners, n - 2 triangles).
                    if corners.len() - start >= MAX_MESH_TRIANGLES + 2 {
                        return Err(malformed(format!(
                            "line {line_no}: a face has more than {} corners",
                            MAX_MESH_TRIANGLES + 2
                        )));
                    }
                    let first = word.split('/').next().unwrap_or("");
                    let index = first.parse::<i64>().map_err(|_| {
                        malformed(format!("line {line_no}: `{word}` is not a face corner"))
                    })?;
                    if index == 0 {
                        return Err(malformed(format!(
                            "line {line_no}: vertex index 0 (OBJ indices start at 1)"
                        )));
                    }
                    corners.push(Corner {
                        index,
                        defined_before: soup.positions.len(),
                    });
                }
                let n = corners.len() - start;
                if n < 3 {
                    return Err(malformed(format!(
                        "line {line_no}: a face has {n} corners, at least 3 are needed"
                    )));
                }
                // A face of n corners is n - 2 fan triangles.
                triangles += (n - 2) as u64;
                check_limit("triangles", triangles, MAX_MESH_TRIANGLES)
                    .map_err(|e| malformed(format!("line {line_no}: {e}")))?;
                faces.push((start, corners.len()));
            }
            _ => {}
        }
    }
    if faces.is_empty() {
        return Err(MeshErrorKind::Empty);
    }
    let vertex_count = soup.positions.len();
    let mut polygon = Vec::new();
    for (start, end) in faces {
        polygon.clear();
        // The file triangle index of this face's first fan triangle.
        let triangle = soup.triangles.len();
        for c in &corners[start..end] {
            let resolved = if c.index > 0 {
                (c.index - 1) as u64
            } else {
                // -1 is the last vertex defined before the line.
                let back = c.index.unsigned_abs();
                match (c.defined_before as u64).checked_sub(back) {
                    Some(i) => i,
                    None => {
                        return Err(malformed(format!(
                            "face corner {} refers back past the first vertex ({} defined before it)",
                            c.index, c.defined_before
                        )));
                    }
                }
            };
            if resolved >= vertex_count as u64 {
                return Err(MeshErrorKind::IndexOutOfRange {
                    triangle,
                    // As written in the file (1-based), so the message matches the text.
                    index: resolved + 1,
                    vertex_count,
                });
            }
            polygon.push(resolved as u32);
        }
        fan_triangulate(&polygon, &mut soup.triangles);
    }
    Ok(soup)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_are_fanned_and_relative_indices_resolve() {
        let text = "# square and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2/2 3//3 4\nv 0 0 1\nf -5 -4 -1\n";
        let soup = parse(text.as_bytes()).expect("valid OBJ");
        assert_eq!(soup.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
    }

    #[test]
    fn faces_over_the_triangle_limit_are_refused_with_their_line() {
        // One face of MAX + 3 corners is MAX + 1 fan triangles.
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
        for _ in 0..MAX_MESH_TRIANGLES + 3 {
            text.push_str(" 1");
        }
        text.push('\n');
        let err = parse(text.as_bytes()).unwrap_err();
        assert!(
            err.to_string().contains("line 4: a face has more than"),
            "{err}"
        );
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
        for _ in 0..MAX_MESH_TRIANGLES + 2 {
            text.push_str(" 1");
        }
        text.push_str("\nf 1 2 3\n");
        let err = parse(text.as_bytes()).unwrap_err();
        assert!(
            err.to_string()
                .contains("line 5: 2000001 triangles, over the limit of 2000000"),
            "{err}"
        );
    }

    #[test]
    fn errors_say_what_is_wrong() {
        let err = parse(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n").unwrap_err();
        assert_eq!(
            err,
            MeshErrorKind::IndexOutOfRange {
                triangle: 1,
                index: 7,
                vertex_count: 3
            }
        );
        let err = parse(b"v 0 0 0\nf 1 0 1\n").unwrap_err();
        assert!(err.to_string().contains("line 2: vertex index 0"), "{err}");
        let err = parse(b"v 0 0\n").unwrap_err();
        assert!(err.to_string().contains("line 1: `v` needs three"), "{err}");
        let err = parse(b"v 0 0 0\nv 0 0 0\nf 1 2\n").unwrap_err();
        assert!(err.to_string().contains("2 corners"), "{err}");
        assert_eq!(
            parse(b"# nothing\nv 1 2 3\n").unwrap_err(),
            MeshErrorKind::Empty
        );
        let err = parse(b"v 0 0 0\nf -1 -2 -3\n").unwrap_err();
        assert!(err.to_string().contains("refers back past"), "{err}");
    }
}
