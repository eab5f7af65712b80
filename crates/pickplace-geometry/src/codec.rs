//! The cluster database's binary format, and the fixed-width encoding other crates' cache
//! entries use ([`to_fixed_bytes`]). Every bincode encode and decode call of this crate and of
//! the grasp crate lives here (bincode is pinned at 2.0.1 and no longer maintained upstream).
//!
//! Layout:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `PPCLUSTR` |
//! | 4 | format version, u32 little-endian ([`FORMAT_VERSION`]) |
//! | 4 | header length `H`, u32 little-endian |
//! | H | header (bincode, standard config): mesh hash, parameters, clustering algorithm version, payload length and hash |
//! | rest | payload (bincode): triangle count, clusters, pairs |
//!
//! Decoding checks, in order: magic, version, header, mesh hash, every parameter, the
//! clustering algorithm's version ([`crate::cluster::ALGORITHM_VERSION`]), payload
//! length and checksum, payload. Arbitrary bytes give a [`DatabaseErrorKind`], never a panic
//! and never a wrongly decoded database.

use crate::cluster::{Cluster, ClusterPair, ClusterParams, Clustering};
use crate::db::ClusterDatabase;
use crate::error::DatabaseErrorKind;
use crate::hash::hash_bytes;

/// First eight bytes of every cluster database.
pub const MAGIC: [u8; 8] = *b"PPCLUSTR";
/// Version of the format written and read by this build. Bump it whenever a serialized type
/// or the mesh hash changes (2: the merge pass, canonical triangle order and pairing of issue
/// 17; 3: the header carries [`crate::cluster::ALGORITHM_VERSION`], which is bumped instead
/// when the clustering algorithm changes what it computes).
pub const FORMAT_VERSION: u32 = 3;

#[derive(Debug, serde::Serialize, serde::Deserialize)]
struct Header {
    mesh_hash: u64,
    params: ClusterParams,
    algorithm_version: u32,
    payload_len: u64,
    payload_hash: u64,
}

#[derive(serde::Serialize)]
struct PayloadRef<'a> {
    triangle_count: u64,
    clusters: &'a [Cluster],
    pairs: &'a [ClusterPair],
}

#[derive(serde::Deserialize)]
struct Payload {
    triangle_count: u64,
    clusters: Vec<Cluster>,
    pairs: Vec<ClusterPair>,
}

fn config() -> bincode::config::Configuration {
    bincode::config::standard()
}

/// Largest value [`to_fixed_bytes`] encodes and [`from_fixed_bytes`] decodes (bytes).
pub const MAX_FIXED: usize = 256 << 20;

fn fixed_config() -> impl bincode::config::Config {
    bincode::config::standard()
        .with_little_endian()
        .with_fixed_int_encoding()
        .with_limit::<MAX_FIXED>()
}

/// `value` in the fixed-width encoding other crates' cache entries store (bincode,
/// little-endian, fixed-size integers; the grasp sets and their keys): the one place outside
/// the roadmap codec where the workspace calls bincode. `None` when it cannot be encoded (over
/// [`MAX_FIXED`] bytes).
pub fn to_fixed_bytes<T: serde::Serialize>(value: &T) -> Option<Vec<u8>> {
    bincode::serde::encode_to_vec(value, fixed_config()).ok()
}

/// The value [`to_fixed_bytes`] encoded in `bytes`; `None` when they are not exactly one
/// such value.
pub fn from_fixed_bytes<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Option<T> {
    match bincode::serde::decode_from_slice(bytes, fixed_config()) {
        Ok((value, used)) if used == bytes.len() => Some(value),
        _ => None,
    }
}

/// Encodes a database.
pub fn encode(db: &ClusterDatabase) -> Vec<u8> {
    encode_as(db, crate::cluster::ALGORITHM_VERSION)
}

