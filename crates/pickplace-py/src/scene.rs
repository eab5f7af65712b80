//! `pickplace.Scene`: a scene file read and set up for planning (robot, meshes, cluster
//! databases, roadmaps), as `pickplace plan` does before it plans.

use crate::convert::{matrix4, mesh_arrays, to_python};
use crate::errors::{facade, input, input_msg};
use numpy::{PyArray1, PyArray2, ToPyArray};
use pickplace::cache::CacheWarning;
use pickplace::{Setup, SetupOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene set up for planning: the robot (URDF + SRDF), the object and the environment
/// with their cluster databases, the arms' roadmaps and the target (docs/scene-format.md).
///
/// Build one with `Scene.load(path)`, `Scene.from_toml(text, base_dir)` or
/// `Scene.from_dict(d, base_dir)`. Setting up reads the cluster databases and roadmaps from
/// the cache folder (`cache_dir`, else `$PICKPLACE_CACHE`, else `$XDG_CACHE_HOME/pickplace`,
/// else `~/.cache/pickplace`) and builds those missing; `use_cache=False` builds them in
/// memory (same plan, slower). Immutable and safe to share between threads.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct Scene {
    /// The set-up scene, shared with plans being computed without the GIL.
    pub setup: Arc<Setup>,
    /// Warnings of the setup (the cache not usable), as the CLI prints them.
    warnings: Vec<String>,
}

/// The cache folder of the keyword arguments `cache_dir` and `use_cache` that every loading
/// function takes (`Scene`, `MotionWorld`, the batch functions), as the CLI's `--cache` and
/// `--no-cache`: none when `use_cache` is false, else `cache_dir`, else the default folder
/// ([`pickplace::cache::default_dir`]); with the warning when that folder cannot be found
/// (no cache then).
pub(crate) fn cache_folder(
    cache_dir: Option<PathBuf>,
    use_cache: bool,
) -> (Option<PathBuf>, Option<CacheWarning>) {
    match (use_cache, cache_dir) {
        (false, _) => (None, None),
        (true, Some(dir)) => (Some(dir), None),
        (true, None) => match pickplace::cache::default_dir() {
            Ok(dir) => (Some(dir), None),
            Err(warning) => (None, Some(warning)),
        },
    }
}

/// The setup options of the keyword arguments `cache_dir`, `use_cache` and `package_dirs`
/// ([`cache_folder`]), and the warning when there is no cache folder at all.
pub(crate) fn setup_options(
    cache_dir: Option<PathBuf>,
    use_cache: bool,
    package_dirs: Vec<PathBuf>,
) -> (SetupOptions, Option<CacheWarning>) {
    let (cache_dir, warning) = cache_folder(cache_dir, use_cache);
    let options = SetupOptions {
        cache_dir,
        package_dirs,
        progress: None,
    };
    (options, warning)
}

impl Scene {
    /// Sets up with the GIL released.
    fn set_up(
        py: Python<'_>,
        load: impl FnOnce(&SetupOptions) -> pickplace::Result<Setup> + Send,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        let (options, warning) = setup_options(cache_dir, use_cache, package_dirs);
        let setup = py.detach(|| load(&options)).map_err(|e| facade(py, &e))?;
        let mut warnings: Vec<String> = warning.iter().map(ToString::to_string).collect();
        warnings.extend(setup.warnings.iter().map(ToString::to_string));
        warnings.extend(setup.mesh_warnings.iter().map(ToString::to_string));
        Ok(Self {
            setup: Arc::new(setup),
            warnings,
        })
    }

    /// Parses TOML text and sets it up; `name` names the scene in errors.
    fn from_text(
        py: Python<'_>,
        text: &str,
        name: &Path,
        base_dir: &Path,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        let scene = pickplace::Scene::parse(text, name, base_dir).map_err(|e| input(&e))?;
        let name = name.to_path_buf();
        Self::set_up(
            py,
            move |options| Setup::new(scene, &name, options),
            cache_dir,
            use_cache,
            package_dirs,
        )
    }
}

