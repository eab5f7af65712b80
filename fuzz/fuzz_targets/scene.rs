//! The scene parser (`pickplace::Scene::parse`) on arbitrary text (lossy UTF-8).
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::Scene;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(scene) = Scene::parse(&text, Path::new("fuzz.toml"), Path::new("/fuzz")) {
        let _ = scene.target_point();
    }
});
