//! The PRM roadmap decoder (`pickplace_prm::codec`).
//!
//! The first byte chooses the mode; the rest is a roadmap file. The joint space passed to
//! `decode` is the one the file's header declares (when the header reads and the space is
//! valid), so the fuzzer gets past the space check.
//! * mode even: decoded as it is (length and checksum checks included).
//! * mode odd: the header's body length and checksum are recomputed for the body that follows
//!   it, so that mutated bodies reach the body decoder and the roadmap's own checks.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_prm::JointSpace;
use pickplace_prm::codec::{FORMAT_VERSION, MAGIC, decode, read_header};

/// FNV-1a 64, the codec's body checksum (restated here: the codec keeps it private).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash = 0xCBF2_9CE4_8422_2325u64;
    for &byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01B3);
    }
    hash
}

fuzz_target!(|data: &[u8]| {
    let [mode, rest @ ..] = data else {
        return;
    };
    let Ok(mut header) = read_header(rest) else {
        return;
    };
    let Ok(space) = JointSpace::new(
        header.lower.clone(),
        header.upper.clone(),
        header.weights.clone(),
    ) else {
        return;
    };
    let bytes = if mode % 2 == 0 {
        rest.to_vec()
    } else {
        let Some(header_len) = rest
            .get(12..16)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
        else {
            return;
        };
        let Some(body) = rest.get(16 + header_len..) else {
            return;
        };
        header.body_len = body.len() as u64;
        header.body_checksum = fnv1a(body);
        let encoded = bincode::serde::encode_to_vec(&header, bincode::config::standard())
            .expect("a header encodes");
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(encoded.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&encoded);
        bytes.extend_from_slice(body);
        bytes
    };
    if let Ok(roadmap) = decode(&bytes, &space) {
        let _ = roadmap.component_count();
        if let Ok(again) = pickplace_prm::codec::encode(&roadmap) {
            assert!(
                decode(&again, &space).is_ok(),
                "re-encoded roadmap rejected"
            );
        }
    }
});
