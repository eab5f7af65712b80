//! The roadmap's binary format, so that roadmaps can be built once per planning group (`cargo
//! xtask precompute`) and loaded by every run. Every bincode call of this crate lives here
//! (bincode is pinned at 2.0.1 and no longer maintained upstream).
//!
//! Layout:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `PPRDMAP\0` ([`MAGIC`]) |
//! | 4 | format version, u32 little-endian ([`FORMAT_VERSION`]) |
//! | 4 | header length `H`, u32 little-endian |
//! | H | header (bincode, standard config): the space (dimension, bounds, weights), the build options (with the seed), the validation, node and edge counts, body length and checksum |
//! | rest | body (bincode): states, edges |
//!
//! Decoding checks, in order: magic, version, header, that the stored space is the caller's
//! (dimension, then every bound and weight bit for bit), body length and checksum, body, and
//! finally the roadmap itself (states in bounds, edges sorted and in range). Arbitrary bytes
//! give an [`Error`], never a panic.

use crate::error::{Error, Result};
use crate::roadmap::{Roadmap, RoadmapOptions, Validation};
use crate::space::JointSpace;

/// First eight bytes of every roadmap file.
pub const MAGIC: [u8; 8] = *b"PPRDMAP\0";
/// Version of the format written and read by this build. Bump it whenever a serialized type,
/// the sampling streams or the construction algorithm changes (a stored roadmap would no longer
/// be the one its options build).
pub const FORMAT_VERSION: u32 = 1;

const PREFIX: usize = 16;

/// What a roadmap file says about itself, readable without knowing its space.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RoadmapHeader {
    /// Number of joints of the space.
    pub dimension: u32,
    /// Lower joint bounds.
    pub lower: Vec<f64>,
    /// Upper joint bounds.
    pub upper: Vec<f64>,
    /// Distance weights.
    pub weights: Vec<f64>,
    /// Options the roadmap was built with (the seed is `options.seed`).
    pub options: RoadmapOptions,
    /// How nodes and edges were validated.
    pub validation: Validation,
    /// Number of nodes.
    pub node_count: u64,
    /// Number of edges.
    pub edge_count: u64,
    /// Length of the body in bytes.
    pub body_len: u64,
    /// FNV-1a 64 checksum of the body.
    pub body_checksum: u64,
}

#[derive(serde::Serialize)]
struct BodyRef<'a> {
    states: &'a [f64],
    edges: &'a [[u32; 2]],
}

#[derive(serde::Deserialize)]
struct Body {
    states: Vec<f64>,
    edges: Vec<[u32; 2]>,
}

fn config() -> bincode::config::Configuration {
    bincode::config::standard()
}

/// FNV-1a, 64 bits: a checksum against truncation and bit rot, not an adversary.
fn checksum(bytes: &[u8]) -> u64 {
    let mut hash = 0xCBF2_9CE4_8422_2325u64;
    for &byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01B3);
    }
    hash
}

