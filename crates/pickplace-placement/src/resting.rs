//! Resting poses of an object on an infinite horizontal plane.
//!
//! This is the stability test of the paper's Fig. 7 ([`crate::stability`]) specialised to an environment cluster of
//! infinite extent: the common area of the object's contact region and the plane is the
//! object's contact region itself, so the support polygon is a facet of the object's convex
//! hull (only hull points can touch a supporting plane), and the object is stable when the
//! vertical through its centre of gravity passes through that facet.
//!
//! A tessellated round object has one hull facet per segment of its round part; reporting one
//! pose per facet would drown the caller in near-identical poses that are not even stable in
//! practice (the object rolls). Facets are therefore grouped into *smooth patches* (neighbours
//! whose normals differ by less than [`RestingOptions::smooth_angle`]) and each patch yields
//! its stable classes:
//! - a patch of one facet: the usual test (CoG inside, with a margin);
//! - a patch whose facets all hold the CoG at the same height (within
//!   [`RestingOptions::neutral_height`]) and whose normals are all perpendicular to one axis:
//!   one *rolling* class (a cylinder lying on its side), reported once with its axis;
//! - a neutral patch whose normals span all directions (a sphere): no stable face contact;
//! - otherwise the facets of the patch where the CoG is lowest among their neighbours (local
//!   minima of potential energy) that pass the CoG test.

use crate::error::{Error, Result};
use crate::stability::SupportHull;
use pickplace_geometry::math::{Isometry3, Point2, Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::parry;
use std::collections::BTreeMap;

/// Options of [`resting_poses`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestingOptions {
    /// Hull facets whose normals differ by less than this angle (rad) belong to one smooth
    /// patch (default: 15° = 0.2618).
    pub smooth_angle: Real,
    /// A patch whose facets hold the CoG at heights within this range (m) is neutral: the
    /// object rolls freely on it (default: 0.0005).
    pub neutral_height: Real,
    /// Minimum distance (m) from the CoG's projection to the support polygon's boundary for a
    /// pose to count as stable (default: [`crate::candidates::DEFAULT_MIN_MARGIN`], 2 mm, as
    /// for placements).
    pub min_margin: Real,
    /// Minimum tipping angle (rad), `atan(margin / CoG height)` (default:
    /// [`crate::candidates::DEFAULT_MIN_TIPPING_ANGLE`], 6°, as for placements).
    pub min_tipping_angle: Real,
    /// Report rolling classes (a cylinder on its side): they are neutral about their axis, so
    /// no margin holds them against a push across it, and the two minimums are not applied to
    /// them (their margin is the best facet's, their CoG must project inside it). A planner
    /// that needs placements it can rely on sets this to `false` (default: `true`).
    pub include_rolling: bool,
    /// The contact model's tolerance (m): points of the object within this distance of the
    /// supporting plane carry it ([`crate::stability::CONTACT_TOLERANCE`], 1 mm, the
    /// clustering's h_max). 0 is the rigid model: only the hull facet itself carries it.
    pub contact_tolerance: Real,
}

impl Default for RestingOptions {
    fn default() -> Self {
        Self {
            smooth_angle: 15f64.to_radians(),
            neutral_height: 5e-4,
            min_margin: crate::candidates::DEFAULT_MIN_MARGIN,
            min_tipping_angle: crate::candidates::DEFAULT_MIN_TIPPING_ANGLE,
            include_rolling: true,
            contact_tolerance: crate::stability::CONTACT_TOLERANCE,
        }
    }
}

/// One stable class of resting poses on a horizontal plane.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RestingPose {
    /// Pose of the object with its support facet on the plane `z = 0`, the CoG above the
    /// world origin. Any rotation about world z keeps it stable.
    pub world_from_object: Isometry3,
    /// Outward normal of the support facet, in the object frame (it points down, −z world).
    pub support_normal: Vector3,
    /// Distance (m) from the CoG's vertical to the support polygon's boundary.
    pub stability_margin: Real,
    /// Height (m) of the CoG above the plane.
    pub cog_height: Real,
    /// Tipping angle (rad): `atan(stability_margin / cog_height)`
    /// ([`crate::stability::tipping_angle`]).
    pub tipping_angle: Real,
    /// For a rolling class, the axis (object frame) the object rolls about.
    pub rolling_axis: Option<Vector3>,
    /// Number of hull facets the class stands for.
    pub facet_count: usize,
    /// Support polygon on the plane (world frame, z = 0), counter-clockwise.
    pub support_polygon: Vec<Point3>,
}

