//! COLLADA (`.dae`) through the `mesh-loader` crate.
//!
//! Every `<geometry>` of the file becomes part of one soup, in the file's order. mesh-loader
//! applies the transform of the `<node>` that instantiates a geometry (with its parents); a
//! geometry that no node instantiates is taken as written, and one instantiated several
//! times is placed once (mesh-loader keeps one transform per geometry). Polygons are
//! triangulated by mesh-loader; lines and points are not triangles and are ignored.
//!
//! Units: mesh-loader 0.1.13 scales the geometry by `<asset><unit meter="…">` *inside* the
//! node transforms, so a node's translation stays in the file's unit (a centimetre file
//! with a node 100 cm up comes out 100 m up). We therefore read `meter` ourselves, hand
//! mesh-loader the file with `meter="1"`, and scale every coordinate afterwards: positions
//! come out in metres, translations included.

use super::{MAX_MESH_TRIANGLES, MAX_MESH_VERTICES, Soup, check_limit};
use crate::error::MeshErrorKind;
use crate::math::Point3;

/// Where the `meter` value of the document's `<asset><unit>` is (a byte range), and the
/// value; `None` when the file has none (mesh-loader's default, 1 m, then holds).
fn unit_meter(
    bytes: &[u8],
) -> std::result::Result<Option<(std::ops::Range<usize>, f64)>, MeshErrorKind> {
    let find =
        |haystack: &[u8], needle: &[u8]| haystack.windows(needle.len()).position(|w| w == needle);
    let Some(asset_end) = find(bytes, b"</asset>") else {
        return Ok(None);
    };
    let asset = &bytes[..asset_end];
    let mut from = 0;
    let tag_start = loop {
        let Some(at) = find(&asset[from..], b"<unit") else {
            return Ok(None);
        };
        let start = from + at;
        // `<unit` followed by a space, `/` or `>`: not `<units…>`.
        match asset.get(start + 5) {
            Some(b' ' | b'\t' | b'\r' | b'\n' | b'/' | b'>') => break start,
            _ => from = start + 5,
        }
    };
    let tag_end = find(&asset[tag_start..], b">").map_or(asset.len(), |e| tag_start + e);
    let tag = &asset[tag_start..tag_end];
    let Some(attribute) = find(tag, b"meter=") else {
        return Ok(None);
    };
    let quote_at = attribute + b"meter=".len();
    let Some(&quote) = tag.get(quote_at).filter(|q| matches!(q, b'"' | b'\'')) else {
        return Err(bad_unit(tag));
    };
    let value_start = quote_at + 1;
    let Some(length) = tag[value_start..].iter().position(|&c| c == quote) else {
        return Err(bad_unit(tag));
    };
    let text =
        std::str::from_utf8(&tag[value_start..value_start + length]).map_err(|_| bad_unit(tag))?;
    let meter: f64 = text
        .trim()
        .parse()
        .ok()
        .filter(|m: &f64| m.is_finite() && *m > 0.0)
        .ok_or_else(|| bad_unit(tag))?;
    let start = tag_start + value_start;
    Ok(Some((start..start + length, meter)))
}

fn bad_unit(tag: &[u8]) -> MeshErrorKind {
    MeshErrorKind::Malformed {
        format: "COLLADA",
        detail: format!(
            "{}: meter is not a positive number",
            String::from_utf8_lossy(tag)
        ),
    }
}

/// Elements whose `count` attribute is a number of primitives: mesh-loader reserves
/// `count × corners × inputs` indices for them.
const PRIMITIVE_ELEMENTS: [&str; 7] = [
    "triangles",
    "polylist",
    "polygons",
    "lines",
    "linestrips",
    "tristrips",
    "trifans",
];

/// The largest `offset` of an `<input>` accepted (the number of inputs of a primitive is the
/// largest offset plus one; files use a handful).
pub(crate) const MAX_INPUT_OFFSET: u64 = 15;

/// The value of attribute `name` in the tag body `tag` (`name="123"`), saturated to
/// `u64::MAX` when it has too many digits; `None` when absent or not a number.
fn attribute_u64(tag: &[u8], name: &[u8]) -> Option<u64> {
    let mut from = 0;
    while let Some(at) = tag[from..].windows(name.len()).position(|w| w == name) {
        let start = from + at;
        from = start + name.len();
        let preceded = start > 0 && tag[start - 1].is_ascii_whitespace();
        let rest = &tag[from..];
        let rest = &rest[rest.iter().take_while(|b| b.is_ascii_whitespace()).count()..];
        if !preceded || rest.first() != Some(&b'=') {
            continue;
        }
        let rest = &rest[1..];
        let rest = &rest[rest.iter().take_while(|b| b.is_ascii_whitespace()).count()..];
        let rest = rest
            .strip_prefix(b"\"")
            .or_else(|| rest.strip_prefix(b"'"))?;
        let digits: Vec<u8> = rest
            .iter()
            .copied()
            .skip_while(u8::is_ascii_whitespace)
            .take_while(u8::is_ascii_digit)
            .collect();
        if digits.is_empty() {
            return None;
        }
        return Some(digits.iter().fold(0u64, |n, d| {
            n.saturating_mul(10).saturating_add(u64::from(d - b'0'))
        }));
    }
    None
}

