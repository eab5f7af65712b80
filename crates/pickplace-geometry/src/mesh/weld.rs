//! Welding a triangle soup's positions, and the hash maps of the mesh builder.
//!
//! A file's soup repeats every corner once per triangle that uses it (a binary STL stores a
//! closed mesh's vertices six times over): exact copies are merged first, by their bits, and
//! only the first occurrence of a position searches the tolerance grid. The merged positions
//! and the mapping are those of searching every position (see [`weld`]); loading a
//! million-triangle environment mesh costs about a second instead of four (issue 33).

use crate::math::{Point3, Real};
use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// FxHash's multiply-and-rotate hasher (rustc's), for the builder's integer keys: grid cells,
/// bit patterns of positions, vertex triples. Deterministic; no map of the builder is iterated
/// in an order that reaches the mesh, so only its speed matters, not its spread under attack.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct IntHasher(u64);

/// FxHash's multiplier.
const SEED: u64 = 0xf135_7aea_2e62_a9c5;

impl IntHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.0 = self.0.wrapping_add(word).wrapping_mul(SEED);
    }
}

impl Hasher for IntHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut word = [0u8; 8];
            word[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(word));
        }
    }

    #[inline]
    fn write_u32(&mut self, n: u32) {
        self.add(u64::from(n));
    }

    #[inline]
    fn write_u64(&mut self, n: u64) {
        self.add(n);
    }

    #[inline]
    fn write_usize(&mut self, n: usize) {
        self.add(n as u64);
    }

    #[inline]
    fn finish(&self) -> u64 {
        // The multiply mixes upwards: the well-mixed high bits are brought down to the low
        // ones the table indexes by.
        self.0.rotate_left(26)
    }
}

/// A hash map keyed by integers ([`IntHasher`]).
pub(super) type IntMap<K, V> = HashMap<K, V, BuildHasherDefault<IntHasher>>;
/// A hash set of integers ([`IntHasher`]).
pub(super) type IntSet<K> = HashSet<K, BuildHasherDefault<IntHasher>>;

/// No representative (the end of a cell's chain).
const NONE: u32 = u32::MAX;