/// Encodes a roadmap.
///
/// The bytes depend only on the roadmap (no time stamp, no map iteration): the same options give
/// the same bytes whatever the number of threads that built it.
///
/// # Errors
/// [`Error::Encode`] if bincode fails (it does not for in-memory buffers of plain data).
pub fn encode(roadmap: &Roadmap) -> Result<Vec<u8>> {
    let body = BodyRef {
        states: roadmap.states(),
        edges: roadmap.edges(),
    };
    let body = bincode::serde::encode_to_vec(&body, config())
        .map_err(|source| Error::Encode { source })?;
    let space = roadmap.space();
    let header = RoadmapHeader {
        dimension: space.dimension() as u32,
        lower: space.lower().to_vec(),
        upper: space.upper().to_vec(),
        weights: space.weights().to_vec(),
        options: roadmap.options().clone(),
        validation: roadmap.validation(),
        node_count: roadmap.node_count() as u64,
        edge_count: roadmap.edge_count() as u64,
        body_len: body.len() as u64,
        body_checksum: checksum(&body),
    };
    let header = bincode::serde::encode_to_vec(&header, config())
        .map_err(|source| Error::Encode { source })?;
    let mut out = Vec::with_capacity(PREFIX + header.len() + body.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    out.extend_from_slice(&header);
    out.extend_from_slice(&body);
    Ok(out)
}

fn u32_at(bytes: &[u8], at: usize) -> Result<u32> {
    let word: [u8; 4] = bytes
        .get(at..at + 4)
        .and_then(|b| b.try_into().ok())
        .ok_or(Error::CorruptRoadmap {
            what: "file truncated inside its prefix",
            index: bytes.len(),
        })?;
    Ok(u32::from_le_bytes(word))
}

/// Reads and checks the prefix and header; returns the header and the body's offset.
fn split(bytes: &[u8]) -> Result<(RoadmapHeader, usize)> {
    if bytes.get(..MAGIC.len()) != Some(&MAGIC[..]) {
        let mut found = [0u8; 8];
        let n = bytes.len().min(8);
        found[..n].copy_from_slice(&bytes[..n]);
        return Err(Error::BadMagic { found });
    }
    let version = u32_at(bytes, 8)?;
    if version != FORMAT_VERSION {
        return Err(Error::UnsupportedVersion {
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    let header_len = u32_at(bytes, 12)? as usize;
    let end = PREFIX.saturating_add(header_len);
    let header_bytes = bytes.get(PREFIX..end).ok_or(Error::CorruptRoadmap {
        what: "file truncated inside the header",
        index: bytes.len(),
    })?;
    let (header, used): (RoadmapHeader, usize) =
        bincode::serde::decode_from_slice(header_bytes, config())
            .map_err(|source| Error::Decode { source })?;
    if used != header_len {
        return Err(Error::CorruptRoadmap {
            what: "header length does not match its content",
            index: PREFIX + used,
        });
    }
    Ok((header, end))
}

/// Reads the header of a roadmap file without decoding its body.
///
/// # Errors
/// [`Error::BadMagic`], [`Error::UnsupportedVersion`], [`Error::CorruptRoadmap`],
/// [`Error::Decode`].
pub fn read_header(bytes: &[u8]) -> Result<RoadmapHeader> {
    split(bytes).map(|(header, _)| header)
}

/// Checks that the stored space is `space`, bit for bit.
fn check_space(header: &RoadmapHeader, space: &JointSpace) -> Result<()> {
    let stored = header.dimension as usize;
    if stored != space.dimension() {
        return Err(Error::DimensionMismatch {
            stored,
            expected: space.dimension(),
        });
    }
    for (field, found, expected) in [
        ("lower bound", &header.lower, space.lower()),
        ("upper bound", &header.upper, space.upper()),
        ("weight", &header.weights, space.weights()),
    ] {
        if found.len() != stored {
            return Err(Error::CorruptRoadmap {
                what: "space vector length differs from the stored dimension",
                index: found.len(),
            });
        }
        if let Some(joint) = (0..stored).find(|&j| found[j].to_bits() != expected[j].to_bits()) {
            return Err(Error::SpaceMismatch {
                joint,
                field,
                stored: found[joint],
                expected: expected[joint],
            });
        }
    }
    Ok(())
}

/// Decodes a roadmap built for `space`.
///
/// # Errors
/// [`Error::BadMagic`] and [`Error::UnsupportedVersion`] for another file;
/// [`Error::DimensionMismatch`] or [`Error::SpaceMismatch`] when the roadmap was built for
/// another space; [`Error::CorruptRoadmap`], [`Error::Decode`] or [`Error::InvalidOption`] for a
/// damaged file.
///
/// # Performance
/// Linear in the file size, plus the k-d tree rebuild (`O(n log n)`).
pub fn decode(bytes: &[u8], space: &JointSpace) -> Result<Roadmap> {
    let (header, offset) = split(bytes)?;
    check_space(&header, space)?;
    let body = &bytes[offset..];
    if body.len() as u64 != header.body_len {
        return Err(Error::CorruptRoadmap {
            what: "body length differs from the header's",
            index: body.len(),
        });
    }
    if checksum(body) != header.body_checksum {
        return Err(Error::CorruptRoadmap {
            what: "body checksum mismatch",
            index: offset,
        });
    }
    // The counts of the header, bounded by the bytes that are there before anything is
    // decoded: a state value is 8 bytes, an edge at least 2 (two varints).
    let state_values = header
        .node_count
        .checked_mul(u64::from(header.dimension))
        .filter(|&n| n.saturating_mul(8) <= header.body_len);
    if state_values.is_none() || header.edge_count.saturating_mul(2) > header.body_len {
        return Err(Error::CorruptRoadmap {
            what: "node or edge count larger than the body can hold",
            index: offset,
        });
    }
    let (body, used): (Body, usize) = bincode::serde::decode_from_slice(body, config())
        .map_err(|source| Error::Decode { source })?;
    if used != header.body_len as usize {
        return Err(Error::CorruptRoadmap {
            what: "trailing bytes after the body",
            index: offset + used,
        });
    }
    if Some(body.states.len() as u64) != header.node_count.checked_mul(u64::from(header.dimension))
    {
        return Err(Error::CorruptRoadmap {
            what: "node count differs from the header's",
            index: body.states.len(),
        });
    }
    if body.edges.len() as u64 != header.edge_count {
        return Err(Error::CorruptRoadmap {
            what: "edge count differs from the header's",
            index: body.edges.len(),
        });
    }
    Roadmap::from_parts(
        space.clone(),
        header.options,
        header.validation,
        body.states,
        body.edges,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn space() -> JointSpace {
        JointSpace::new(
            vec![-1.0, 0.0, -2.0],
            vec![1.0, 2.0, 2.0],
            vec![1.0, 0.5, 2.0],
        )
        .expect("space")
    }

    fn roadmap() -> Roadmap {
        let options = RoadmapOptions {
            node_count: 120,
            neighbors: 6,
            seed: 11,
            ..RoadmapOptions::default()
        };
        Roadmap::build_lazy(&space(), &options).expect("roadmap")
    }

    /// `bytes` with its body replaced by `body` and the header's length and checksum fixed.
    fn with_body(bytes: &[u8], body: &[u8], node_count: u64) -> Vec<u8> {
        let mut header = read_header(bytes).expect("header");
        header.body_len = body.len() as u64;
        header.body_checksum = checksum(body);
        header.node_count = node_count;
        header.edge_count = 0;
        let header = bincode::serde::encode_to_vec(&header, config()).expect("encode");
        let mut out = bytes[..8 + 4].to_vec();
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
        out.extend_from_slice(&header);
        out.extend_from_slice(body);
        out
    }

    #[test]
    fn counts_beyond_the_body_are_refused_before_allocating() {
        // Regression (issue 18): a body whose vector length claims 2^62 states, with the
        // checksum right, is an error (no allocation of the claimed size, no abort).
        let bytes = encode(&roadmap()).expect("encode");
        let mut body = vec![0xFD];
        body.extend_from_slice(&(1u64 << 62).to_le_bytes());
        body.push(0);
        let e = decode(&with_body(&bytes, &body, 1u64 << 60), &space()).expect_err("refused");
        assert!(e.to_string().contains("larger than the body"), "{e}");
        // The header's counts agree with the body's size but the vector length lies.
        body.resize(8 * 3 + 10, 0);
        let e = decode(&with_body(&bytes, &body, 1), &space()).expect_err("refused");
        assert!(matches!(e, Error::Decode { .. }), "{e}");
    }

    #[test]
    fn round_trip_is_exact() {
        let roadmap = roadmap();
        let bytes = encode(&roadmap).expect("encode");
        let back = decode(&bytes, &space()).expect("decode");
        assert_eq!(back, roadmap);
        assert_eq!(back.component_count(), roadmap.component_count());
        assert_eq!(encode(&back).expect("encode"), bytes);
        let header = read_header(&bytes).expect("header");
        assert_eq!(header.dimension, 3);
        assert_eq!(header.options.seed, 11);
        assert_eq!(header.node_count, 120);
        assert_eq!(header.validation, Validation::Lazy);
    }

    #[test]
    fn another_space_is_a_clear_error() {
        let bytes = encode(&roadmap()).expect("encode");
        let flat = JointSpace::with_unit_weights(vec![-1.0, 0.0], vec![1.0, 2.0]).expect("space");
        assert!(matches!(
            decode(&bytes, &flat),
            Err(Error::DimensionMismatch {
                stored: 3,
                expected: 2
            })
        ));
        let wider = JointSpace::new(
            vec![-1.0, 0.0, -2.0],
            vec![1.0, 2.5, 2.0],
            vec![1.0, 0.5, 2.0],
        )
        .expect("space");
        assert!(matches!(
            decode(&bytes, &wider),
            Err(Error::SpaceMismatch {
                joint: 1,
                field: "upper bound",
                ..
            })
        ));
        let reweighted = JointSpace::new(
            vec![-1.0, 0.0, -2.0],
            vec![1.0, 2.0, 2.0],
            vec![1.0, 0.5, 3.0],
        )
        .expect("space");
        assert!(matches!(
            decode(&bytes, &reweighted),
            Err(Error::SpaceMismatch {
                joint: 2,
                field: "weight",
                ..
            })
        ));
    }

    #[test]
    fn damaged_files_are_rejected() {
        let bytes = encode(&roadmap()).expect("encode");
        assert!(matches!(
            decode(b"PPRD", &space()),
            Err(Error::BadMagic { .. })
        ));
        let mut other = bytes.clone();
        other[8] = 9;
        assert!(matches!(
            decode(&other, &space()),
            Err(Error::UnsupportedVersion {
                found: 9,
                supported: FORMAT_VERSION
            })
        ));
        let mut flipped = bytes.clone();
        let last = flipped.len() - 1;
        flipped[last] ^= 0x40;
        assert!(matches!(
            decode(&flipped, &space()),
            Err(Error::CorruptRoadmap {
                what: "body checksum mismatch",
                ..
            })
        ));
        for cut in [0, 7, 12, 15, 20, bytes.len() / 2, bytes.len() - 1] {
            assert!(decode(&bytes[..cut], &space()).is_err(), "cut at {cut}");
        }
    }
}
