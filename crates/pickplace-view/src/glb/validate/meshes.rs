//! Meshes and their primitives: attributes, materials and indices.

use super::buffers::Accessor;
use super::fields::{list, optional_u64, property, reference, rule};
use crate::error::Result;
use serde_json::Value;

/// Totals over every mesh primitive.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct MeshTotals {
    /// Number of meshes.
    pub(super) count: usize,
    pub(super) triangles: u64,
    pub(super) vertices: u64,
    pub(super) coloured_primitives: usize,
}

/// Every mesh: at least one primitive, each checked by [`check_primitive`].
pub(super) fn check_meshes(
    root: &Value,
    accessors: &[Accessor],
    materials: usize,
    bin: &[u8],
) -> Result<MeshTotals> {
    let meshes = list(root, "meshes")?;
    let mut totals = MeshTotals {
        count: meshes.len(),
        ..MeshTotals::default()
    };
    for (m, mesh) in meshes.iter().enumerate() {
        let primitives = mesh
            .get("primitives")
            .and_then(Value::as_array)
            .filter(|p| !p.is_empty())
            .ok_or_else(|| property("mesh", m, "primitives"))?;
        for p in primitives {
            check_primitive(m, p, accessors, materials, bin, &mut totals)?;
        }
    }
    Ok(totals)
}

/// One primitive of mesh `m`: attributes referring to accessors of one count, a float VEC3
/// `POSITION` with min and max, unit `NORMAL`s, a material in range, unsigned integer indices
/// below the vertex count and, for triangle lists, a multiple of 3 corners. Adds its
/// triangles, vertices and colour to `totals`.
pub(super) fn check_primitive(
    m: usize,
    p: &Value,
    accessors: &[Accessor],
    materials: usize,
    bin: &[u8],
    totals: &mut MeshTotals,
) -> Result<()> {
    let attributes = p
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| property("mesh", m, "attributes"))?;
    let mut vertex_count = None;
    for (name, value) in attributes {
        let index = value
            .as_u64()
            .filter(|&x| x < accessors.len() as u64)
            .ok_or_else(|| rule("mesh", m, "an attribute refers to a missing accessor"))?
            as usize;
        let a = &accessors[index];
        if *vertex_count.get_or_insert(a.count) != a.count {
            return Err(rule(
                "mesh",
                m,
                "attributes of a primitive must have the same count",
            ));
        }
        if name == "POSITION"
            && (a.type_name != "VEC3" || a.component_type != 5126 || a.min.is_none())
        {
            return Err(rule(
                "mesh",
                m,
                "POSITION must be a float VEC3 accessor with min and max",
            ));
        }
        if name == "NORMAL" {
            for e in 0..a.count {
                let n: f64 = (0..3)
                    .map(|k| a.component(bin, e, k).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if (n - 1.0).abs() > 1e-3 {
                    return Err(rule("mesh", m, "NORMAL values must be unit vectors"));
                }
            }
        }
        if name == "COLOR_0" {
            totals.coloured_primitives += 1;
        }
    }
    let vertex_count = attributes
        .get("POSITION")
        .and(vertex_count)
        .ok_or_else(|| property("mesh", m, "POSITION"))?;
    reference(p, "mesh", m, "material", materials)?;
    let mode = optional_u64(p, "mesh", m, "mode")?.unwrap_or(4);
    let corner_count = match reference(p, "mesh", m, "indices", accessors.len())? {
        Some(k) => {
            let a = &accessors[k];
            if a.type_name != "SCALAR" || !matches!(a.component_type, 5121 | 5123 | 5125) {
                return Err(rule("mesh", m, "indices must be unsigned integer scalars"));
            }
            if (0..a.count).any(|e| a.component(bin, e, 0) as u64 >= vertex_count) {
                return Err(rule("mesh", m, "an index is not below the vertex count"));
            }
            a.count
        }
        None => vertex_count,
    };
    if mode == 4 {
        if corner_count % 3 != 0 {
            return Err(rule(
                "mesh",
                m,
                "a triangle list needs a multiple of 3 corners",
            ));
        }
        totals.triangles += corner_count / 3;
    }
    totals.vertices += vertex_count;
    Ok(())
}
