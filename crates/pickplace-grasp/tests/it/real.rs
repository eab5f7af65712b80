//! Grasps on curved, thin-walled and shuffled meshes (issue 17): widths measured on the mesh,
//! grasps on doubly curved bodies, outer walls paired across hollow objects, a grasp set that
//! does not depend on the triangle order.

use super::support::{self, Planned};
use pickplace_geometry::math::{Point3, Real, Vector3};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use pickplace_geometry::shapes::{self, MeshBuilder};
use pickplace_grasp::{Grasp, GraspOptions};
use pickplace_objects as objects;
use std::f64::consts::{PI, TAU};

fn tcp(g: &Grasp) -> Point3 {
    Point3::from(g.object_from_tcp.translation.vector)
}

/// A UV ellipsoid centred at `center` (semi-axes `radii`).
fn ellipsoid(radii: [Real; 3], center: Vector3, rings: usize, segments: usize) -> MeshBuilder {
    let mut b = MeshBuilder::default();
    let south = b.vertex(Point3::new(0.0, 0.0, -radii[2]));
    let mut bands = Vec::new();
    for i in 1..rings {
        let theta = PI * i as Real / rings as Real;
        bands.push(
            (0..segments)
                .map(|j| {
                    let phi = TAU * j as Real / segments as Real;
                    b.vertex(Point3::new(
                        radii[0] * theta.sin() * phi.cos(),
                        radii[1] * theta.sin() * phi.sin(),
                        -radii[2] * theta.cos(),
                    ))
                })
                .collect::<Vec<u32>>(),
        );
    }
    let north = b.vertex(Point3::new(0.0, 0.0, radii[2]));
    for j in 0..segments {
        let k = (j + 1) % segments;
        b.triangle(south, bands[0][k], bands[0][j]);
        for w in bands.windows(2) {
            b.quad(w[0][j], w[0][k], w[1][k], w[1][j]);
        }
        let last = &bands[bands.len() - 1];
        b.triangle(last[j], last[k], north);
    }
    b.translated(center)
}

/// An open-topped box (a hollow brick): outer `2·half` in x and y, height `height`, walls and
/// floor `wall` thick, rim at the top. With `rim = false` the rim is left out: an open mesh
/// whose inner and outer walls are separate sheets.
fn hollow_brick(half: Real, height: Real, wall: Real, rim: bool) -> TriMesh {
    let mut b = MeshBuilder::default();
    let inner = half - wall;
    // Outer and inner rings at the bottom and the top.
    let ring = |b: &mut MeshBuilder, r: Real, z: Real| -> Vec<u32> {
        [(r, r), (-r, r), (-r, -r), (r, -r)]
            .iter()
            .map(|&(x, y)| b.vertex(Point3::new(x, y, z)))
            .collect()
    };
    let ob = ring(&mut b, half, 0.0);
    let ot = ring(&mut b, half, height);
    let ib = ring(&mut b, inner, wall);
    let it = ring(&mut b, inner, height);
    for i in 0..4 {
        let j = (i + 1) % 4;
        b.quad(ob[j], ob[i], ot[i], ot[j]);
        b.quad(ib[i], ib[j], it[j], it[i]);
        if rim {
            b.quad(ot[j], ot[i], it[i], it[j]);
        }
    }
    b.quad(ob[0], ob[1], ob[2], ob[3]);
    b.quad(ib[3], ib[2], ib[1], ib[0]);
    // The quads above are wound clockwise seen from outside: turn every triangle over.
    for t in &mut b.triangles {
        t.swap(1, 2);
    }
    b.build().expect("valid brick")
}

/// A square tube with an open top and a floor: the profile revolved with four segments, so
/// the corners are at `corner` from the axis and the walls at `corner/√2`; the walls (and the
/// floor) are `wall/√2` thick.
fn square_tube(corner: Real, height: Real, wall: Real) -> TriMesh {
    let i = corner - wall;
    let profile = [
        [0.0, 0.0],
        [corner, 0.0],
        [corner, height],
        [i, height],
        [i, wall],
        [0.0, wall],
    ];
    shapes::revolve_builder(&profile, 4)
        .build()
        .expect("valid square tube")
}