/// A planar face of the convex hull: the union of coplanar hull triangles.
#[derive(Debug, Clone)]
struct Facet {
    normal: Vector3,
    offset: Real, // plane: normal · x = offset
    points: Vec<Point3>,
}

/// Every stable class of resting poses of `mesh` on a horizontal plane, most stable first
/// (largest margin divided by CoG height, then by margin).
///
/// # Arguments
/// * `mesh`: the object, in its own frame.
/// * `cog`: its centre of gravity (object frame).
///
/// # Errors
/// [`Error::DegenerateHull`] for a flat object, [`Error::NonFiniteCog`], [`Error::InvalidOption`].
///
/// # Performance
/// One convex hull (quickhull over the mesh's vertices) plus linear work in its facets.
pub fn resting_poses(
    mesh: &TriMesh,
    cog: &Point3,
    options: &RestingOptions,
) -> Result<Vec<RestingPose>> {
    if !(cog.x.is_finite() && cog.y.is_finite() && cog.z.is_finite()) {
        return Err(Error::NonFiniteCog {
            x: cog.x,
            y: cog.y,
            z: cog.z,
        });
    }
    check_option(
        "smooth_angle",
        options.smooth_angle,
        0.0,
        std::f64::consts::PI,
    )?;
    check_option(
        "neutral_height",
        options.neutral_height,
        0.0,
        Real::INFINITY,
    )?;
    check_option("min_margin", options.min_margin, 0.0, Real::INFINITY)?;
    check_option(
        "contact_tolerance",
        options.contact_tolerance,
        0.0,
        Real::INFINITY,
    )?;
    check_option(
        "min_tipping_angle",
        options.min_tipping_angle,
        0.0,
        std::f64::consts::FRAC_PI_2,
    )?;

    let (facets, facet_neighbours, hull) = hull_facets(mesh.vertices())?;
    let heights: Vec<Real> = facets
        .iter()
        .map(|f| f.offset - f.normal.dot(&cog.coords))
        .collect();
    // The CoG's foot inside the facet itself: the facet is an equilibrium, a local minimum of
    // the CoG's height (a rigid body on a plane rests on a facet of its hull).
    let exact_margins: Vec<Real> = facets.iter().map(|f| facet_margin(f, cog)).collect();

    // Smooth patches: union-find over facet adjacencies with a small dihedral angle.
    let mut parent: Vec<usize> = (0..facets.len()).collect();
    let cos_smooth = options.smooth_angle.cos();
    for (a, list) in facet_neighbours.iter().enumerate() {
        for &b in list {
            if facets[a].normal.dot(&facets[b].normal) > cos_smooth {
                union(&mut parent, a, b);
            }
        }
    }
    let mut patches: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for f in 0..facets.len() {
        let root = find(&mut parent, f);
        patches.entry(root).or_default().push(f);
    }

    let mut out = Vec::new();
    let mut equilibria: Vec<usize> = Vec::new();
    for members in patches.values() {
        let (lo, hi) = members
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), &f| {
                (lo.min(heights[f]), hi.max(heights[f]))
            });
        if members.len() > 1 && hi - lo <= options.neutral_height {
            if !options.include_rolling {
                continue;
            }
            if let Some(axis) = common_axis(members.iter().map(|&f| facets[f].normal)) {
                // Rolling class: the facet with the largest margin represents it (ties: lowest index).
                let best = members.iter().copied().fold(members[0], |b, f| {
                    if exact_margins[f] > exact_margins[b] + 1e-12 {
                        f
                    } else {
                        b
                    }
                });
                if exact_margins[best] > 0.0 {
                    let support = tolerance_support(&facets[best], &facets[best].points, 1e-9);
                    out.push(make_pose(
                        &facets[best],
                        cog,
                        (exact_margins[best], heights[best]),
                        Some(axis),
                        members.len(),
                        &support,
                    ));
                }
            }
            continue;
        }
        equilibria.extend(members.iter().copied().filter(|&f| exact_margins[f] > 0.0));
    }

    // The contact model (crate::stability::CONTACT_TOLERANCE): each equilibrium rests on the
    // hull of the points within the tolerance of its plane, and the hull's tipping angle keeps
    // that support honest on curved surfaces. Lowest equilibria first, so that of several
    // resting on the same points within the tolerance the lowest one stands for them.
    equilibria.sort_by(|&a, &b| heights[a].total_cmp(&heights[b]).then(a.cmp(&b)));
    let tolerance = options.contact_tolerance;
    // Basins: an equilibrium the hull scan sees sink into a lower pose by more than a
    // significant rise ([`crate::stability::MIN_BARRIER_RISE`]) before any barrier belongs to
    // the nearest lower equilibrium (a scanned base or a low-poly curve rocks between such
    // minima); the lowest of a basin stands for it, on the supports of all its members.
    let tips: Vec<Real> = equilibria
        .iter()
        .map(|&f| crate::stability::hull_tipping_angle(&hull, cog, &facets[f].normal))
        .collect();
    let mut owner: Vec<usize> = (0..equilibria.len()).collect();
    for i in 0..equilibria.len() {
        // Within its barrier-free cone the body rocks to any lower equilibrium: one basin.
        let reach = if tips[i] > 0.0 {
            tips[i].min(MERGE_ANGLE)
        } else {
            MERGE_ANGLE
        };
        let n = facets[equilibria[i]].normal;
        let nearest = (0..i)
            .filter(|&j| heights[equilibria[j]] < heights[equilibria[i]])
            .map(|j| (facets[equilibria[j]].normal.dot(&n), j))
            .filter(|&(dot, _)| dot > reach.cos())
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
        if let Some((_, j)) = nearest {
            owner[i] = owner[j];
        }
    }
    let mut accepted: Vec<usize> = Vec::new();
    for (i, &f) in equilibria.iter().enumerate() {
        if owner[i] != i {
            continue;
        }
        let facet = &facets[f];
        let same_contact = accepted.iter().any(|&g| {
            facets[g].normal.dot(&facet.normal) > DUPLICATE_ANGLE.cos()
                && facet
                    .points
                    .iter()
                    .all(|p| facets[g].offset - facets[g].normal.dot(&p.coords) <= 2.0 * tolerance)
        });
        if same_contact {
            continue;
        }
        // The points within the tolerance of any member's plane, seen on this one's.
        let mut points: Vec<Point3> = Vec::new();
        for (k, &m) in equilibria.iter().enumerate() {
            if owner[k] == i {
                let g = &facets[m];
                points.extend(
                    hull.iter()
                        .filter(|p| g.offset - g.normal.dot(&p.coords) <= tolerance),
                );
            }
        }
        let support = tolerance_support(facet, &points, Real::INFINITY);
        let on_support = support.cog_margin_convex(&support_foot(facet, cog));
        let height = heights[f];
        let margin = on_support.min(height.max(1e-9) * tips[i].tan());
        if crate::stability::is_stable(
            margin,
            height,
            options.min_margin,
            options.min_tipping_angle,
        ) {
            accepted.push(f);
            let members = owner.iter().filter(|&&o| o == i).count();
            out.push(make_pose(
                facet,
                cog,
                (margin, height),
                None,
                members,
                &support,
            ));
        }
    }
    out.sort_by(|a, b| {
        let ka = a.stability_margin / a.cog_height.max(1e-9);
        let kb = b.stability_margin / b.cog_height.max(1e-9);
        kb.total_cmp(&ka)
            .then(b.stability_margin.total_cmp(&a.stability_margin))
    });
    Ok(out)
}

