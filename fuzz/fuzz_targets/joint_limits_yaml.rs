//! The `joint_limits.yaml` reader (`pickplace::joint_limits::parse_yaml`, the YAML subset
//! MoveIt's setup assistant writes) on arbitrary text (lossy UTF-8): it returns a value or a
//! `line N: …` error, never panics or recurses without bound; an accepted document that fits
//! the file's shape must have its limits checked without panicking.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::joint_limits::{JointLimitsFile, check_spec, parse_yaml};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match parse_yaml(&text) {
        Ok(value) => {
            assert!(value.is_object(), "a document is a mapping");
            if let Ok(file) = serde_json::from_value::<JointLimitsFile>(value) {
                for spec in file.joint_limits.values() {
                    let _ = check_spec(spec);
                }
            }
        }
        Err(e) => assert!(e.starts_with("line "), "{e}"),
    }
});