#[test]
fn widths_across_a_square_tube_wall_are_the_wall_thickness() {
    // Walls 8.5 mm thick, 49 mm across.
    let wall = 0.0085;
    let mesh = square_tube(0.035, 0.09, wall * std::f64::consts::SQRT_2);
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(mesh, &gripper, &GraspOptions::default());
    let across: Vec<&Grasp> = set.grasps.iter().filter(|g| g.width < 0.02).collect();
    assert!(
        across.len() >= 10,
        "{} wall grasps {:?}",
        across.len(),
        set.rejected
    );
    for g in &across {
        assert!((g.width - wall).abs() < 2e-4, "width {} vs {wall}", g.width);
    }
}

#[test]
fn widths_across_a_round_tube_wall_are_where_the_pads_touch() {
    // A tube (a mug without handle) with an 8.5 mm wall, 96 facets around.
    let (ro, wall, h, floor) = (0.04, 0.0085, 0.09, 0.006);
    let ri = ro - wall;
    let profile = [
        [0.0, 0.0],
        [ro, 0.0],
        [ro, h],
        [ri, h],
        [ri, floor],
        [0.0, floor],
    ];
    let mesh = shapes::revolve_builder(&profile, 96)
        .build()
        .expect("valid");
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(mesh, &gripper, &GraspOptions::default());
    let across: Vec<&Grasp> = set.grasps.iter().filter(|g| g.width < 0.02).collect();
    assert!(
        across.len() >= 10,
        "{} wall grasps {:?}",
        across.len(),
        set.rejected
    );
    let (hw, hd) = (0.5 * gripper.pad_width, 0.5 * gripper.pad_depth);
    for g in &across {
        let p = tcp(g);
        let mut c = support::closing(g, &gripper);
        assert!(c.z.abs() < 0.05, "radial closing: {g:?}");
        if c.dot(&Vector3::new(p.x, p.y, 0.0)) < 0.0 {
            c = -c;
        }
        let tangent = Vector3::z().cross(&c);
        let (l, a) = (
            g.object_from_tcp.rotation * gripper.lateral(),
            support::approach(g, &gripper),
        );
        // Through the TCP: the wall's chord along the closing axis.
        let chord = |t: Real| (ro * ro - t * t).sqrt() - (ri * ri - t * t).sqrt();
        let centre = chord(p.coords.dot(&tangent));
        // Rigid pads over the whole footprint: the outer pad stops at the highest point of the
        // outer wall under it, the inner pad at the innermost point of the inner wall.
        let (mut outer, mut inner) = (Real::NEG_INFINITY, Real::INFINITY);
        for i in 0..=40 {
            for j in 0..=40 {
                let q =
                    p + l * (hw * (i as Real / 20.0 - 1.0)) + a * (hd * (j as Real / 20.0 - 1.0));
                let t = q.coords.dot(&tangent);
                if (0.0..=h).contains(&q.z) && t.abs() < ro {
                    outer = outer.max((ro * ro - t * t).sqrt());
                }
                if (floor..=h).contains(&q.z) && t.abs() < ri {
                    inner = inner.min((ri * ri - t * t).sqrt());
                }
            }
        }
        assert!(
            g.width >= centre - 2e-4 && g.width <= outer - inner + 2e-4,
            "width {} vs {centre} through the TCP and {} for rigid pads",
            g.width,
            outer - inner
        );
    }
}

#[test]
fn widths_on_a_box_are_its_sides() {
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(
        shapes::box_mesh([0.03, 0.02, 0.025]),
        &gripper,
        &GraspOptions::default(),
    );
    assert!(!set.grasps.is_empty());
    for g in &set.grasps {
        assert!(
            [0.06, 0.04, 0.05]
                .iter()
                .any(|w| (g.width - w).abs() < 1e-9),
            "{}",
            g.width
        );
    }
}

#[test]
fn doubly_curved_bodies_get_grasps() {
    let gripper = support::gripper();
    // A ball-like fruit (70 mm), a rubber duck's body (58 mm long), an egg.
    for (name, radii) in [
        ("fruit", [0.035, 0.035, 0.033]),
        ("duck", [0.029, 0.024, 0.022]),
        ("egg", [0.022, 0.022, 0.03]),
    ] {
        let mesh = ellipsoid(radii, Vector3::zeros(), 32, 48)
            .build()
            .expect("valid");
        let Planned { set, .. } = support::plan(mesh, &gripper, &GraspOptions::default());
        assert!(set.grasps.len() >= 4, "{name}: {} grasps", set.grasps.len());
        for g in &set.grasps {
            // Across the body, within the sheet's give, no wider than the body.
            assert!(g.quality.pad_depth <= 0.005 + 1e-9);
            assert!(g.width <= 2.0 * radii[0].max(radii[1]).max(radii[2]) + 1e-6);
        }
        // Some through the centre.
        assert!(
            set.grasps.iter().any(|g| tcp(g).coords.norm() < 0.003),
            "{name}: none through the centre"
        );
    }
}