/// An equilibrium that sinks into a lower pose, or sees a lower one inside its barrier-free
/// cone, joins the nearest lower one whose normal is within this angle (rad) of its own (30°).
const MERGE_ANGLE: Real = 0.523_598_775_598_298_8;

/// Two equilibria whose facets lie within twice the contact tolerance of each other's planes
/// and whose normals differ by less than this (rad) rest on the same contact: one pose (10°).
const DUPLICATE_ANGLE: Real = 0.174_532_925_199_432_95;

/// The support of the body resting on `facet` under the contact model: the hull, in the
/// facet's plane basis, of the `points` within `tolerance` of its plane.
fn tolerance_support(facet: &Facet, points: &[Point3], tolerance: Real) -> SupportHull {
    let (u, v) = plane_basis(&facet.normal);
    crate::stability::tolerance_support(points, &facet.normal, facet.offset, (&u, &v), tolerance)
}

/// The CoG's foot on the facet's plane, in the facet's plane basis.
fn support_foot(facet: &Facet, cog: &Point3) -> Point2 {
    let (u, v) = plane_basis(&facet.normal);
    Point2::new(cog.coords.dot(&u), cog.coords.dot(&v))
}

fn check_option(name: &'static str, value: Real, lo: Real, hi: Real) -> Result<()> {
    if value.is_nan() || value < lo || value > hi {
        return Err(Error::InvalidOption {
            name,
            value,
            reason: "out of range",
        });
    }
    Ok(())
}

