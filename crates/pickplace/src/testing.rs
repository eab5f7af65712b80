//! Shared fixtures of the unit tests: the shipped scenes, set up once per test binary.

use crate::{Setup, SetupOptions};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Mutex, OnceLock};

/// The shipped scene `name` (a file in `scenes/`), set up once and kept for the whole run.
pub(crate) fn setup(name: &str) -> &'static Setup {
    static SETUPS: OnceLock<Mutex<BTreeMap<String, &'static Setup>>> = OnceLock::new();
    let mut map = SETUPS
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    map.entry(name.to_owned()).or_insert_with(|| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let options = SetupOptions {
            cache_dir: Some(root.join("target/pickplace-test-cache")),
            ..SetupOptions::default()
        };
        let setup = Setup::load(&root.join("scenes").join(name), &options)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        Box::leak(Box::new(setup))
    })
}
