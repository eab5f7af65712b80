//! The scene parser's numeric fields (issue 33): the fuzzer's bytes become the numbers of
//! every numeric field of a scene (any f64 bit pattern: NaN, infinities, denormals, 1e300,
//! negative zero, spelled as TOML spells them), written into an otherwise valid scene. A
//! scene that parses must hold only numbers inside their ranges (`pickplace::ranges`): a
//! time budget a `Duration` holds, positions within 10 km, scales, masses and tolerances that
//! cannot overflow or underflow what the planner computes from them.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::Scene;
use pickplace::ranges;
use std::path::Path;

/// A TOML float for any f64.
fn toml(v: f64) -> String {
    if v.is_nan() {
        "nan".to_owned()
    } else if v == f64::INFINITY {
        "inf".to_owned()
    } else if v == f64::NEG_INFINITY {
        "-inf".to_owned()
    } else {
        // `{:e}` always has an exponent, so the text is a TOML float, never an integer.
        format!("{v:e}")
    }
}

fuzz_target!(|data: &[u8]| {
    let mut numbers = data
        .chunks(8)
        .map(|c| {
            let mut b = [0u8; 8];
            b[..c.len()].copy_from_slice(c);
            f64::from_le_bytes(b)
        })
        .chain(std::iter::repeat(0.5));
    let mut n = || toml(numbers.next().unwrap_or(0.5));
    let text = format!(
        "format = 1\n[robot]\nurdf = \"r.urdf\"\nbase_pose = {{ position = [{}, {}, {}], orientation = [{}, {}, {}, {}] }}\nstart_state = {{ j = {} }}\n\
         [object]\nmesh = \"o.stl\"\nscale = {}\nmass = {}\ncenter_of_gravity = [{}, {}, {}]\nstart_pose = {{ position = [{}, {}, {}] }}\n\
         [[environment]]\nname = \"t\"\nmesh = \"t.stl\"\nscale = {}\npose = {{ position = [{}, {}, {}] }}\n\
         [target]\npoint = [{}, {}, {}]\ntolerance = {}\n\
         [planner]\nh_max_environment = {}\nh_max_finger = {}\ntime_budget = {}\n\
         [trajectory]\nvelocity_scaling = {}\nacceleration_scaling = {}\nmax_acceleration = {}\n\
         [trajectory.joint_limits.j]\nmax_velocity = {}\nmax_acceleration = {}\n\
         [collision_matrix]\nmin_collision_fraction = {}\n",
        n(), n(), n(), n(), n(), n(), n(), n(),
        n(), n(), n(), n(), n(), n(), n(), n(),
        n(), n(), n(), n(),
        n(), n(), n(), n(),
        n(), n(), n(),
        n(), n(), n(),
        n(), n(),
        n(),
    );
    let Ok(scene) = Scene::parse(&text, Path::new("fuzz.toml"), Path::new("/fuzz")) else {
        return;
    };
    let p = &scene.planner;
    assert!(ranges::TIME_BUDGET.contains(p.time_budget));
    assert!(std::time::Duration::try_from_secs_f64(p.time_budget).is_ok());
    assert!(ranges::H_MAX.contains(p.h_max_environment) && ranges::H_MAX.contains(p.h_max_finger));
    let o = &scene.object;
    assert!(ranges::MESH_SCALE.contains(o.scale));
    assert!(o.mass.is_none_or(|m| ranges::MASS.contains(m)));
    let coordinates = o
        .start_pose
        .position
        .iter()
        .chain(o.center_of_gravity.iter().flatten())
        .chain(&scene.target.point)
        .chain(scene.robots.iter().flat_map(|r| r.base_pose.position.iter()))
        .chain(scene.environment.iter().flat_map(|e| e.pose.position.iter()));
    for &c in coordinates {
        assert!(ranges::COORDINATE.contains(c), "{c}");
    }
    for e in &scene.environment {
        assert!(ranges::MESH_SCALE.contains(e.scale));
        let iso = e.pose.to_isometry().expect("a parsed pose converts");
        assert!((iso.rotation.quaternion().norm() - 1.0).abs() < 1e-9);
    }
    assert!(scene.target.tolerance.is_none_or(|t| ranges::TARGET_TOLERANCE.contains(t)));
    let t = &scene.trajectory;
    for s in [t.velocity_scaling, t.acceleration_scaling].into_iter().flatten() {
        assert!(ranges::SCALING.contains(s));
    }
    assert!(ranges::JOINT_ACCELERATION.contains(t.max_acceleration));
    for spec in t.joint_limits.values() {
        assert!(spec.max_velocity.is_none_or(|v| ranges::JOINT_VELOCITY.contains(v)));
        assert!(spec.max_acceleration.is_none_or(|v| ranges::JOINT_ACCELERATION.contains(v)));
    }
    assert!(ranges::COLLISION_FRACTION.contains(scene.collision_matrix.min_collision_fraction));
    for r in &scene.robots {
        for &v in r.start_state.values() {
            assert!(ranges::JOINT_VALUE.contains(v));
        }
    }
});
