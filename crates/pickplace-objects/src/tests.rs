use crate::*;
use pickplace_geometry::math::Real;
use pickplace_geometry::mesh::MassMethod;
use std::f64::consts::{PI, TAU};

#[test]
fn shipped_meshes_are_closed_and_outward() {
    for shipped in shipped_meshes() {
        let mesh = shipped.builder.build().expect("valid shipped mesh");
        let report = mesh.report();
        assert!(report.is_closed(), "{}: {report:?}", shipped.file_name);
        assert_eq!(report.degenerate_triangles, 0, "{}", shipped.file_name);
        let mass = mesh.mass_properties();
        assert_eq!(mass.method, MassMethod::Volume, "{}", shipped.file_name);
        assert!(!mass.inverted_winding, "{}", shipped.file_name);
        let (lo, _) = mesh.aabb();
        assert!(lo.z.abs() < 1e-12, "{}: base at z = 0", shipped.file_name);
    }
}

/// Every builder of the scene suite: closed, outward-wound, no degenerate triangle, base on
/// `z = 0` (the jittered box within its noise).
#[test]
fn suite_builders_are_closed_and_outward() {
    let builders: Vec<(&str, MeshBuilder, Real)> = vec![
        ("cereal box", cereal_box_builder(), 0.0),
        ("domino", domino_builder(), 0.0),
        ("toy block", toy_block_builder(), 0.0),
        ("milk carton", milk_carton_builder(), 0.0),
        ("dense can", dense_can_builder(), 0.0),
        ("bottle", punted_bottle_builder(), 0.0),
        ("L", l_shape_builder(), 0.0),
        ("hollow brick", hollow_brick_builder(), 0.0),
        ("fruit", fruit_builder(), 0.0),
        ("duck", duck_builder(), 0.0),
        ("scanned box", scanned_box_builder(), 0.0003),
        ("table", plain_table_builder([0.6, 0.9], 0.7), 0.0),
        ("shelf", shelf_builder([0.2, 0.3], 0.15), 0.0),
        (
            "subdivided",
            subdivided_box_builder([0.1, 0.2, 0.3], 3),
            0.0,
        ),
    ];
    for (name, builder, noise) in builders {
        let mesh = builder.build().expect("valid");
        let report = mesh.report();
        assert!(report.is_closed(), "{name}: {report:?}");
        assert_eq!(report.degenerate_triangles, 0, "{name}");
        let mass = mesh.mass_properties();
        assert_eq!(mass.method, MassMethod::Volume, "{name}");
        assert!(!mass.inverted_winding, "{name}");
        assert!(mass.volume > 0.0, "{name}");
        let (lo, _) = mesh.aabb();
        assert!(lo.z.abs() <= noise + 1e-12, "{name}: base at z = {}", lo.z);
    }
}

#[test]
fn suite_builders_have_their_volumes_and_sizes() {
    let vol = |b: MeshBuilder| b.build().expect("valid").mass_properties().volume;
    assert!((vol(cereal_box_builder()) - 0.19 * 0.03 * 0.26).abs() < 1e-12);
    let carton = 0.07 * 0.07 * 0.19 + 0.07 * 0.07 * 0.03 / 2.0;
    assert!((vol(milk_carton_builder()) - carton).abs() < 1e-12);
    let l = 0.12 * 0.03 * 0.045 + 0.03 * 0.07 * 0.045;
    assert!((vol(l_shape_builder()) - l).abs() < 1e-12);
    let brick = 0.06 * 0.05 * 0.04 - 0.056 * 0.046 * 0.038;
    assert!((vol(hollow_brick_builder()) - brick).abs() < 1e-12);
    let sub = vol(subdivided_box_builder([0.1, 0.2, 0.3], 5));
    assert!((sub - 0.006).abs() < 1e-12, "{sub}");
    // Thousands of triangles where the suite says so.
    assert_eq!(dense_can_builder().triangles.len(), 256 * 26);
    assert_eq!(scanned_box_builder().triangles.len(), 12 * 16 * 16);
    // The punt: the bottle's lowest points are a ring, its axis point is 12 mm up.
    let bottle = punted_bottle_builder().build().expect("valid");
    let (lo, hi) = bottle.aabb();
    assert!(lo.z.abs() < 1e-12 && (hi.z - 0.25).abs() < 1e-12);
    // The fruit's flat base and height.
    let (lo, hi) = fruit_builder().build().expect("valid").aabb();
    assert!((hi.z - lo.z - 0.054).abs() < 1e-9, "{}", hi.z - lo.z);
}

