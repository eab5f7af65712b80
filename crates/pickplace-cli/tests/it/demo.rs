//! `pickplace demo`: the README's main command.

use crate::pickplace;

#[test]
fn demo_writes_its_outputs_and_says_where() {
    let dir = std::env::temp_dir().join(format!("pickplace-demo-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = pickplace(&["demo", "--out", dir.to_str().expect("utf-8 temp dir")]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let listed = String::from_utf8_lossy(&out.stdout);
    for name in [
        "can.env-clusters.ply",
        "pallet.env-clusters.ply",
        "plan-near.json",
        "plan-far-left.json",
        "view-near/plan.glb",
        "view-far-left/plan.glb",
        "view-far-left/keypose-00-pre-grasp.png",
    ] {
        let path = dir.join(name);
        assert!(
            listed.contains(&path.display().to_string()),
            "{name} not listed: {listed}"
        );
        assert!(std::fs::metadata(&path).expect(name).len() > 0);
    }
    let near: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("plan-near.json")).expect("read"))
            .expect("json");
    assert_eq!(near["strategy"], "right-right");
    let far: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("plan-far-left.json")).expect("read"))
            .expect("json");
    assert_eq!(
        far["grasps"].as_array().expect("grasps").len(),
        2,
        "a handover"
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.matches("validated:").count(), 2, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
