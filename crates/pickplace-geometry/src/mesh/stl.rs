//! STL reading (binary and ASCII) and binary STL writing.
//!
//! Parsed by hand rather than with `stl_io`: `stl_io` pre-allocates from the triangle count in
//! the binary header (a corrupt count asks for gigabytes) and its errors do not say which facet
//! or line is wrong. Both dialects are small.
//!
//! Binary layout: 80-byte header, little-endian `u32` triangle count, then 50 bytes per
//! triangle (normal and three corners as `f32`, a `u16` attribute). A file is read as binary
//! when its size matches the declared count exactly, when it does not start with `solid`, or
//! when it holds a NUL byte; otherwise as ASCII (`solid … facet normal … outer loop vertex x y
//! z … endloop endfacet … endsolid`). The stored normals are ignored: the winding defines the
//! outside.

use super::{
    MAX_MESH_TRIANGLES, Soup, TriangleSource, check_limit, fan_triangulate, push_text_vertex,
};
use crate::error::{Error, MeshErrorKind, Result};
use crate::math::{Point3, Real};
use std::path::Path;

const HEADER_LEN: usize = 80;
const FACET_LEN: usize = 50;
/// Header of the binary STL files this crate writes. Does not start with `solid`, so no reader
/// mistakes the file for ASCII.
const WRITTEN_HEADER: &[u8] = b"pickplace binary STL (metres, counter-clockwise seen from outside)";

fn malformed(detail: String) -> MeshErrorKind {
    MeshErrorKind::Malformed {
        format: "STL",
        detail,
    }
}

/// Parses STL bytes (binary or ASCII) into a soup; one soup triangle per facet, in file order
/// (an ASCII facet with more than three vertices is fan-triangulated).
pub(crate) fn parse(bytes: &[u8]) -> std::result::Result<Soup, MeshErrorKind> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(MeshErrorKind::Empty);
    }
    let declared = if bytes.len() >= HEADER_LEN + 4 {
        let c = &bytes[HEADER_LEN..HEADER_LEN + 4];
        Some(u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize)
    } else {
        None
    };
    let exact_binary = declared.is_some_and(|n| {
        n.checked_mul(FACET_LEN)
            .and_then(|b| b.checked_add(HEADER_LEN + 4))
            == Some(bytes.len())
    });
    // ASCII STL never holds a NUL byte; binary STL nearly always does (attribute words, high
    // bytes of the count), so a binary file whose header starts with `solid` but whose size is
    // wrong is still reported as a truncated binary file.
    if !exact_binary && starts_with_solid(bytes) && !bytes.contains(&0) {
        return parse_ascii(bytes);
    }
    parse_binary(bytes, declared)
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    bytes[start..].len() >= 5 && bytes[start..start + 5].eq_ignore_ascii_case(b"solid")
}

fn parse_binary(bytes: &[u8], declared: Option<usize>) -> std::result::Result<Soup, MeshErrorKind> {
    let Some(count) = declared else {
        return Err(malformed(format!(
            "truncated binary STL: {} bytes, shorter than the 84-byte header and triangle count",
            bytes.len()
        )));
    };
    // From the header, before anything is allocated for the triangles.
    check_limit(
        "triangles declared in the binary STL header",
        count as u64,
        MAX_MESH_TRIANGLES,
    )?;
    let needed = (count as u128) * FACET_LEN as u128 + (HEADER_LEN + 4) as u128;
    if (bytes.len() as u128) < needed {
        let complete = (bytes.len() - HEADER_LEN - 4) / FACET_LEN;
        return Err(malformed(format!(
            "truncated binary STL: the header declares {count} triangles ({needed} bytes) but the \
             file has {} bytes ({complete} complete triangles)",
            bytes.len()
        )));
    }
    if count == 0 {
        return Err(MeshErrorKind::Empty);
    }
    let mut soup = Soup::with_capacity(3 * count, count);
    let body = &bytes[HEADER_LEN + 4..];
    for facet in body.chunks_exact(FACET_LEN).take(count) {
        let base = soup.positions.len() as u32;
        for corner in 0..3 {
            let at = 12 + 12 * corner;
            let read = |k: usize| -> Real {
                let b = &facet[at + 4 * k..at + 4 * k + 4];
                Real::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            };
            soup.positions.push(Point3::new(read(0), read(1), read(2)));
        }
        soup.triangles.push([base, base + 1, base + 2]);
    }
    Ok(soup)
}