/// Merges vertices closer than `tolerance`; returns the merged positions and, for each input
/// vertex, its merged index. Deterministic: a vertex joins the first earlier representative
/// (the lowest index) within the tolerance, scanning a uniform grid of cell size `tolerance`.
///
/// An exact copy of an earlier position joins what that position joined, without a search:
/// the representatives made since have higher indices, and one made before that was not
/// within the tolerance of the position is not within it of its copy either.
pub(super) fn weld(positions: &[Point3], tolerance: Real) -> (Vec<Point3>, Vec<u32>) {
    let mut out: Vec<Point3> = Vec::new();
    let mut remap = Vec::with_capacity(positions.len());
    let bits = |p: &Point3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut exact: IntMap<[u64; 3], u32> = IntMap::default();
    if tolerance <= 0.0 || !tolerance.is_finite() {
        for p in positions {
            let id = *exact.entry(bits(p)).or_insert_with(|| {
                out.push(*p);
                (out.len() - 1) as u32
            });
            remap.push(id);
        }
        return (out, remap);
    }
    let inv = 1.0 / tolerance;
    let cell_of = |p: &Point3| -> [i64; 3] {
        [
            (p.x * inv).floor() as i64,
            (p.y * inv).floor() as i64,
            (p.z * inv).floor() as i64,
        ]
    };
    // Each cell's representatives as a chain: the cell's latest, then `next` of each.
    let mut heads: IntMap<[i64; 3], u32> = IntMap::default();
    let mut next: Vec<u32> = Vec::new();
    let tol2 = tolerance * tolerance;
    for p in positions {
        let key = bits(p);
        if let Some(&id) = exact.get(&key) {
            remap.push(id);
            continue;
        }
        let c = cell_of(p);
        let mut found: Option<u32> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    // Saturating: coordinates beyond ±9.2e11 tolerances share the extreme cells.
                    let cell = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    let mut id = heads.get(&cell).copied().unwrap_or(NONE);
                    while id != NONE {
                        if (out[id as usize] - p).norm_squared() <= tol2
                            && found.is_none_or(|f| id < f)
                        {
                            found = Some(id);
                        }
                        id = next[id as usize];
                    }
                }
            }
        }
        let id = match found {
            Some(id) => id,
            None => {
                out.push(*p);
                let id = (out.len() - 1) as u32;
                let head = heads.entry(c).or_insert(NONE);
                next.push(*head);
                *head = id;
                id
            }
        };
        exact.insert(key, id);
        remap.push(id);
    }
    (out, remap)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The weld as it was written first (every position searched, the grid's cells as
    /// lists): the reference the faster one must agree with exactly.
    fn reference_weld(positions: &[Point3], tolerance: Real) -> (Vec<Point3>, Vec<u32>) {
        let mut out: Vec<Point3> = Vec::with_capacity(positions.len());
        let mut remap = Vec::with_capacity(positions.len());
        if tolerance <= 0.0 || !tolerance.is_finite() {
            let mut exact: HashMap<[u64; 3], u32> = HashMap::new();
            for p in positions {
                let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
                let id = *exact.entry(key).or_insert_with(|| {
                    out.push(*p);
                    (out.len() - 1) as u32
                });
                remap.push(id);
            }
            return (out, remap);
        }
        let inv = 1.0 / tolerance;
        let cell_of = |p: &Point3| -> [i64; 3] {
            [
                (p.x * inv).floor() as i64,
                (p.y * inv).floor() as i64,
                (p.z * inv).floor() as i64,
            ]
        };
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let tol2 = tolerance * tolerance;
        for p in positions {
            let c = cell_of(p);
            let mut found: Option<u32> = None;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let cell = [
                            c[0].saturating_add(dx),
                            c[1].saturating_add(dy),
                            c[2].saturating_add(dz),
                        ];
                        let Some(list) = grid.get(&cell) else {
                            continue;
                        };
                        for &id in list {
                            if (out[id as usize] - p).norm_squared() <= tol2
                                && found.is_none_or(|f| id < f)
                            {
                                found = Some(id);
                            }
                        }
                    }
                }
            }
            let id = match found {
                Some(id) => id,
                None => {
                    out.push(*p);
                    let id = (out.len() - 1) as u32;
                    grid.entry(c).or_default().push(id);
                    id
                }
            };
            remap.push(id);
        }
        (out, remap)
    }

    fn same(positions: &[Point3], tolerance: Real) -> Result<(), TestCaseError> {
        let (a, ra) = weld(positions, tolerance);
        let (b, rb) = reference_weld(positions, tolerance);
        let bits = |v: &[Point3]| -> Vec<[u64; 3]> {
            v.iter()
                .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
                .collect()
        };
        prop_assert_eq!(bits(&a), bits(&b));
        prop_assert_eq!(ra, rb);
        Ok(())
    }

    proptest! {
        /// Positions on a coarse lattice near the tolerance (so that chains of near
        /// neighbours, cells shared and exact copies, `-0.0` among them, all occur): the same
        /// positions and mapping as searching every position.
        #[test]
        fn welding_agrees_with_searching_every_position(
            raw in proptest::collection::vec((-6i32..6, -6i32..6, -3i32..3, 0usize..4), 1..300),
            tolerance in prop_oneof![Just(1e-7), Just(0.3), Just(0.45), Just(1.0), Just(0.0)],
        ) {
            let jitter = [0.0, 0.1, -0.0, 0.24];
            let positions: Vec<Point3> = raw
                .iter()
                .map(|&(x, y, z, j)| {
                    let (x, y, z) = (x as Real, y as Real, z as Real);
                    Point3::new(x * 0.2 + jitter[j], y * 0.2, z * 0.1 * jitter[j])
                })
                .collect();
            same(&positions, tolerance)?;
        }
    }

    #[test]
    fn a_soup_welds_to_its_shared_corners() {
        // Three copies of the same corner, one 1e-8 away, one farther.
        let p = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1e-8, 0.0, 0.0),
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1e-6, 0.0),
        ];
        let (out, remap) = weld(&p, 1e-7);
        assert_eq!(out.len(), 3);
        assert_eq!(remap, [0, 1, 0, 0, 0, 2]);
        same(&p, 1e-7).expect("as the reference");
    }
}
