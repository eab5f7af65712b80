//! Edge adjacency of a triangle mesh.

use std::collections::HashMap;

/// Which triangles share an edge with which. Manifold edges link two triangles; a
/// non-manifold edge (three or more triangles) links all of them pairwise; a boundary edge
/// links none.
#[derive(Debug, Clone, Default)]
pub struct Adjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    boundary_edges: usize,
    non_manifold_edges: usize,
}

impl Adjacency {
    /// Builds the adjacency of `triangles` (indices below `vertex_count`).
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        let _ = vertex_count;
        // Undirected edge -> triangles using it, in triangle order.
        let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::with_capacity(triangles.len() * 2);
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let key = if a < b { (a, b) } else { (b, a) };
                edges.entry(key).or_default().push(t as u32);
            }
        }
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); triangles.len()];
        let mut boundary_edges = 0;
        let mut non_manifold_edges = 0;
        for users in edges.values() {
            match users.len() {
                1 => boundary_edges += 1,
                2 => {}
                _ => non_manifold_edges += 1,
            }
            for &a in users {
                for &b in users {
                    if a != b {
                        lists[a as usize].push(b);
                    }
                }
            }
        }
        let mut offsets = Vec::with_capacity(triangles.len() + 1);
        let mut neighbours = Vec::with_capacity(triangles.len() * 3);
        offsets.push(0);
        for mut list in lists {
            // Sorted and unique so that every traversal is deterministic.
            list.sort_unstable();
            list.dedup();
            neighbours.extend_from_slice(&list);
            offsets.push(neighbours.len() as u32);
        }
        Self {
            offsets,
            neighbours,
            boundary_edges,
            non_manifold_edges,
        }
    }

    /// Triangles sharing an edge with `triangle`, in increasing order.
    pub fn neighbours(&self, triangle: usize) -> &[u32] {
        &self.neighbours[self.offsets[triangle] as usize..self.offsets[triangle + 1] as usize]
    }

    /// Number of edges used by one triangle.
    pub fn boundary_edges(&self) -> usize {
        self.boundary_edges
    }

    /// Number of edges used by three or more triangles.
    pub fn non_manifold_edges(&self) -> usize {
        self.non_manifold_edges
    }
}