/// The unit axis perpendicular to every normal, if the normals lie in one plane (within 1°).
fn common_axis(normals: impl Iterator<Item = Vector3> + Clone) -> Option<Vector3> {
    let mut m = pickplace_geometry::math::Matrix3::zeros();
    for n in normals.clone() {
        m += n * n.transpose();
    }
    let eig = m.symmetric_eigen();
    let (i, _) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    let mut axis: Vector3 = eig.eigenvectors.column(i).into_owned();
    axis.normalize_mut();
    let tolerance = 1f64.to_radians().sin();
    if normals.clone().all(|n| n.dot(&axis).abs() < tolerance) {
        // Canonical sign so that the output does not depend on the eigen solver's choice.
        let first = axis.iter().copied().find(|c| c.abs() > 1e-9).unwrap_or(1.0);
        Some(if first < 0.0 { -axis } else { axis })
    } else {
        None
    }
}

fn make_pose(
    facet: &Facet,
    cog: &Point3,
    (margin, height): (Real, Real),
    rolling_axis: Option<Vector3>,
    facet_count: usize,
    support: &SupportHull,
) -> RestingPose {
    let rotation = rotation_taking(&facet.normal, &-Vector3::z());
    let projected = cog - facet.normal * (facet.normal.dot(&cog.coords) - facet.offset);
    // Put the CoG's foot point at the origin; the facet plane maps to z = 0.
    let foot = rotation * projected;
    let world_from_object = Isometry3::from_parts((-foot.coords).into(), rotation);
    let (u, v) = plane_basis(&facet.normal);
    let on_plane = |q: &Point2| u * q.x + v * q.y + facet.normal * facet.offset;
    let polygon: Vec<Point3> = support
        .points()
        .iter()
        .map(|q| {
            let mut p = world_from_object * Point3::from(on_plane(q));
            p.z = 0.0;
            p
        })
        .rev() // the plane's basis is right-handed about the downward normal
        .collect();
    RestingPose {
        world_from_object,
        support_normal: facet.normal,
        stability_margin: margin,
        cog_height: height,
        tipping_angle: crate::stability::tipping_angle(margin, height),
        rolling_axis,
        facet_count,
        support_polygon: polygon,
    }
}

/// The shortest rotation taking unit vector `from` to unit vector `to`; for opposite vectors a
/// half turn about a fixed perpendicular axis.
pub(crate) fn rotation_taking(from: &Vector3, to: &Vector3) -> UnitQuaternion {
    UnitQuaternion::rotation_between(from, to).unwrap_or_else(|| {
        let helper = if from.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let axis = nalgebra_unit(from.cross(&helper));
        UnitQuaternion::from_axis_angle(&axis, std::f64::consts::PI)
    })
}

fn nalgebra_unit(v: Vector3) -> pickplace_geometry::math::UnitVector3 {
    pickplace_geometry::math::UnitVector3::new_normalize(v)
}

/// The stability margin of the object resting on `facet` (Fig. 7 on an infinite plane, see
/// [`crate::stability`]): the signed distance from the CoG's projection to the boundary of the
/// facet's hull (positive inside).
fn facet_margin(facet: &Facet, cog: &Point3) -> Real {
    let (u, v) = plane_basis(&facet.normal);
    let to2 = |p: &Point3| Point2::new(p.coords.dot(&u), p.coords.dot(&v));
    let points: Vec<Point2> = facet.points.iter().map(to2).collect();
    SupportHull::of_points(&points).cog_margin_convex(&to2(cog))
}

/// An orthonormal basis (u, v) of the plane with normal `n`, right-handed (u × v = n).
pub(crate) fn plane_basis(n: &Vector3) -> (Vector3, Vector3) {
    let helper = if n.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let u = n.cross(&helper).normalize();
    let v = n.cross(&u);
    (u, v)
}