/// A bottle with a recessed base, a shoulder and a 25 mm neck.
fn bottle() -> TriMesh {
    let profile = [
        [0.0, 0.006],
        [0.012, 0.006],
        [0.016, 0.0],
        [0.035, 0.0],
        [0.035, 0.12],
        [0.0125, 0.16],
        [0.0125, 0.2],
        [0.0, 0.2],
    ];
    shapes::revolve_builder(&profile, 48)
        .build()
        .expect("valid bottle")
}

#[test]
fn a_bottle_with_a_recessed_base_is_held_by_its_body_and_its_neck() {
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(bottle(), &gripper, &GraspOptions::default());
    let body = set
        .grasps
        .iter()
        .filter(|g| (g.width - 0.07).abs() < 0.002)
        .count();
    let neck = set
        .grasps
        .iter()
        .filter(|g| (g.width - 0.025).abs() < 0.001 && tcp(g).z > 0.16)
        .count();
    assert!(body >= 4, "{body} body grasps");
    assert!(neck >= 4, "{neck} neck grasps");
}

#[test]
fn hollow_bricks_are_held_across_their_outer_walls() {
    let gripper = support::gripper();
    for rim in [true, false] {
        let mesh = hollow_brick(0.016, 0.05, 0.001, rim);
        let Planned {
            set, clustering, ..
        } = support::plan(mesh, &gripper, &GraspOptions::default());
        assert!(
            clustering.pairs.iter().all(|p| p.width > 0.002),
            "rim {rim}: a wall is paired with its own other side"
        );
        let across = set
            .grasps
            .iter()
            .filter(|g| (g.width - 0.032).abs() < 2e-4)
            .count();
        assert!(
            across >= 4,
            "rim {rim}: {across} grasps across the brick; pairs {:?}; rejected {:?}",
            clustering
                .pairs
                .iter()
                .map(|p| (p.first, p.second, p.width, p.overlap_area))
                .collect::<Vec<_>>(),
            set.rejected
        );
        assert!(set.grasps.iter().all(|g| g.width > 0.002));
    }
}

/// The same mesh with its triangles permuted and each triangle's vertices rotated.
fn shuffled(mesh: &TriMesh, mut seed: u64) -> TriMesh {
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        seed >> 33
    };
    let mut tris: Vec<[u32; 3]> = mesh.triangles().to_vec();
    for i in (1..tris.len()).rev() {
        let j = (next() % (i as u64 + 1)) as usize;
        tris.swap(i, j);
    }
    for t in &mut tris {
        t.rotate_left((next() % 3) as usize);
    }
    TriMesh::from_soup(mesh.vertices(), &tris, &MeshOptions::default()).expect("valid")
}

/// Whether every grasp of `a` has a grasp of `b` with the same pose and width (1e-6).
fn covered(a: &[Grasp], b: &[Grasp]) -> Option<usize> {
    a.iter().position(|g| {
        !b.iter().any(|h| {
            (tcp(g) - tcp(h)).norm() < 1e-6
                && g.object_from_tcp
                    .rotation
                    .angle_to(&h.object_from_tcp.rotation)
                    < 1e-6
                && (g.width - h.width).abs() < 1e-6
                && (g.score - h.score).abs() < 1e-6
        })
    })
}

#[test]
fn the_grasp_set_does_not_depend_on_the_triangle_order() {
    let gripper = support::gripper();
    let options = GraspOptions::default();
    for (name, mesh) in [
        ("bottle", bottle()),
        ("mug", objects::mug_builder().build().expect("valid")),
        (
            "duck",
            ellipsoid([0.029, 0.024, 0.022], Vector3::new(0.0, 0.0, 0.03), 24, 36)
                .build()
                .expect("valid"),
        ),
    ] {
        let a = support::plan(mesh.clone(), &gripper, &options).set;
        assert!(!a.grasps.is_empty(), "{name}");
        for seed in [1, 2, 3] {
            let b = support::plan(shuffled(&mesh, seed), &gripper, &options).set;
            assert_eq!(a.grasps.len(), b.grasps.len(), "{name}, seed {seed}");
            assert_eq!(covered(&a.grasps, &b.grasps), None, "{name}, seed {seed}");
            assert_eq!(covered(&b.grasps, &a.grasps), None, "{name}, seed {seed}");
        }
    }
}

