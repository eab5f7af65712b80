//! The binary container: the 12-byte header, the JSON and BIN chunks, and the JSON document.

use super::fields::property;
use crate::error::{GlbErrorKind, Result, glb_error};
use crate::glb::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};
use serde_json::Value;

fn truncated(what: &'static str, needed: u64, available: u64) -> crate::Error {
    glb_error(GlbErrorKind::Truncated {
        what,
        needed,
        available,
    })
}

fn read_u32(bytes: &[u8], at: usize, what: &'static str) -> Result<u32> {
    bytes
        .get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .ok_or_else(|| truncated(what, at as u64 + 4, bytes.len() as u64))
}

/// The 12-byte header: magic `glTF`, version 2, and a total length equal to the file's.
pub(super) fn check_header(bytes: &[u8]) -> Result<()> {
    if bytes.len() < 12 {
        return Err(truncated("header", 12, bytes.len() as u64));
    }
    if read_u32(bytes, 0, "header")? != GLB_MAGIC {
        return Err(glb_error(GlbErrorKind::BadMagic));
    }
    let version = read_u32(bytes, 4, "header")?;
    if version != 2 {
        return Err(glb_error(GlbErrorKind::Version { version }));
    }
    let length = u64::from(read_u32(bytes, 8, "header")?);
    if length != bytes.len() as u64 {
        return Err(glb_error(GlbErrorKind::LengthMismatch {
            header: length,
            actual: bytes.len() as u64,
        }));
    }
    Ok(())
}

/// The chunks after the header: a JSON chunk, then at most one BIN chunk, each of a length
/// that is a multiple of 4. Returns the JSON chunk's data and the BIN chunk's (empty when
/// absent).
pub(super) fn split_chunks(bytes: &[u8]) -> Result<(&[u8], &[u8])> {
    let mut chunks: Vec<&[u8]> = Vec::new();
    let mut at = 12usize;
    while at < bytes.len() {
        let chunk_length = read_u32(bytes, at, "chunk header")? as usize;
        let chunk_type = read_u32(bytes, at + 4, "chunk header")?;
        let end = at + 8 + chunk_length;
        let data = bytes
            .get(at + 8..end)
            .ok_or_else(|| truncated("chunk", end as u64, bytes.len() as u64))?;
        let index = chunks.len();
        let chunk_rule = |reason| {
            glb_error(GlbErrorKind::Chunk {
                index,
                chunk_type,
                length: chunk_length as u64,
                reason,
            })
        };
        if !chunk_length.is_multiple_of(4) {
            return Err(chunk_rule("length is not a multiple of 4"));
        }
        match (index, chunk_type) {
            (0, CHUNK_JSON) | (1, CHUNK_BIN) => {}
            (0, _) => return Err(chunk_rule("the first chunk must be JSON")),
            (1, _) => return Err(chunk_rule("the second chunk must be BIN")),
            _ => return Err(chunk_rule("this writer never emits more than two chunks")),
        }
        chunks.push(data);
        at = end;
    }
    let json = chunks
        .first()
        .copied()
        .ok_or_else(|| truncated("JSON chunk", 20, bytes.len() as u64))?;
    Ok((json, chunks.get(1).copied().unwrap_or(&[])))
}

/// The JSON chunk parsed, with `asset.version` "2.0".
pub(super) fn parse_document(json_bytes: &[u8]) -> Result<Value> {
    let root: Value = serde_json::from_slice(json_bytes).map_err(|e| {
        glb_error(GlbErrorKind::Json {
            detail: e.to_string(),
        })
    })?;
    if root
        .get("asset")
        .and_then(|a| a.get("version"))
        .and_then(Value::as_str)
        != Some("2.0")
    {
        return Err(property("asset", 0, "version"));
    }
    Ok(root)
}
