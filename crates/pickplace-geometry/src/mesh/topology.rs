//! Edge adjacency of a triangle mesh.

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
    ///
    /// # Performance
    /// Two sorts of `3 n` entries (edges with their triangle, then triangle pairs): no hash
    /// map and no allocation per edge or triangle.
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        let _ = vertex_count;
        // Undirected edge and the triangle using it, grouped by edge.
        let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let (a, b) = if a < b { (a, b) } else { (b, a) };
                edges.push((a, b, t as u32));
            }
        }
        edges.sort_unstable();
        // Every ordered pair of distinct triangles on one edge.
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(edges.len());
        let mut boundary_edges = 0;
        let mut non_manifold_edges = 0;
        for users in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            match users.len() {
                1 => boundary_edges += 1,
                2 => {}
                _ => non_manifold_edges += 1,
            }
            for &(_, _, a) in users {
                for &(_, _, b) in users {
                    if a != b {
                        pairs.push((a, b));
                    }
                }
            }
        }
        // Sorted and unique so that every traversal is deterministic.
        pairs.sort_unstable();
        pairs.dedup();
        let mut offsets = Vec::with_capacity(triangles.len() + 1);
        let mut neighbours = Vec::with_capacity(pairs.len());
        offsets.push(0);
        let mut next = pairs.iter().peekable();
        for t in 0..triangles.len() as u32 {
            while let Some(&(_, b)) = next.next_if(|(a, _)| *a == t) {
                neighbours.push(b);
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::HashMap;

    /// The adjacency as it was written first (a map of edges to their triangles): the
    /// reference the sorting one must agree with exactly.
    fn reference(triangles: &[[u32; 3]]) -> Adjacency {
        let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
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
        let mut offsets = vec![0];
        let mut neighbours = Vec::new();
        for mut list in lists {
            list.sort_unstable();
            list.dedup();
            neighbours.extend_from_slice(&list);
            offsets.push(neighbours.len() as u32);
        }
        Adjacency {
            offsets,
            neighbours,
            boundary_edges,
            non_manifold_edges,
        }
    }

    proptest! {
        /// Random triangles over a few vertices (shared, boundary and non-manifold edges, a
        /// triangle repeated): the same neighbours and counts as the map of edges.
        #[test]
        fn the_sorted_adjacency_agrees_with_the_map_of_edges(
            raw in proptest::collection::vec((0u32..8, 0u32..8, 0u32..8), 0..60),
        ) {
            let triangles: Vec<[u32; 3]> = raw
                .into_iter()
                .filter(|(a, b, c)| a != b && b != c && a != c)
                .map(|(a, b, c)| [a, b, c])
                .collect();
            let fast = Adjacency::new(&triangles, 8);
            let slow = reference(&triangles);
            prop_assert_eq!(&fast.offsets, &slow.offsets);
            prop_assert_eq!(&fast.neighbours, &slow.neighbours);
            prop_assert_eq!(fast.boundary_edges, slow.boundary_edges);
            prop_assert_eq!(fast.non_manifold_edges, slow.non_manifold_edges);
        }
    }
}