/// Issue 17: a pad's contact is the surface its flexible sheet reaches, measured on the mesh.
/// Through the centre of a 30 mm sphere (a grape, a bottle's cap) the sheet (5 mm deep) wraps a
/// spherical cap of radius √(2·R·h − h²) ≈ 11 mm, of which the 20 × 25 mm pad covers the part
/// inside its rectangle.
#[test]
fn a_pad_on_a_sphere_touches_the_cap_its_sheet_wraps() {
    let gripper = support::gripper();
    let r = 0.015;
    let mesh = ellipsoid([r; 3], Vector3::zeros(), 48, 96)
        .build()
        .expect("valid");
    let Planned {
        set, clustering, ..
    } = support::plan(mesh, &gripper, &GraspOptions::default());
    let h = clustering.params.h_max;
    let cap = (2.0 * r * h - h * h).sqrt();
    // The cap's disc inside the pad's rectangle, on a fine grid.
    let (hw, hd) = (0.5 * gripper.pad_width, 0.5 * gripper.pad_depth);
    let n = 400;
    let mut inside = 0usize;
    for i in 0..n {
        for j in 0..n {
            let x = -hw + 2.0 * hw * (i as Real + 0.5) / n as Real;
            let y = -hd + 2.0 * hd * (j as Real + 0.5) / n as Real;
            inside += usize::from(x.hypot(y) <= cap);
        }
    }
    let expected = 4.0 * hw * hd * inside as Real / (n * n) as Real;
    let central: Vec<&Grasp> = set
        .grasps
        .iter()
        .filter(|g| tcp(g).coords.norm() < 1e-3)
        .collect();
    assert!(!central.is_empty(), "no grasp through the centre");
    for g in central {
        let area = g.quality.contact_area;
        assert!(
            (area - expected).abs() < 0.04 * expected,
            "contact {area} vs the cap's {expected}"
        );
        // The pads touch the sphere: the width is its diameter (less the facets' sag).
        assert!((g.width - 2.0 * r).abs() < 2e-4, "width {}", g.width);
    }
}

/// Issue 17: the finger's rigid face behind the pad must not reach the object before the pad
/// does. On a bottle whose lip stands 2 mm proud of its neck, the pad may hold the neck only
/// where the finger behind it clears the lip; on every object, each finger placed 0.2 mm off
/// its grasp's width touches nothing along its whole length.
#[test]
fn no_finger_reaches_the_object_before_its_pad() {
    let gripper = support::gripper();
    for (name, mesh) in [
        ("bottle", objects::punted_bottle_builder()),
        ("duck", objects::duck_builder()),
        ("mug", objects::mug_builder()),
    ] {
        let mesh = mesh.build().expect("valid");
        let Planned { set, .. } = support::plan(mesh.clone(), &gripper, &GraspOptions::default());
        assert!(
            set.grasps.len() >= 20,
            "{name}: {} grasps",
            set.grasps.len()
        );
        for g in &set.grasps {
            for finger in gripper.fingers(g.width + 4e-4) {
                let b = support::obb(&g.object_from_tcp, &finger);
                assert!(
                    !support::body_hits(&mesh, &b),
                    "{name}: a finger of the grasp at {} (width {}) hits the object",
                    tcp(g),
                    g.width
                );
            }
        }
    }
}

/// Issue 17: the duck (doubly curved body and head) gets grasps on its body across both of its
/// widths and on its head, not only where two flat-enough patches face each other.
#[test]
fn the_duck_gets_grasps_on_its_body_and_head() {
    let gripper = support::gripper();
    let mesh = objects::duck_builder().build().expect("valid");
    let Planned { set, .. } = support::plan(mesh, &gripper, &GraspOptions::default());
    assert!(set.grasps.len() >= 60, "{} grasps", set.grasps.len());
    let head = set.grasps.iter().filter(|g| tcp(g).z > 0.05).count();
    let body = set.grasps.iter().filter(|g| tcp(g).z < 0.035).count();
    assert!(head >= 4 && body >= 20, "head {head}, body {body}");
}
