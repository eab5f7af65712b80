//! The drop test lives in the library (`pickplace_placement::simulate`, feature `physics`);
//! the pallet's cuboid model is a fixture of these tests.

use pickplace_geometry::math::Real;
pub use pickplace_placement::simulate::{Drift, Obstacle, drop_test};

/// The pallet as the convex pieces it is made of: the grid of cells its dents cut its top into,
/// each a box from the floor to the cell's level (the same grid `dented_slab_builder` meshes).
/// A second, independent model of the environment for the drop test: flat box faces and box
/// edges instead of a triangle soup.
pub fn pallet_cuboids() -> Vec<Obstacle> {
    use pickplace_objects::{PALLET_DENTS, PALLET_SIZE};
    let [sx, sy, sz] = PALLET_SIZE;
    let mut xs = vec![-sx / 2.0, sx / 2.0];
    let mut ys = vec![-sy / 2.0, sy / 2.0];
    for d in &PALLET_DENTS {
        xs.extend([d.center[0] - d.size[0] / 2.0, d.center[0] + d.size[0] / 2.0]);
        ys.extend([d.center[1] - d.size[1] / 2.0, d.center[1] + d.size[1] / 2.0]);
    }
    for c in [&mut xs, &mut ys] {
        c.sort_by(Real::total_cmp);
        c.dedup();
    }
    let mut out = Vec::new();
    for x in xs.windows(2) {
        for y in ys.windows(2) {
            let (cx, cy) = ((x[0] + x[1]) / 2.0, (y[0] + y[1]) / 2.0);
            let top = PALLET_DENTS
                .iter()
                .filter(|d| {
                    (cx - d.center[0]).abs() < d.size[0] / 2.0
                        && (cy - d.center[1]).abs() < d.size[1] / 2.0
                })
                .map(|d| sz - d.depth)
                .fold(sz, Real::min);
            out.push(Obstacle::Cuboid(
                [cx, cy, top / 2.0],
                [(x[1] - x[0]) / 2.0, (y[1] - y[0]) / 2.0, top / 2.0],
            ));
        }
    }
    out
}
