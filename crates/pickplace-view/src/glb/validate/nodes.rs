//! The node hierarchy (references, transforms, single parents, no cycle) and the scenes.

use super::fields::{floats, list, property, reference, rule};
use crate::error::{GlbErrorKind, Result, glb_error};
use serde_json::Value;

/// The node hierarchy: names and parents, in node order.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Nodes {
    pub(super) names: Vec<Option<String>>,
    pub(super) parents: Vec<Option<usize>>,
}

/// Every node: a mesh in range, a 3-vector translation, a unit quaternion rotation, children
/// in range with one parent each; then no cycle ([`check_acyclic`]).
pub(super) fn check_nodes(root: &Value, mesh_count: usize) -> Result<Nodes> {
    let nodes = list(root, "nodes")?;
    let mut parents: Vec<Option<usize>> = vec![None; nodes.len()];
    let mut names = Vec::with_capacity(nodes.len());
    for (i, node) in nodes.iter().enumerate() {
        reference(node, "node", i, "mesh", mesh_count)?;
        if let Some(t) = floats(node, "node", i, "translation")?
            && t.len() != 3
        {
            return Err(property("node", i, "translation"));
        }
        if let Some(q) = floats(node, "node", i, "rotation")? {
            let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if q.len() != 4 || (norm - 1.0).abs() > 1e-6 {
                return Err(rule("node", i, "rotation must be a unit quaternion"));
            }
        }
        if let Some(children) = node.get("children") {
            let children = children
                .as_array()
                .ok_or_else(|| property("node", i, "children"))?;
            for c in children {
                let c = c.as_u64().ok_or_else(|| property("node", i, "children"))?;
                if c >= nodes.len() as u64 {
                    return Err(glb_error(GlbErrorKind::Reference {
                        element: "node",
                        index: i,
                        property: "children",
                        value: c,
                        count: nodes.len(),
                    }));
                }
                if parents[c as usize].replace(i).is_some() {
                    return Err(rule("node", c as usize, "a node has more than one parent"));
                }
            }
        }
        names.push(node.get("name").and_then(Value::as_str).map(str::to_owned));
    }
    check_acyclic(&parents)?;
    Ok(Nodes { names, parents })
}

/// No node is its own ancestor: following parents from any node ends at a root.
pub(super) fn check_acyclic(parents: &[Option<usize>]) -> Result<()> {
    for start in 0..parents.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parents[at] {
            at = p;
            steps += 1;
            if steps > parents.len() {
                return Err(rule("node", start, "the node hierarchy has a cycle"));
            }
        }
    }
    Ok(())
}

/// Every scene lists existing root nodes.
pub(super) fn check_scenes(root: &Value, parents: &[Option<usize>]) -> Result<()> {
    for (s, scene) in list(root, "scenes")?.iter().enumerate() {
        for n in floats(scene, "scene", s, "nodes")?.unwrap_or_default() {
            let n = n as usize;
            if n >= parents.len() || parents[n].is_some() {
                return Err(rule("scene", s, "scene nodes must be existing root nodes"));
            }
        }
    }
    Ok(())
}
