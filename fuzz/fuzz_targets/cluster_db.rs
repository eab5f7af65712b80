//! The cluster database decoder (`pickplace_geometry::codec::decode`).
//!
//! The first byte chooses the mode; the second the expected parameters (environment or finger
//! clustering); the expected mesh hash is the one the seeds were built for ([`SEED_MESH_HASH`]).
//! * mode even: the rest is a whole database file, decoded as it is (magic, version, header,
//!   checksum checks).
//! * mode odd: the rest is a payload; a valid header is built around it (right hash, parameters,
//!   length and checksum), so the fuzzer reaches the payload decoder and its consistency checks
//!   instead of stopping at the checksum.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::codec::{FORMAT_VERSION, MAGIC, decode};
use pickplace_geometry::hash::hash_bytes;

/// `mesh_hash` of the shipped `meshes/can.stl`, which the seeds were built from
/// (`cargo xtask fuzz-seeds` writes the seeds and checks this value).
const SEED_MESH_HASH: u64 = include!("../seeds/cluster_db.hash");

fuzz_target!(|data: &[u8]| {
    let [mode, which, rest @ ..] = data else {
        return;
    };
    let params = if which % 2 == 0 {
        ClusterParams::environment()
    } else {
        ClusterParams::finger()
    };
    let bytes = if mode % 2 == 0 {
        rest.to_vec()
    } else {
        let header = (
            SEED_MESH_HASH,
            params.clone(),
            pickplace_geometry::cluster::ALGORITHM_VERSION,
            rest.len() as u64,
            hash_bytes(rest),
        );
        let header = bincode::serde::encode_to_vec(&header, bincode::config::standard())
            .expect("a header encodes");
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(header.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&header);
        bytes.extend_from_slice(rest);
        bytes
    };
    if let Ok(db) = decode(&bytes, SEED_MESH_HASH, &params) {
        // A decoded database re-encodes, and decodes again to the same content.
        let again = pickplace_geometry::codec::encode(&db);
        assert!(
            decode(&again, SEED_MESH_HASH, &params).is_ok(),
            "re-encoded database rejected"
        );
    }
});