/// Encodes a database as if built by the clustering algorithm's version `algorithm_version`.
fn encode_as(db: &ClusterDatabase, algorithm_version: u32) -> Vec<u8> {
    let payload = PayloadRef {
        triangle_count: db.triangle_count as u64,
        clusters: &db.clustering.clusters,
        pairs: &db.clustering.pairs,
    };
    // Plain structs of numbers and vectors: serialising them into memory cannot fail.
    let payload = bincode::serde::encode_to_vec(&payload, config())
        .expect("in-memory encoding of plain data");
    let header = Header {
        mesh_hash: db.mesh_hash,
        params: db.clustering.params,
        algorithm_version,
        payload_len: payload.len() as u64,
        payload_hash: hash_bytes(&payload),
    };
    let header =
        bincode::serde::encode_to_vec(&header, config()).expect("in-memory encoding of plain data");
    let mut out = Vec::with_capacity(16 + header.len() + payload.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    out.extend_from_slice(&header);
    out.extend_from_slice(&payload);
    out
}

fn corrupt(detail: impl Into<String>) -> DatabaseErrorKind {
    DatabaseErrorKind::Corrupt {
        detail: detail.into(),
    }
}

fn mismatch(
    what: &'static str,
    found: impl ToString,
    expected: impl ToString,
) -> DatabaseErrorKind {
    DatabaseErrorKind::Mismatch {
        what,
        found: found.to_string(),
        expected: expected.to_string(),
    }
}

fn check_params(found: &ClusterParams, expected: &ClusterParams) -> Result<(), DatabaseErrorKind> {
    if found.mode != expected.mode {
        return Err(mismatch("mode", found.mode.name(), expected.mode.name()));
    }
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
    if !same(found.h_max, expected.h_max) {
        return Err(mismatch("h_max", found.h_max, expected.h_max));
    }
    if !same(found.max_facet_angle, expected.max_facet_angle) {
        return Err(mismatch(
            "max_facet_angle",
            found.max_facet_angle,
            expected.max_facet_angle,
        ));
    }
    if !same(found.opposite_dot, expected.opposite_dot) {
        return Err(mismatch(
            "opposite_dot",
            found.opposite_dot,
            expected.opposite_dot,
        ));
    }
    Ok(())
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b: [u8; 4] = bytes.get(at..at + 4)?.try_into().ok()?;
    Some(u32::from_le_bytes(b))
}

/// Decodes a database built for the mesh with hash `expected_hash` and the parameters
/// `expected`.
///
/// # Errors
/// [`DatabaseErrorKind::BadMagic`], [`DatabaseErrorKind::Version`],
/// [`DatabaseErrorKind::Mismatch`] (mesh hash or a parameter) or
/// [`DatabaseErrorKind::Corrupt`].
pub fn decode(
    bytes: &[u8],
    expected_hash: u64,
    expected: &ClusterParams,
) -> Result<ClusterDatabase, DatabaseErrorKind> {
    if bytes.get(..8) != Some(&MAGIC[..]) {
        return Err(DatabaseErrorKind::BadMagic);
    }
    let version = u32_at(bytes, 8).ok_or_else(|| corrupt("truncated before the version"))?;
    if version != FORMAT_VERSION {
        return Err(DatabaseErrorKind::Version {
            found: version,
            expected: FORMAT_VERSION,
        });
    }
    let header_len =
        u32_at(bytes, 12).ok_or_else(|| corrupt("truncated before the header"))? as usize;
    let header_bytes = bytes
        .get(16..16usize.saturating_add(header_len))
        .ok_or_else(|| corrupt("truncated header"))?;
    let (header, used): (Header, usize) = bincode::serde::decode_from_slice(header_bytes, config())
        .map_err(|e| corrupt(format!("header: {e}")))?;
    if used != header_len {
        return Err(corrupt("header length does not match its content"));
    }
    if header.mesh_hash != expected_hash {
        return Err(mismatch(
            "mesh hash",
            format!("{:016x}", header.mesh_hash),
            format!("{expected_hash:016x}"),
        ));
    }
    check_params(&header.params, expected)?;
    if header.algorithm_version != crate::cluster::ALGORITHM_VERSION {
        return Err(mismatch(
            "clustering algorithm version",
            header.algorithm_version,
            crate::cluster::ALGORITHM_VERSION,
        ));
    }
    let payload = &bytes[16 + header_len..];
    if payload.len() as u64 != header.payload_len {
        return Err(corrupt(format!(
            "payload is {} bytes, the header says {}",
            payload.len(),
            header.payload_len
        )));
    }
    if hash_bytes(payload) != header.payload_hash {
        return Err(corrupt("payload checksum mismatch"));
    }
    let (p, used): (Payload, usize) = bincode::serde::decode_from_slice(payload, config())
        .map_err(|e| corrupt(format!("payload: {e}")))?;
    if used != payload.len() {
        return Err(corrupt("trailing bytes after the payload"));
    }
    let triangle_count = usize::try_from(p.triangle_count)
        .ok()
        .filter(|&n| n <= crate::mesh::MAX_MESH_TRIANGLES)
        .ok_or_else(|| {
            corrupt(format!(
                "triangle count {} is over the mesh limit of {}",
                p.triangle_count,
                crate::mesh::MAX_MESH_TRIANGLES
            ))
        })?;
    for (i, c) in p.clusters.iter().enumerate() {
        if c.id as usize != i {
            return Err(corrupt(format!("cluster {i} carries id {}", c.id)));
        }
        if c.triangles.iter().any(|&t| t as usize >= triangle_count) {
            return Err(corrupt(format!(
                "cluster {} refers to a triangle beyond {triangle_count}",
                c.id
            )));
        }
    }
    let n = p.clusters.len() as u32;
    if p.pairs.iter().any(|q| q.first >= n || q.second >= n) {
        return Err(corrupt("a pair refers to a missing cluster"));
    }
    Ok(ClusterDatabase {
        mesh_hash: header.mesh_hash,
        triangle_count,
        clustering: Clustering {
            params: header.params,
            clusters: p.clusters,
            pairs: p.pairs,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::box_mesh;

    #[test]
    fn a_database_of_another_algorithm_version_is_a_mismatch() {
        let mesh = box_mesh([0.05, 0.03, 0.02]);
        let params = ClusterParams::finger();
        let db = ClusterDatabase::build(&mesh, &params).expect("clusters");
        let hash = db.mesh_hash;
        assert_eq!(
            decode(&encode(&db), hash, &params).expect("same version"),
            db
        );
        let older = encode_as(&db, crate::cluster::ALGORITHM_VERSION.wrapping_sub(1));
        let e = decode(&older, hash, &params).expect_err("another algorithm");
        assert!(
            matches!(
                &e,
                DatabaseErrorKind::Mismatch {
                    what: "clustering algorithm version",
                    ..
                }
            ),
            "{e:?}"
        );
    }

    /// A database file around `payload`, with a valid header for mesh hash 7.
    fn file(payload: &[u8], params: ClusterParams) -> Vec<u8> {
        let header = Header {
            mesh_hash: 7,
            params,
            algorithm_version: crate::cluster::ALGORITHM_VERSION,
            payload_len: payload.len() as u64,
            payload_hash: hash_bytes(payload),
        };
        let header = bincode::serde::encode_to_vec(&header, config()).expect("encode");
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(header.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&header);
        bytes.extend_from_slice(payload);
        bytes
    }

    #[test]
    fn counts_a_payload_cannot_hold_are_errors_not_allocations() {
        // Regression (issue 18): a vector length of 2^62 clusters with a valid checksum is a
        // decoding error at once (bincode's serde path reserves at most a bounded amount).
        let params = ClusterParams::environment();
        let mut payload = vec![0u8];
        payload.push(0xFD);
        payload.extend_from_slice(&(1u64 << 62).to_le_bytes());
        let e = decode(&file(&payload, params), 7, &params).expect_err("refused");
        assert!(matches!(e, DatabaseErrorKind::Corrupt { .. }), "{e}");
        // A triangle count over the mesh limit, with no clusters.
        let mut payload = vec![0xFC];
        payload.extend_from_slice(&3_000_000u32.to_le_bytes());
        payload.extend_from_slice(&[0, 0]);
        let e = decode(&file(&payload, params), 7, &params).expect_err("refused");
        assert!(
            e.to_string()
                .contains("triangle count 3000000 is over the mesh limit of 2000000"),
            "{e}"
        );
    }
}