fn parse_ascii(bytes: &[u8]) -> std::result::Result<Soup, MeshErrorKind> {
    let text = String::from_utf8_lossy(bytes);
    let mut soup = Soup::default();
    let mut in_loop = false;
    let mut loop_vertices: Vec<u32> = Vec::new();
    let mut facet_open = false;
    let mut last_line = 0;
    for (line_index, line) in text.lines().enumerate() {
        let line_no = line_index + 1;
        last_line = line_no;
        let mut words = line.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword.to_ascii_lowercase().as_str() {
            "solid" | "endsolid" => {
                if facet_open {
                    return Err(malformed(format!(
                        "line {line_no}: `{keyword}` inside a facet"
                    )));
                }
            }
            "facet" => {
                if facet_open {
                    return Err(malformed(format!(
                        "line {line_no}: `facet` before `endfacet`"
                    )));
                }
                facet_open = true;
            }
            "outer" => {
                if !facet_open || in_loop {
                    return Err(malformed(format!(
                        "line {line_no}: unexpected `outer loop`"
                    )));
                }
                in_loop = true;
                loop_vertices.clear();
            }
            "vertex" => {
                if !in_loop {
                    return Err(malformed(format!(
                        "line {line_no}: `vertex` outside `outer loop`"
                    )));
                }
                loop_vertices.push(push_text_vertex(
                    &mut words,
                    ("STL", "vertex", line_no),
                    &mut soup.positions,
                )?);
            }
            "endloop" => {
                if !in_loop {
                    return Err(malformed(format!(
                        "line {line_no}: `endloop` without `outer loop`"
                    )));
                }
                if loop_vertices.len() < 3 {
                    return Err(malformed(format!(
                        "line {line_no}: a facet has {} vertices, at least 3 are needed",
                        loop_vertices.len()
                    )));
                }
                fan_triangulate(&loop_vertices, &mut soup.triangles);
                check_limit("triangles", soup.triangles.len() as u64, MAX_MESH_TRIANGLES)
                    .map_err(|e| malformed(format!("line {line_no}: {e}")))?;
                in_loop = false;
            }
            "endfacet" => {
                if !facet_open || in_loop {
                    return Err(malformed(format!("line {line_no}: unexpected `endfacet`")));
                }
                facet_open = false;
            }
            _ => {
                return Err(malformed(format!(
                    "line {line_no}: unknown keyword `{keyword}`"
                )));
            }
        }
    }
    if facet_open {
        return Err(malformed(format!(
            "line {last_line}: the file ends inside a facet"
        )));
    }
    if soup.triangles.is_empty() {
        return Err(MeshErrorKind::Empty);
    }
    Ok(soup)
}

/// Encodes a mesh as binary STL: a fixed header, the triangle count, and per triangle its unit
/// normal (zero for a degenerate triangle) and corners as little-endian `f32`. The output
/// depends only on the input (byte for byte).
///
/// # Errors
/// [`Error::Mesh`] (path `<memory>`) when a triangle refers to a missing vertex, a coordinate
/// is not finite or does not fit `f32`, or there are more than `u32::MAX` triangles.
pub fn encode_stl_binary(mesh: &impl TriangleSource) -> Result<Vec<u8>> {
    encode_inner(mesh).map_err(|kind| Error::Mesh {
        path: crate::error::memory_path(),
        kind,
    })
}

