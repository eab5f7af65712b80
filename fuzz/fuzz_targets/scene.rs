//! The scene parser (`pickplace::Scene::parse`) on arbitrary text (lossy UTF-8). A scene that
//! parses must hold only usable poses: each converts to an isometry whose rotation is a finite
//! unit quaternion.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::Scene;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(scene) = Scene::parse(&text, Path::new("fuzz.toml"), Path::new("/fuzz")) {
        let _ = scene.target_point();
        let poses = scene
            .robot
            .iter()
            .chain(&scene.robots)
            .map(|r| &r.base_pose)
            .chain([&scene.object.start_pose])
            .chain(scene.environment.iter().map(|e| &e.pose));
        for pose in poses {
            let iso = pose.to_isometry().expect("a parsed scene's pose converts");
            let norm = iso.rotation.quaternion().norm();
            assert!(
                (norm - 1.0).abs() < 1e-9,
                "rotation of norm {norm} from {pose:?}"
            );
            assert!(iso.translation.vector.iter().all(|v| v.is_finite()));
        }
    }
});