/// Refuses, before mesh-loader reads the file, the counts it would allocate from: mesh-loader
/// 0.1.13 calls `Vec::with_capacity(count)` for `<float_array count>` (and the other arrays)
/// and reserves `count × corners × inputs` indices for a primitive element, so a count of
/// billions aborts the process. Every counted item takes at least a byte of the file, a
/// primitive element's count is at most [`MAX_MESH_TRIANGLES`], any other count at most three
/// per vertex of [`MAX_MESH_VERTICES`], and an input's offset at most [`MAX_INPUT_OFFSET`].
/// A tag inside a comment is checked too (being strict there costs nothing).
fn check_declared_counts(bytes: &[u8]) -> std::result::Result<(), MeshErrorKind> {
    let mut at = 0;
    while let Some(lt) = bytes[at..].iter().position(|&b| b == b'<') {
        let start = at + lt + 1;
        let end = bytes[start..]
            .iter()
            .position(|&b| b == b'>')
            .map_or(bytes.len(), |e| start + e);
        let tag = &bytes[start..end];
        at = end;
        let name_len = tag
            .iter()
            .take_while(|b| !b.is_ascii_whitespace() && **b != b'/')
            .count();
        let name = String::from_utf8_lossy(&tag[..name_len]);
        if let Some(count) = attribute_u64(tag, b"count") {
            if count > bytes.len() as u64 {
                return Err(MeshErrorKind::Malformed {
                    format: "COLLADA",
                    detail: format!(
                        "<{name} count=\"{count}\">: more items than the file has bytes ({})",
                        bytes.len()
                    ),
                });
            }
            if PRIMITIVE_ELEMENTS.contains(&name.as_ref()) {
                check_limit(
                    "primitives declared by a COLLADA count",
                    count,
                    MAX_MESH_TRIANGLES,
                )?;
            } else {
                check_limit(
                    "values declared by a COLLADA count",
                    count,
                    3 * MAX_MESH_VERTICES,
                )?;
            }
        }
        if let Some(offset) = attribute_u64(tag, b"offset")
            && offset > MAX_INPUT_OFFSET
        {
            return Err(MeshErrorKind::Malformed {
                format: "COLLADA",
                detail: format!(
                    "<{name} offset=\"{offset}\">: an input offset over {MAX_INPUT_OFFSET}"
                ),
            });
        }
    }
    Ok(())
}

/// Parses COLLADA bytes into one soup (all meshes of the file), in metres.
pub(crate) fn parse(bytes: &[u8]) -> std::result::Result<Soup, MeshErrorKind> {
    check_declared_counts(bytes)?;
    let unit = unit_meter(bytes)?;
    let (scene, meter) = {
        let rewritten;
        let (input, meter) = match unit {
            Some((range, meter)) if meter != 1.0 => {
                let mut copy = Vec::with_capacity(bytes.len());
                copy.extend_from_slice(&bytes[..range.start]);
                copy.extend_from_slice(b"1");
                copy.extend_from_slice(&bytes[range.end..]);
                rewritten = copy;
                (rewritten.as_slice(), meter)
            }
            _ => (bytes, 1.0),
        };
        // mesh-loader 0.1.13 asserts, indexes and unwraps on some malformed files (an
        // accessor longer than its array, a dangling reference, …): its panics are caught
        // and become errors. The default panic hook still prints the message on stderr.
        let parsed = std::panic::catch_unwind(|| mesh_loader::collada::from_slice(input)).map_err(
            |payload| MeshErrorKind::Malformed {
                format: "COLLADA",
                detail: format!(
                    "mesh-loader failed on it ({})",
                    payload
                        .downcast_ref::<&str>()
                        .map(|s| (*s).to_owned())
                        .or_else(|| payload.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "panic".to_owned())
                ),
            },
        )?;
        let scene = parsed.map_err(|error| MeshErrorKind::Malformed {
            format: "COLLADA",
            detail: error.to_string(),
        })?;
        (scene, meter)
    };
    let vertices: usize = scene.meshes.iter().map(|m| m.vertices.len()).sum();
    let triangles: usize = scene.meshes.iter().map(|m| m.faces.len()).sum();
    check_limit("triangles", triangles as u64, MAX_MESH_TRIANGLES)?;
    check_limit("vertices", vertices as u64, MAX_MESH_VERTICES)?;
    let mut soup = Soup::with_capacity(vertices, triangles);
    for mesh in &scene.meshes {
        let offset = u32::try_from(soup.positions.len()).map_err(|_| too_large(vertices))?;
        soup.positions.extend(
            mesh.vertices
                .iter()
                .map(|v| Point3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])) * meter),
        );
        for face in &mesh.faces {
            let mut triangle = [0u32; 3];
            for (corner, &index) in triangle.iter_mut().zip(face) {
                *corner = index
                    .checked_add(offset)
                    .ok_or_else(|| too_large(vertices))?;
            }
            soup.triangles.push(triangle);
        }
    }
    u32::try_from(soup.positions.len()).map_err(|_| too_large(vertices))?;
    Ok(soup)
}