fn encode_inner(mesh: &impl TriangleSource) -> std::result::Result<Vec<u8>, MeshErrorKind> {
    let positions = mesh.soup_positions();
    let triangles = mesh.soup_triangles();
    let count = u32::try_from(triangles.len()).map_err(|_| {
        malformed(format!(
            "{} triangles do not fit a binary STL",
            triangles.len()
        ))
    })?;
    if count == 0 {
        return Err(MeshErrorKind::Empty);
    }
    for (vertex, p) in positions.iter().enumerate() {
        let fits = |v: Real| v.is_finite() && v.abs() <= Real::from(f32::MAX);
        if !(fits(p.x) && fits(p.y) && fits(p.z)) {
            return Err(MeshErrorKind::NonFiniteCoordinate { vertex });
        }
    }
    let mut out = Vec::with_capacity(HEADER_LEN + 4 + FACET_LEN * triangles.len());
    let mut header = [b' '; HEADER_LEN];
    header[..WRITTEN_HEADER.len()].copy_from_slice(WRITTEN_HEADER);
    out.extend_from_slice(&header);
    out.extend_from_slice(&count.to_le_bytes());
    for (triangle, t) in triangles.iter().enumerate() {
        let mut corners = [Point3::origin(); 3];
        for (corner, &index) in corners.iter_mut().zip(t) {
            *corner = *positions
                .get(index as usize)
                .ok_or(MeshErrorKind::IndexOutOfRange {
                    triangle,
                    index: u64::from(index),
                    vertex_count: positions.len(),
                })?;
        }
        // The normal of the corners as stored (f32), so a reader recomputing it agrees.
        let stored = corners.map(|p| p.map(|v| Real::from(v as f32)));
        let n = (stored[1] - stored[0]).cross(&(stored[2] - stored[0]));
        let n = if n.norm() > 0.0 { n.normalize() } else { n };
        for v in n.iter().chain(stored.iter().flat_map(|p| p.coords.iter())) {
            out.extend_from_slice(&(*v as f32).to_le_bytes());
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    Ok(out)
}

/// Writes a mesh as a binary STL file (see [`encode_stl_binary`]), atomically: the bytes go to
/// a temporary file in the same folder, which is then renamed over `path`, so a reader never
/// sees a half-written file ([`pickplace_base::io::write_atomic`]).
///
/// # Errors
/// [`Error::Mesh`] (with `path`) for the reasons of [`encode_stl_binary`]; [`Error::Io`] when
/// the temporary file cannot be written or renamed.
pub fn write_stl_binary(mesh: &impl TriangleSource, path: &Path) -> Result<()> {
    let bytes = encode_inner(mesh).map_err(|kind| Error::Mesh {
        path: path.to_path_buf(),
        kind,
    })?;
    Ok(pickplace_base::io::write_atomic(path, &bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII_TETRA: &str = "solid t
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 1 0
  vertex 1 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 0 1
 endloop
endfacet
facet normal 1 1 1
 outer loop
  vertex 1 0 0
  vertex 0 1 0
  vertex 0 0 1
 endloop
endfacet
facet normal -1 0 0
 outer loop
  vertex 0 0 0
  vertex 0 0 1
  vertex 0 1 0
 endloop
endfacet
endsolid t
";

    #[test]
    fn ascii_tetrahedron_parses_in_file_order() {
        let soup = parse(ASCII_TETRA.as_bytes()).expect("valid ASCII STL");
        assert_eq!(soup.triangles.len(), 4);
        assert_eq!(soup.positions.len(), 12);
        assert_eq!(soup.positions[5], Point3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn binary_round_trip_is_exact_for_f32_coordinates() {
        let soup = parse(ASCII_TETRA.as_bytes()).expect("valid");
        let bytes = encode_inner(&soup).expect("encodable");
        assert_eq!(bytes.len(), 84 + 4 * 50);
        assert!(!bytes.starts_with(b"solid"));
        let back = parse(&bytes).expect("valid binary STL");
        assert_eq!(back.positions, soup.positions);
        assert_eq!(back.triangles, soup.triangles);
    }

    #[test]
    fn binary_starting_with_solid_is_still_binary() {
        let soup = parse(ASCII_TETRA.as_bytes()).expect("valid");
        let mut bytes = encode_inner(&soup).expect("encodable");
        bytes[..5].copy_from_slice(b"solid");
        assert_eq!(parse(&bytes).expect("binary by size").triangles.len(), 4);
    }

    #[test]
    fn truncated_binary_says_how_much_is_missing() {
        let soup = parse(ASCII_TETRA.as_bytes()).expect("valid");
        let bytes = encode_inner(&soup).expect("encodable");
        let err = parse(&bytes[..bytes.len() - 10]).unwrap_err();
        assert!(err.to_string().contains("declares 4 triangles"), "{err}");
        assert!(err.to_string().contains("3 complete"), "{err}");
        let mut solid = bytes.clone();
        solid[..5].copy_from_slice(b"solid");
        let err = parse(&solid[..solid.len() - 50]).unwrap_err();
        assert!(err.to_string().contains("truncated binary STL"), "{err}");
        let err = parse(&bytes[..40]).unwrap_err();
        assert!(err.to_string().contains("truncated binary STL"), "{err}");
    }

    #[test]
    fn a_header_over_the_triangle_limit_is_refused_before_allocating() {
        // Regression (issue 18): a header claiming 4e9 triangles; the file is 84 bytes.
        let mut bytes = vec![b' '; 80];
        bytes.extend_from_slice(&4_000_000_000u32.to_le_bytes());
        let err = parse(&bytes).unwrap_err();
        assert_eq!(
            err,
            MeshErrorKind::OverLimit {
                what: "triangles declared in the binary STL header",
                count: 4_000_000_000,
                limit: MAX_MESH_TRIANGLES as u64
            }
        );
        // Just over the limit, with the bytes really there: still refused.
        let count = MAX_MESH_TRIANGLES as u32 + 1;
        let mut big = vec![b' '; 80];
        big.extend_from_slice(&count.to_le_bytes());
        big.resize(84 + 50 * count as usize, 0);
        let err = parse(&big).unwrap_err();
        assert!(
            err.to_string().contains("over the limit of 2000000"),
            "{err}"
        );
        // At the limit the size check decides (here: truncated).
        let mut at = vec![b' '; 80];
        at.extend_from_slice(&(MAX_MESH_TRIANGLES as u32).to_le_bytes());
        let err = parse(&at).unwrap_err();
        assert!(err.to_string().contains("truncated"), "{err}");
    }

    #[test]
    fn ascii_errors_name_the_line() {
        let bad = ASCII_TETRA.replace(
            "vertex 0 1 0\n  vertex 1 0 0",
            "vertex 0 x 0\n  vertex 1 0 0",
        );
        let err = parse(bad.as_bytes()).unwrap_err();
        assert!(
            err.to_string().contains("line 5: `x` is not a number"),
            "{err}"
        );
        let err = parse(b"solid a\nfacet normal 0 0 1\n").unwrap_err();
        assert!(err.to_string().contains("ends inside a facet"), "{err}");
        assert_eq!(
            parse(b"solid a\nendsolid a\n").unwrap_err(),
            MeshErrorKind::Empty
        );
        assert_eq!(parse(b"").unwrap_err(), MeshErrorKind::Empty);
    }
}
