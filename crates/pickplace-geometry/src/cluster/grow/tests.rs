//! Unit tests of `grow`.

use super::*;

#[test]
fn regression_plane_of_a_tilted_square_is_its_normal() {
    let a = Vector3::new(0.0, 0.0, 0.0);
    let b = Vector3::new(1.0, 0.0, 1.0);
    let c = Vector3::new(1.0, 1.0, 1.0);
    let d = Vector3::new(0.0, 1.0, 0.0);
    let m = Moments::triangle(&a, &b, &c).add(&Moments::triangle(&a, &c, &d));
    let (n, centroid) = m.plane();
    assert!(
        (n - Vector3::new(-1.0, 0.0, 1.0).normalize()).norm() < 1e-12,
        "{n}"
    );
    assert!((centroid - Vector3::new(0.5, 0.5, 0.5)).norm() < 1e-12);
    assert!((m.area - 2.0_f64.sqrt()).abs() < 1e-12);
}

#[test]
fn fast_eigenvector_matches_the_full_decomposition() {
    // A curved patch (part of a sphere), a flat one, and near-isotropic matrices.
    let mut state = 0x1234_5678_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as Real / (1u64 << 53) as Real - 0.5
    };
    for case in 0..200 {
        let q = nalgebra::Rotation3::from_euler_angles(next() * 6.0, next() * 6.0, next() * 6.0);
        let scale = [1e-2, 1e-4, 1.0][case % 3];
        let l = if case % 5 == 0 {
            [0.0, 0.3 + next(), 1.0]
        } else if case % 7 == 0 {
            [0.5, 0.5 + 1e-6 * next(), 0.9]
        } else {
            [(next() + 0.5) * 0.1, 0.5 + next() * 0.2, 1.0]
        };
        let d = Matrix3::from_diagonal(&Vector3::new(l[0], l[1], l[2])) * scale;
        let m = q.matrix() * d * q.matrix().transpose();
        let expected = q.matrix().column(0).into_owned();
        let guess = expected + Vector3::new(next(), next(), next()) * 0.5;
        let v = smallest_eigenvector(&m, &guess).expect("an eigenvector");
        let full = smallest_eigenvector_full(&m).expect("an eigenvector");
        // The eigenvector itself when λ₁ is separated; otherwise any unit vector v with
        // the smallest Rayleigh quotient.
        let rayleigh = |v: &Vector3| v.dot(&(m * v)) / scale;
        assert!((v.norm() - 1.0).abs() < 1e-12);
        assert!(
            rayleigh(&v) <= rayleigh(&full) + 1e-9,
            "case {case}: {v} vs {full}"
        );
        if l[1] - l[0] > 0.05 {
            assert!(
                v.dot(&expected).abs() > 1.0 - 1e-10,
                "case {case}: {v} vs {expected}"
            );
        }
    }
}
