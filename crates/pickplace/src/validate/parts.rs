//! The environment's parts as the validator's contact queries see them (issue 33): which
//! parts the object rests on, and which part holds the target point.
//!
//! A part's collision mesh (its triangles in the world frame and their BVH) is prepared the
//! first time a query may reach the part, and never when the part's bounding box lies beyond
//! every query's reach: the validator's cost then grows with what moves and where the object
//! rests, not with the triangles of parts nothing comes near (a million-triangle crate in a
//! corner of the scene costs its bounding box, once). The answers are those of preparing
//! every part: a part beyond a query's reach by its box is beyond it by its triangles.
//! [`ValidationWork`] counts what was prepared.

use crate::error::{Result, internal};
use crate::setup::Setup;
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_placement::collide::CollisionMesh;
use serde::Serialize;

/// Slack (m) on the box tests, for rounding: a box this much beyond reach is still tested.
const BOX_SLACK: Real = 1e-9;

/// What the validator's contact queries prepared of the environment, the work that could grow
/// with the environment's size: parts whose triangles nothing came near are not counted,
/// because they were not prepared.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct ValidationWork {
    /// Environment parts whose collision mesh was prepared: a part within reach of a resting
    /// pose of the object (the start, a rest, the final pose), or a candidate for the target
    /// point's surface.
    pub environment_parts_prepared: usize,
    /// Their triangles (each part's BVH is built once).
    pub environment_triangles_prepared: usize,
}

/// The world-frame box of `points`: `(lower, upper)`; an empty set gives an empty box
/// (lower above upper), which nothing reaches.
fn bounds(points: impl Iterator<Item = Point3>) -> (Point3, Point3) {
    let mut lo = Point3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY);
    let mut hi = Point3::new(Real::NEG_INFINITY, Real::NEG_INFINITY, Real::NEG_INFINITY);
    for p in points {
        lo = lo.inf(&p);
        hi = hi.sup(&p);
    }
    (lo, hi)
}

/// The distance from `p` to the box `(lo, hi)` (0 inside): a lower bound of its distance to
/// anything inside the box.
fn box_distance(p: &Point3, (lo, hi): &(Point3, Point3)) -> Real {
    (lo - p).sup(&(p - hi)).sup(&Vector3::zeros()).norm()
}

/// The environment's parts, each with its world box, its collision mesh once prepared.
#[derive(Debug)]
pub(super) struct Parts<'a> {
    setup: &'a Setup,
    /// World-frame box of each part's vertices, in scene order.
    boxes: Vec<(Point3, Point3)>,
    /// Each part's collision mesh (world frame), once a query needed it.
    meshes: Vec<Option<CollisionMesh>>,
    work: ValidationWork,
}

impl<'a> Parts<'a> {
    /// The parts of `setup`'s environment, none prepared: a pass over their vertices for
    /// their boxes.
    pub(super) fn new(setup: &'a Setup) -> Self {
        let boxes = setup
            .environment
            .iter()
            .map(|e| bounds(e.mesh.vertices().iter().map(|p| e.world_from_mesh * p)))
            .collect();
        Self {
            setup,
            boxes,
            meshes: setup.environment.iter().map(|_| None).collect(),
            work: ValidationWork::default(),
        }
    }

    /// What was prepared so far.
    pub(super) fn work(&self) -> ValidationWork {
        self.work
    }

    /// Part `i`'s collision mesh, prepared on first use.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when the mesh cannot be prepared.
    fn mesh(&mut self, i: usize) -> Result<&CollisionMesh> {
        if self.meshes[i].is_none() {
            let e = &self.setup.environment[i];
            let mesh = CollisionMesh::from_meshes(&[(&e.mesh, e.world_from_mesh)])
                .map_err(internal("validator: environment meshes"))?;
            self.work.environment_parts_prepared += 1;
            self.work.environment_triangles_prepared += e.mesh.triangle_count();
            self.meshes[i] = Some(mesh);
        }
        self.meshes[i]
            .as_ref()
            .ok_or_else(|| crate::Error::Internal {
                stage: "validator: environment meshes",
                reason: "a prepared mesh went missing".into(),
            })
    }

    /// Names of the parts within `reach` (m) of `object` at `world_from_object` (some pair
    /// of triangles closer: [`CollisionMesh::touching_points`]), in scene order. A part
    /// whose box is farther than `reach` from the object's box is not prepared.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when a part's mesh cannot be prepared.
    pub(super) fn touching(
        &mut self,
        object: &CollisionMesh,
        world_from_object: &Isometry3,
        reach: Real,
    ) -> Result<Vec<String>> {
        let (lo, hi) = bounds(object.vertices().iter().map(|p| world_from_object * p));
        let margin = reach + BOX_SLACK;
        let mut names = Vec::new();
        for i in 0..self.boxes.len() {
            let (plo, phi) = &self.boxes[i];
            let apart = (0..3).any(|k| plo[k] > hi[k] + margin || lo[k] > phi[k] + margin);
            if apart {
                continue;
            }
            if !self
                .mesh(i)?
                .touching_points(object, world_from_object, reach)
                .is_empty()
            {
                names.push(self.setup.environment[i].name.clone());
            }
        }
        Ok(names)
    }

    /// The part whose surface is nearest to the world point `p` (the first in scene order
    /// when several are as near), `None` without parts. Only parts whose box is no farther
    /// than the nearest surface found are prepared.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when a part's mesh cannot be prepared.
    pub(super) fn nearest(&mut self, p: &Point3) -> Result<Option<String>> {
        let mut order: Vec<(Real, usize)> = self
            .boxes
            .iter()
            .enumerate()
            .map(|(i, b)| (box_distance(p, b), i))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best: Option<(Real, usize)> = None;
        for (lower, i) in order {
            if best.is_some_and(|(d, _)| lower > d + BOX_SLACK) {
                break;
            }
            let d = self.mesh(i)?.distance_to_point(p);
            let better = match best {
                None => true,
                Some((bd, bi)) => d < bd || (d == bd && i < bi),
            };
            if better {
                best = Some((d, i));
            }
        }
        Ok(best.map(|(_, i)| self.setup.environment[i].name.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_distance_is_zero_inside_and_the_gap_outside() {
        let b = (Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 3.0));
        assert_eq!(box_distance(&Point3::new(0.5, 1.0, 1.0), &b), 0.0);
        assert!((box_distance(&Point3::new(4.0, 6.0, 3.0), &b) - 5.0).abs() < 1e-12);
        assert!((box_distance(&Point3::new(-1.0, 1.0, 1.0), &b) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_parts_the_can_rests_on_and_the_target_surface_prepare_only_what_is_near() {
        let setup = crate::testing::setup("fig9-near.toml");
        let mut parts = Parts::new(setup);
        let object = &setup.placement_object.collision;
        let on_table = parts
            .touching(
                object,
                &setup.object_start,
                crate::contact::SUPPORT_DISTANCE,
            )
            .expect("prepared");
        assert_eq!(on_table, ["table"]);
        // Lifted 50 cm, it touches nothing, and no box is near enough to prepare another part.
        let before = parts.work();
        let lifted =
            pickplace_geometry::math::Translation3::new(0.0, 0.0, 0.5) * setup.object_start;
        assert!(
            parts
                .touching(object, &lifted, crate::contact::SUPPORT_DISTANCE)
                .expect("prepared")
                .is_empty()
        );
        assert_eq!(parts.work(), before);
        // The target point is on the pallet.
        let target = setup.scene.target_point();
        assert_eq!(
            parts.nearest(&target).expect("prepared").as_deref(),
            Some("pallet")
        );
    }
}