fn too_large(vertices: usize) -> MeshErrorKind {
    MeshErrorKind::Malformed {
        format: "COLLADA",
        detail: format!("{vertices} vertices: more than a 32-bit index can address"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit right triangle in centimetres, placed by a node 1 m (100 cm) up.
    const TRIANGLE_CM: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri">
      <mesh>
        <source id="tri-pos">
          <float_array id="tri-pos-array" count="9">0 0 0 10 0 0 0 10 0</float_array>
          <technique_common>
            <accessor source="#tri-pos-array" count="3" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
        <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="n"><translate>0 0 100</translate><instance_geometry url="#tri"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##;

    #[test]
    fn units_and_node_transforms_are_applied() {
        let soup = parse(TRIANGLE_CM.as_bytes()).expect("valid COLLADA");
        assert_eq!(soup.triangles, vec![[0, 1, 2]]);
        let expected = [
            Point3::new(0.0, 0.0, 1.0),
            Point3::new(0.1, 0.0, 1.0),
            Point3::new(0.0, 0.1, 1.0),
        ];
        for (p, e) in soup.positions.iter().zip(&expected) {
            assert!((p - e).norm() < 1e-6, "{p} != {e}");
        }
    }

    #[test]
    fn a_file_in_metres_or_without_unit_is_read_as_written() {
        let metres = TRIANGLE_CM.replace(r#"meter="0.01""#, r#"meter="1""#);
        let soup = parse(metres.as_bytes()).expect("valid");
        assert!((soup.positions[1] - Point3::new(10.0, 0.0, 100.0)).norm() < 1e-6);
        let none = TRIANGLE_CM.replace(r#"<unit name="centimeter" meter="0.01"/>"#, "");
        let soup = parse(none.as_bytes()).expect("valid");
        assert!((soup.positions[1] - Point3::new(10.0, 0.0, 100.0)).norm() < 1e-6);
        let bad = TRIANGLE_CM.replace(r#"meter="0.01""#, r#"meter="-2""#);
        assert!(matches!(
            parse(bad.as_bytes()),
            Err(MeshErrorKind::Malformed { .. })
        ));
    }

    #[test]
    fn an_accessor_longer_than_its_array_is_an_error_not_a_panic() {
        // Regression: mesh-loader asserts `count * stride <= len` and panicked.
        let long = TRIANGLE_CM.replace(r#"count="3" stride="3""#, r#"count="9" stride="3""#);
        assert!(matches!(
            parse(long.as_bytes()),
            Err(MeshErrorKind::Malformed { .. })
        ));
    }

    #[test]
    fn counts_that_would_allocate_gigabytes_are_refused_before_mesh_loader() {
        // Regression (issue 18): mesh-loader calls `Vec::with_capacity(count)`.
        let huge = TRIANGLE_CM.replace(r#"count="9">"#, r#"count="4000000000">"#);
        let e = parse(huge.as_bytes()).expect_err("refused");
        assert!(
            e.to_string().contains("more items than the file has bytes"),
            "{e}"
        );
        let mut padded =
            TRIANGLE_CM.replace(r#"<triangles count="1">"#, r#"<triangles count="2000001">"#);
        padded.push_str(&" ".repeat(2_000_100));
        let e = parse(padded.as_bytes()).expect_err("refused");
        assert!(
            e.to_string().contains(
                "2000001 primitives declared by a COLLADA count, over the limit of 2000000"
            ),
            "{e}"
        );
        let offset = TRIANGLE_CM.replace(r#"offset="0""#, r#"offset = '99999999999999999999999'"#);
        let e = parse(offset.as_bytes()).expect_err("refused");
        assert!(e.to_string().contains("input offset over 15"), "{e}");
        // `account="…"` is not `count`.
        assert_eq!(attribute_u64(b"x account=\"5\"", b"count"), None);
        assert_eq!(attribute_u64(b"x count = '5'", b"count"), Some(5));
    }

    #[test]
    fn garbage_is_a_malformed_collada_error() {
        let error = parse(b"<COLLADA><oops").expect_err("not XML");
        assert!(matches!(
            error,
            MeshErrorKind::Malformed {
                format: "COLLADA",
                ..
            }
        ));
    }
}