/// Builds the convex hull and merges coplanar hull triangles into facets. Returns the facets
/// and, for each, the facets sharing a hull edge with it (sorted).
/// The vertices of the convex hull of `vertices`.
pub(crate) fn hull_points(vertices: &[Point3]) -> Result<Vec<Point3>> {
    let points: Vec<_> = vertices.iter().map(parry::point).collect();
    let (hull_points, _) = parry3d_f64::transformation::try_convex_hull(&points).map_err(|e| {
        Error::DegenerateHull {
            reason: format!("{e:?}"),
        }
    })?;
    Ok(hull_points.into_iter().map(parry::to_point).collect())
}

#[allow(clippy::type_complexity)] // facets, their neighbours, the hull's vertices
fn hull_facets(vertices: &[Point3]) -> Result<(Vec<Facet>, Vec<Vec<usize>>, Vec<Point3>)> {
    let points: Vec<_> = vertices.iter().map(parry::point).collect();
    let (hull_points, hull_triangles) = parry3d_f64::transformation::try_convex_hull(&points)
        .map_err(|e| Error::DegenerateHull {
            reason: format!("{e:?}"),
        })?;
    if hull_triangles.len() < 4 {
        return Err(Error::DegenerateHull {
            reason: "fewer than 4 hull faces".into(),
        });
    }
    let hp: Vec<Point3> = hull_points.iter().copied().map(parry::to_point).collect();
    let normals: Vec<Option<Vector3>> = hull_triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| hp[i as usize]);
            let n = (b - a).cross(&(c - a));
            let len = n.norm();
            (len > 1e-18).then(|| n / len)
        })
        .collect();
    // Edge -> hull triangles.
    let mut edges: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (i, t) in hull_triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    // Merge coplanar neighbours (and sliver triangles with no normal) into facets.
    let mut parent: Vec<usize> = (0..hull_triangles.len()).collect();
    for users in edges.values() {
        if let [a, b] = users[..] {
            let coplanar = match (normals[a], normals[b]) {
                (Some(na), Some(nb)) => na.dot(&nb) > 1.0 - 1e-9,
                _ => true,
            };
            if coplanar {
                union(&mut parent, a, b);
            }
        }
    }
    let mut facet_of_root: BTreeMap<usize, usize> = BTreeMap::new();
    let mut facet_of_triangle = vec![0; hull_triangles.len()];
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (t, facet) in facet_of_triangle.iter_mut().enumerate() {
        let root = find(&mut parent, t);
        let id = *facet_of_root.entry(root).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[id].push(t);
        *facet = id;
    }
    let mut facets = Vec::with_capacity(members.len());
    for list in &members {
        // Area-weighted normal of the facet's triangles.
        let mut n = Vector3::zeros();
        let mut pts: Vec<u32> = Vec::new();
        for &t in list {
            let [a, b, c] = hull_triangles[t].map(|i| hp[i as usize]);
            n += (b - a).cross(&(c - a));
            pts.extend_from_slice(&hull_triangles[t]);
        }
        pts.sort_unstable();
        pts.dedup();
        let normal = n.try_normalize(1e-30).unwrap_or_else(Vector3::z);
        let points: Vec<Point3> = pts.iter().map(|&i| hp[i as usize]).collect();
        let offset = points
            .iter()
            .map(|p| normal.dot(&p.coords))
            .fold(Real::NEG_INFINITY, Real::max);
        facets.push(Facet {
            normal,
            offset,
            points,
        });
    }
    let mut neighbours = vec![Vec::new(); facets.len()];
    for users in edges.values() {
        if let [a, b] = users[..] {
            let (fa, fb) = (facet_of_triangle[a], facet_of_triangle[b]);
            if fa != fb {
                neighbours[fa].push(fb);
                neighbours[fb].push(fa);
            }
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    Ok((facets, neighbours, hp))
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        // Smaller index as root: deterministic.
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi] = lo;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::shapes;
    use pickplace_objects as objects;

    fn centroid(mesh: &TriMesh) -> Point3 {
        let (lo, hi) = mesh.aabb();
        nalgebra::center(&lo, &hi)
    }
    use pickplace_geometry::math::nalgebra;

    #[test]
    fn box_has_six_faces() {
        let m = shapes::box_mesh([0.03, 0.02, 0.05]);
        let poses = resting_poses(&m, &Point3::origin(), &RestingOptions::default()).expect("hull");
        assert_eq!(poses.len(), 6);
        // Most stable first: lying on the largest face (0.06 x 0.1), CoG 0.02 high.
        assert!((poses[0].cog_height - 0.02).abs() < 1e-12);
        assert!((poses[0].stability_margin - 0.03).abs() < 1e-12);
    }

    #[test]
    fn cylinder_gives_two_caps_and_a_rolling_side() {
        let m = shapes::cylinder(0.033, 0.12, 64);
        let poses = resting_poses(&m, &centroid(&m), &RestingOptions::default()).expect("hull");
        assert_eq!(poses.len(), 3, "{poses:#?}");
        let rolling: Vec<_> = poses.iter().filter(|p| p.rolling_axis.is_some()).collect();
        assert_eq!(rolling.len(), 1);
        let axis = rolling[0].rolling_axis.expect("axis");
        assert!(axis.z.abs() > 0.999);
        assert_eq!(rolling[0].facet_count, 64);
    }

    #[test]
    fn sphere_gives_no_face_contact() {
        // A geodesic-ish sphere: an octahedron subdivided and pushed to radius 0.05.
        let mut b = shapes::MeshBuilder::default();
        let r = 0.05;
        let n = 24;
        for i in 0..=n {
            for j in 0..n {
                let th = std::f64::consts::PI * i as f64 / n as f64;
                let ph = std::f64::consts::TAU * j as f64 / n as f64;
                b.vertex(Point3::new(
                    r * th.sin() * ph.cos(),
                    r * th.sin() * ph.sin(),
                    r * th.cos(),
                ));
            }
        }
        for i in 0..n {
            for j in 0..n {
                let a = (i * n + j) as u32;
                let bb = (i * n + (j + 1) % n) as u32;
                let c = ((i + 1) * n + (j + 1) % n) as u32;
                let d = ((i + 1) * n + j) as u32;
                b.quad(a, d, c, bb);
            }
        }
        let m = b.build().expect("sphere");
        let poses = resting_poses(&m, &Point3::origin(), &RestingOptions::default()).expect("hull");
        assert!(poses.is_empty(), "{} poses", poses.len());
    }

    /// Issue 31: a box scanned with 0.5 mm of noise (flat only to a millimetre) rests on each
    /// of its six faces, as a physics engine sees it; the rigid model (tolerance 0, only the
    /// hull facet carries it) finds a sliver under most faces.
    #[test]
    fn a_box_flat_only_to_a_millimetre_rests_on_its_six_faces() {
        let mesh = objects::jittered(
            objects::subdivided_box_builder([0.08, 0.06, 0.05], 24),
            0.0005,
            7,
        )
        .build()
        .expect("box");
        let cog = pickplace_geometry::mesh::MassProperties::of(&mesh).center_of_mass;
        let poses = resting_poses(&mesh, &cog, &RestingOptions::default()).expect("hull");
        assert_eq!(poses.len(), 6, "{poses:#?}");
        for p in &poses {
            // Each close to a face normal, with about the face's half width as margin.
            let n = p.support_normal;
            assert!(n.abs().max() > 0.995, "{n}");
            assert!(p.stability_margin > 0.02, "{}", p.stability_margin);
        }
        let rigid = RestingOptions {
            contact_tolerance: 0.0,
            ..RestingOptions::default()
        };
        let poses = resting_poses(&mesh, &cog, &rigid).expect("hull");
        assert!(poses.len() < 6, "{}", poses.len());
    }

    #[test]
    fn cog_outside_support_is_rejected() {
        // A tall thin box with its CoG pushed sideways beyond one face: standing on the small
        // face is unstable.
        let m = shapes::box_mesh([0.01, 0.01, 0.1]);
        let cog = Point3::new(0.02, 0.0, 0.0);
        let poses = resting_poses(&m, &cog, &RestingOptions::default()).expect("hull");
        assert!(poses.iter().all(|p| p.support_normal.z.abs() < 0.5));
        for p in &poses {
            let c = p.world_from_object * cog;
            assert!(c.x.abs() < 1e-12 && c.y.abs() < 1e-12);
        }
    }
}
