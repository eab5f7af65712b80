//! The setup's unit tests.

use super::*;
use std::sync::Mutex;

/// An unusable cache (its folder under a regular file, so that even root cannot write
/// it) gives one warning, reports the long work, and sets up the same clusters and
/// roadmaps as a working cache.
#[test]
fn an_unusable_cache_gives_one_warning_progress_and_the_same_setup() {
    let cached = crate::testing::setup("fig9-near.toml");
    let base = std::env::temp_dir().join(format!("pickplace-setup-nocache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base).expect("base");
    let file = base.join("a-file");
    std::fs::write(&file, "x").expect("file");
    let calls: Arc<Mutex<Vec<(String, usize, usize)>>> = Arc::default();
    let sink = Arc::clone(&calls);
    let options = SetupOptions {
        cache_dir: Some(file.join("cache")),
        progress: Some(Arc::new(move |p: SetupProgress<'_>| {
            sink.lock()
                .expect("calls")
                .push((p.stage.to_owned(), p.done, p.total));
        })),
        ..SetupOptions::default()
    };
    let fresh = Setup::load(&cached.scene_path, &options).expect("sets up in memory");
    assert_eq!(fresh.warnings.len(), 1, "{:?}", fresh.warnings);
    assert!(
        matches!(&fresh.warnings[0], CacheWarning::NotWritable { folder, .. } if *folder == file.join("cache")),
        "{:?}",
        fresh.warnings
    );
    assert!(cached.warnings.is_empty(), "{:?}", cached.warnings);

    // Freshly computed equals what the cache gave.
    assert_eq!(fresh.object_env, cached.object_env);
    assert_eq!(fresh.object_finger, cached.object_finger);
    for (a, b) in fresh.environment.iter().zip(&cached.environment) {
        assert_eq!(a.clustering, b.clustering);
    }
    for (a, b) in fresh.arms.iter().zip(&cached.arms) {
        assert!(a.roadmap == b.roadmap, "{} roadmap differs", a.group);
        assert_eq!(a.roadmap_report.source, roadmaps::RoadmapSource::Built);
    }

    // Every stage is named and ends with done == total.
    let calls = calls.lock().expect("calls");
    let mut stages: Vec<&str> = calls.iter().map(|c| c.0.as_str()).collect();
    stages.dedup();
    stages.sort_unstable();
    stages.dedup();
    let mut expected = vec![
        "clustering object.mesh (env)".to_owned(),
        "clustering object.mesh (finger)".to_owned(),
    ];
    for (i, e) in fresh.scene.environment.iter().enumerate() {
        expected.push(format!("clustering environment[{i}] {:?} (env)", e.name));
    }
    for a in &fresh.arms {
        expected.push(format!("roadmap {}", a.group));
    }
    expected.sort_unstable();
    assert_eq!(stages, expected);
    for stage in &expected {
        let ends = calls
            .iter()
            .filter(|c| c.0 == *stage && c.1 == c.2 && c.2 > 0)
            .count();
        assert_eq!(ends, 1, "{stage} ends once: {calls:?}");
    }
    std::fs::remove_dir_all(&base).expect("cleanup");
}