#[test]
fn jitter_is_seeded_bounded_and_keeps_copies_together() {
    let clean = subdivided_box_builder([0.06, 0.04, 0.1], 4);
    let a = jittered(clean.clone(), 0.001, 5);
    let b = jittered(clean.clone(), 0.001, 5);
    let c = jittered(clean.clone(), 0.001, 6);
    assert_eq!(a.positions, b.positions, "same seed, same mesh");
    assert_ne!(a.positions, c.positions, "another seed, another mesh");
    for (p, q) in clean.positions.iter().zip(&a.positions) {
        assert!((p - q).amax() <= 0.001, "bounded");
        assert!(p != q, "every vertex moves");
    }
    // Copies of a corner (one per face) moved to one point: the mesh stays closed.
    assert!(a.build().expect("valid").report().is_closed());
    let mut rng = SplitMix64::new(0);
    // The reference sequence of SplitMix64 seeded with 0.
    assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
}

#[test]
fn mug_volume_is_the_body_plus_the_handle() {
    let mug = mug_builder().build().expect("valid");
    assert!(
        (1000..=3000).contains(&mug.triangle_count()),
        "{}",
        mug.triangle_count()
    );
    let m = mug.mass_properties();
    // Body: outer cylinder minus the cavity, for a 64-gon (area factor sin(2pi/n) n / 2pi).
    let k = (TAU / 64.0).sin() * 64.0 / TAU;
    let body = k
        * PI
        * (MUG_RADIUS.powi(2) * MUG_HEIGHT
            - (MUG_RADIUS - MUG_WALL).powi(2) * (MUG_HEIGHT - MUG_BOTTOM));
    // Handle: tube of radius 6 mm along a half ellipse of semi-axes 35 and 28 mm (length
    // ~ 99.9 mm by Ramanujan's perimeter / 2), 16-gon section.
    let (a, c) = (0.035, 0.028);
    let h = 3.0 * (a - c) * (a - c) / ((a + c) * (a + c));
    let length = PI * (a + c) * (1.0 + h / (10.0 + (4.0 - 3.0 * h).sqrt())) / 2.0;
    let handle = (TAU / 16.0).sin() * 16.0 / 2.0 * 0.006f64.powi(2) * length;
    assert!(
        (m.volume - body - handle).abs() < 0.03 * handle,
        "{} vs {}",
        m.volume,
        body + handle
    );
    assert!(m.center_of_mass.x > 0.0, "the handle pulls the CoG to +x");
}

#[test]
fn pallet_has_its_dents_as_floors() {
    let pallet = pallet_builder().build().expect("valid");
    let mut floors: Vec<Real> = Vec::new();
    for t in 0..pallet.triangle_count() {
        let [a, b, c] = pallet.triangle_points(t);
        if pallet.triangle_normal(t).z > 0.999 && a.z == b.z && b.z == c.z && !floors.contains(&a.z)
        {
            floors.push(a.z);
        }
    }
    floors.sort_by(Real::total_cmp);
    assert_eq!(floors, vec![0.02, 0.025, 0.028, 0.03, 0.04]);
    let [sx, sy, sz] = PALLET_SIZE;
    let dents: Real = PALLET_DENTS
        .iter()
        .map(|d| d.size[0] * d.size[1] * d.depth)
        .sum();
    let m = pallet.mass_properties();
    assert!(
        (m.volume - (sx * sy * sz - dents)).abs() < 1e-12,
        "{}",
        m.volume
    );
}

#[test]
fn overlapping_dents_stay_closed() {
    let dents = [
        Dent {
            center: [0.0, 0.0],
            size: [0.2, 0.2],
            depth: 0.01,
        },
        Dent {
            center: [0.05, 0.05],
            size: [0.1, 0.06],
            depth: 0.02,
        },
        Dent {
            center: [-0.2, 0.0],
            size: [0.1, 0.1],
            depth: 0.005,
        },
    ];
    let slab = dented_slab_builder([0.5, 0.4], 0.05, &dents)
        .expect("valid")
        .build()
        .expect("valid");
    assert!(slab.report().is_closed(), "{:?}", slab.report());
    let expected = 0.5 * 0.4 * 0.05 - 0.2 * 0.2 * 0.01 - 0.1 * 0.06 * 0.01 - 0.1 * 0.1 * 0.005;
    assert!((slab.mass_properties().volume - expected).abs() < 1e-12);
    let err = dented_slab_builder(
        [0.5, 0.4],
        0.05,
        &[Dent {
            center: [0.3, 0.0],
            size: [0.1, 0.1],
            depth: 0.01,
        }],
    );
    assert!(err.is_err());
}

#[test]
fn table_top_is_at_its_height() {
    let table = table_builder().build().expect("valid");
    let (lo, hi) = table.aabb();
    assert!((lo.z).abs() < 1e-12 && (hi.z - (TABLE_HEIGHT + 0.18)).abs() < 1e-12);
    assert!((hi.x - 0.45).abs() < 1e-12 && (lo.y + 0.30).abs() < 1e-12);
}
