//! 2D polygon module: hull, minimum-area rectangle, booleans.

use pickplace_geometry::math::{Point2, Real, Vector2};
use pickplace_geometry::polygon::{self, Polygon};
use proptest::prelude::*;

fn points() -> impl Strategy<Value = Vec<Point2>> {
    proptest::collection::vec((-1.0..1.0f64, -1.0..1.0f64), 1..40)
        .prop_map(|v| v.into_iter().map(|(x, y)| Point2::new(x, y)).collect())
}

/// Brute force: the best rectangle aligned with some hull edge.
fn brute_min_rect_area(hull: &[Point2]) -> Real {
    let n = hull.len();
    let mut best = Real::INFINITY;
    for i in 0..n {
        let u = (hull[(i + 1) % n] - hull[i]).normalize();
        let v = Vector2::new(-u.y, u.x);
        let (mut a0, mut a1, mut b0, mut b1) = (
            Real::INFINITY,
            Real::NEG_INFINITY,
            Real::INFINITY,
            Real::NEG_INFINITY,
        );
        for p in hull {
            let (a, b) = (p.coords.dot(&u), p.coords.dot(&v));
            a0 = a0.min(a);
            a1 = a1.max(a);
            b0 = b0.min(b);
            b1 = b1.max(b);
        }
        best = best.min((a1 - a0) * (b1 - b0));
    }
    best
}

fn regular(n: usize, r: Real, c: Point2, phase: Real) -> Vec<Point2> {
    (0..n)
        .map(|i| {
            let a = phase + std::f64::consts::TAU * i as Real / n as Real;
            c + Vector2::new(a.cos(), a.sin()) * r
        })
        .collect()
}

proptest! {
    #[test]
    fn convex_distance_matches_the_general_margin_on_hulls(
        pts in points(), x in -1.5..1.5f64, y in -1.5..1.5f64,
    ) {
        let hull = polygon::convex_hull(&pts);
        let p = Point2::new(x, y);
        let convex = polygon::signed_distance_convex(&hull, &p);
        if hull.len() >= 3 {
            let general = polygon::signed_margin(&p, &hull);
            prop_assert!((convex - general).abs() <= 1e-9, "{} vs {}", convex, general);
        } else {
            prop_assert_eq!(convex, Real::NEG_INFINITY);
        }
    }

    #[test]
    fn hull_is_convex_ccw_and_contains_every_point(pts in points()) {
        let hull = polygon::convex_hull(&pts);
        if hull.len() >= 3 {
            prop_assert!(polygon::signed_area(&hull) > 0.0);
            let n = hull.len();
            for i in 0..n {
                let (a, b) = (hull[i], hull[(i + 1) % n]);
                for p in &pts {
                    prop_assert!((b - a).perp(&(p - a)) >= -1e-12);
                }
            }
        }
    }

    #[test]
    fn calipers_match_brute_force(pts in points()) {
        let hull = polygon::convex_hull(&pts);
        let rect = polygon::min_area_rect(&pts).expect("non-empty");
        for p in &pts {
            prop_assert!(rect.contains(p, 1e-9));
        }
        if hull.len() >= 3 {
            let brute = brute_min_rect_area(&hull);
            prop_assert!((rect.area() - brute).abs() <= 1e-9 * brute.max(1e-12), "{} vs {}", rect.area(), brute);
        }
    }

    #[test]
    fn intersection_and_difference_partition_a(
        n in 3usize..12, m in 3usize..12, dx in -1.0..1.0f64, dy in -1.0..1.0f64, phase in 0.0..1.0f64,
    ) {
        let a = [Polygon::new(regular(n, 1.0, Point2::origin(), 0.0))];
        let b = [Polygon::new(regular(m, 0.8, Point2::new(dx, dy), phase))];
        let inter = polygon::total_area(&polygon::intersection(&a, &b));
        let diff = polygon::total_area(&polygon::difference(&a, &b));
        let uni = polygon::total_area(&polygon::union(&a, &b));
        let (aa, ab) = (a[0].area(), b[0].area());
        prop_assert!((inter + diff - aa).abs() < 1e-6, "{} + {} vs {}", inter, diff, aa);
        prop_assert!((uni - (aa + ab - inter)).abs() < 1e-6);
        prop_assert!(inter <= aa.min(ab) + 1e-6);
    }
}

#[test]
fn support_region_minus_holes_and_margin() {
    // Fig. 7: a can base (disc) on a plate with a hole under the base.
    let base = Polygon::new(regular(32, 0.033, Point2::origin(), 0.0));
    let mut hole = regular(16, 0.01, Point2::new(0.02, 0.0), 0.0);
    hole.reverse();
    let env = Polygon {
        outer: regular(4, 0.1, Point2::new(0.02, 0.0), std::f64::consts::FRAC_PI_4),
        holes: vec![hole],
    };
    let region = polygon::support_region(&base, &env);
    let expected = base.area() - polygon::signed_area(&env.holes[0]).abs();
    assert!(
        (polygon::total_area(&region) - expected).abs() < 1e-8,
        "{}",
        polygon::total_area(&region)
    );
    let hull = polygon::support_hull(&base, &env);
    assert!(
        (polygon::signed_area(&hull) - base.area()).abs() < 1e-8,
        "the hull fills the hole back"
    );
    let margin = polygon::signed_margin(&Point2::origin(), &hull);
    assert!((margin - 0.033 * (std::f64::consts::PI / 32.0).cos()).abs() < 1e-9);
}