#[pymethods]
impl Scene {
    /// Reads a scene file (TOML, docs/scene-format.md) and sets it up. Relative paths in the
    /// file are relative to its folder.
    ///
    /// Raises InputError (a ValueError) naming the file and what is wrong, as `pickplace
    /// plan` prints it.
    #[staticmethod]
    #[pyo3(signature = (path, *, cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        Self::set_up(
            py,
            move |options| Setup::load(&path, options),
            cache_dir,
            use_cache,
            package_dirs,
        )
    }

    /// A scene from TOML text. Relative paths in it are relative to `base_dir` (default: the
    /// working directory); `name` names the scene in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=PathBuf::from("."), *, name=PathBuf::from("<scene>"), cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
    fn from_toml(
        py: Python<'_>,
        text: &str,
        base_dir: PathBuf,
        name: PathBuf,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        Self::from_text(
            py,
            text,
            &name,
            &base_dir,
            cache_dir,
            use_cache,
            package_dirs,
        )
    }

    /// A scene from Python values: a dict with the TOML file's tables and keys (`robot`,
    /// `object`, `environment`, `target`, `planner`, `trajectory`; docs/scene-format.md).
    /// Relative paths are relative to `base_dir`. None values are not allowed (leave the key
    /// out); errors name the key as in TOML.
    #[staticmethod]
    #[pyo3(signature = (scene, base_dir=PathBuf::from("."), *, name=PathBuf::from("<dict>"), cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
    fn from_dict(
        py: Python<'_>,
        scene: &Bound<'_, PyAny>,
        base_dir: PathBuf,
        name: PathBuf,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        let json: String = py
            .import("json")?
            .call_method1("dumps", (scene,))
            .map_err(|e| input_msg(format!("{}: not a JSON-like dict: {e}", name.display())))?
            .extract()?;
        let table: toml::Table = serde_json::from_str(&json).map_err(|e| {
            input_msg(format!(
                "{}: not a table of TOML values (None is not allowed): {e}",
                name.display()
            ))
        })?;
        let text =
            toml::to_string(&table).map_err(|e| input_msg(format!("{}: {e}", name.display())))?;
        Self::from_text(
            py,
            &text,
            &name,
            &base_dir,
            cache_dir,
            use_cache,
            package_dirs,
        )
    }

    /// The scene file (or the name given to `from_toml`/`from_dict`).
    #[getter]
    fn path(&self) -> PathBuf {
        self.setup.scene_path.clone()
    }

    /// The scene as a dict (the TOML file's tables, paths resolved).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.setup.scene)
    }

    /// Every actuated joint of the robot (grippers included), in model order: the columns of
    /// `Plan.positions` and of `start`.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.setup
            .model
            .variable_names()
            .map(str::to_owned)
            .collect()
    }

    /// The robot's start configuration, shape (J,), rad or m.
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.setup.start.to_pyarray(py)
    }

    /// The object's start pose in the world, 4x4 homogeneous matrix.
    #[getter]
    fn object_start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        crate::convert::matrix4(py, &self.setup.object_start)
    }

    /// The target point (the paper's click) in the world, shape (3,), m.
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let p = self.setup.scene.target_point();
        [p.x, p.y, p.z].to_pyarray(py)
    }

    /// The scene's planner seed (`planner.seed`, default 1).
    #[getter]
    fn seed(&self) -> u64 {
        self.setup.scene.planner.seed
    }

    /// The scene's time budget (`planner.time_budget`, s).
    #[getter]
    fn time_budget(&self) -> f64 {
        self.setup.scene.planner.time_budget
    }

    /// The environment parts' names, in scene order.
    #[getter]
    fn environment(&self) -> Vec<String> {
        self.setup
            .environment
            .iter()
            .map(|e| e.name.clone())
            .collect()
    }

    /// The environment parts as the planner has them, in scene order: dicts with `name`,
    /// `vertices` (V, 3) and `faces` (F, 3) in the part's frame (a mesh file's triangles, or a
    /// box's, cylinder's or sphere's tessellation), `world_from_mesh` (4x4) and `clusters`
    /// (its environment-contact clusters, the `clusters` list of `pickplace.clusters`).
    fn environment_parts<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let mut out = Vec::new();
        for part in &self.setup.environment {
            let d = PyDict::new(py);
            d.set_item("name", &part.name)?;
            let (vertices, faces) = mesh_arrays(py, part.mesh.vertices(), part.mesh.triangles())?;
            d.set_item("vertices", vertices)?;
            d.set_item("faces", faces)?;
            d.set_item("world_from_mesh", matrix4(py, &part.world_from_mesh))?;
            let doc = pickplace_geometry::cluster::ClustersJson::new(
                &part.clustering,
                &part.mesh,
                &part.name,
            );
            let doc = to_python(py, &doc)?;
            d.set_item("clusters", doc.get_item("clusters")?)?;
            out.push(d);
        }
        Ok(out)
    }

    /// What setting up did (cache hits, builds, times), one line each.
    #[getter]
    fn log(&self) -> Vec<String> {
        self.setup.log.clone()
    }

    /// Why the cache could not be used, or only in part (the setup went on in memory).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {} joints, {} environment parts)",
            self.setup.scene_path.display().to_string(),
            self.setup.model.variable_count(),
            self.setup.environment.len()
        )
    }
}
