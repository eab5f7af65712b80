//! `pickplace.Robot`: a URDF (+ SRDF) model with forward kinematics, Jacobians and IK on
//! numpy arrays (the `pickplace robot fk|ik` commands).

use crate::convert::{isometry, matrices, matrix4, vector};
use crate::errors::{input, input_msg};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, ToPyArray};
use pickplace_geometry::math::{Isometry3, Point3, UnitVector3, Vector3};
use pickplace_robot::model::UnreadableMesh;
use pickplace_robot::{IkOptions, IkSolver, Jacobian, LoadOptions, RobotModel, Semantics};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A robot model read from a URDF, with its SRDF's groups when given. Poses are
/// `root_from_link` as 4x4 homogeneous matrices (m); joint vectors have one value per
/// actuated joint (`joint_names`, rad or m). Immutable and safe to share between threads.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct Robot {
    model: RobotModel,
    semantics: Option<Semantics>,
}

impl Robot {
    /// `q` as a full joint vector of this model.
    fn joints(&self, q: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        let q = vector(q, "q")?;
        if q.len() != self.model.variable_count() {
            return Err(input_msg(format!(
                "q: {} values for {} joints ({})",
                q.len(),
                self.model.variable_count(),
                self.model.variable_names().collect::<Vec<_>>().join(", ")
            )));
        }
        Ok(q)
    }

    fn link(&self, name: &str) -> PyResult<usize> {
        self.model.require_link(name).map_err(|e| input(&e))
    }

    fn semantics(&self) -> PyResult<&Semantics> {
        self.semantics.as_ref().ok_or_else(|| {
            input_msg(format!(
                "{}: no SRDF was given: groups need Robot.load(urdf, srdf)",
                self.model.source().display()
            ))
        })
    }
}

#[pymethods]
impl Robot {
    /// Reads a URDF (and an SRDF for groups and IK). `package://` URIs resolve through
    /// `package_dirs`, then `ROS_PACKAGE_PATH`; `skip_unreadable_meshes` leaves out meshes
    /// that cannot be read instead of failing.
    ///
    /// Raises InputError naming the file and what is wrong.
    #[staticmethod]
    #[pyo3(signature = (urdf, srdf=None, *, package_dirs=Vec::new(), skip_unreadable_meshes=false))]
    fn load(
        py: Python<'_>,
        urdf: PathBuf,
        srdf: Option<PathBuf>,
        package_dirs: Vec<PathBuf>,
        skip_unreadable_meshes: bool,
    ) -> PyResult<Self> {
        let options = LoadOptions {
            package_dirs,
            unreadable_mesh: if skip_unreadable_meshes {
                UnreadableMesh::Skip
            } else {
                UnreadableMesh::Error
            },
            ..LoadOptions::default()
        };
        py.detach(|| {
            let model = RobotModel::from_urdf_file(&urdf, &options).map_err(|e| input(&e))?;
            let semantics = srdf
                .map(|path| Semantics::from_file(&model, &path))
                .transpose()
                .map_err(|e| input(&e))?;
            Ok(Self { model, semantics })
        })
    }

    /// The robot's name in the URDF.
    #[getter]
    fn name(&self) -> &str {
        self.model.name()
    }

    /// Actuated joints in model order: the entries of every joint vector.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.variable_names().map(str::to_owned).collect()
    }

    /// Every link, in model order (the first is the root): the rows of `fk(q)`.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        self.model.links().iter().map(|l| l.name.clone()).collect()
    }

    /// Lower joint limits, shape (J,) (−inf for continuous joints).
    #[getter]
    fn lower_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.model.variable_limits().map(|l| l.lower).collect();
        v.to_pyarray(py)
    }

    /// Upper joint limits, shape (J,) (+inf for continuous joints).
    #[getter]
    fn upper_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.model.variable_limits().map(|l| l.upper).collect();
        v.to_pyarray(py)
    }

    /// Velocity limits, shape (J,), rad/s or m/s.
    #[getter]
    fn velocity_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v: Vec<f64> = self.model.variable_limits().map(|l| l.velocity).collect();
        v.to_pyarray(py)
    }

    /// The SRDF's planning groups (empty without an SRDF).
    #[getter]
    fn groups(&self) -> Vec<String> {
        self.semantics
            .as_ref()
            .map(|s| s.groups().iter().map(|g| g.name.clone()).collect())
            .unwrap_or_default()
    }

    /// The zero configuration (each joint clamped into its limits), shape (J,).
    fn zero_configuration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.model.zero_configuration().into_pyarray(py)
    }

    /// A named group state of the SRDF (e.g. `home`) applied over `q` (default: zero).
    #[pyo3(signature = (name, q=None))]
    fn state<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        q: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut q = match q {
            Some(q) => self.joints(q)?,
            None => self.model.zero_configuration(),
        };
        self.semantics()?
            .apply_state(&self.model, name, &mut q)
            .map_err(|e| input(&e))?;
        Ok(q.into_pyarray(py))
    }

    /// Forward kinematics. With `link`, that link's pose, shape (4, 4); without, every
    /// link's pose, shape (L, 4, 4) in `link_names` order. `q` is not checked against the
    /// limits.
    #[pyo3(signature = (q, link=None))]
    fn fk<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: Option<&str>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.joints(q)?;
        if let Some(name) = link {
            let index = self.link(name)?;
            let pose = self.model.link_pose(&q, index).map_err(|e| input(&e))?;
            return Ok(matrix4(py, &pose).into_any());
        }
        let poses = self.model.link_poses(&q).map_err(|e| input(&e))?;
        Ok(matrices(py, &poses).into_any())
    }

    /// The Jacobian of a point fixed in `link` (`point`, in the link's frame; default its
    /// origin), shape (6, n): rows are linear (m/s) then angular (rad/s) velocity in the
    /// root frame, columns the joints named in `joints` (default: every joint, model order).
    #[pyo3(signature = (q, link, point=None, joints=None))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: &str,
        point: Option<&Bound<'py, PyAny>>,
        joints: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.joints(q)?;
        let index = self.link(link)?;
        let point = match point {
            Some(p) => {
                let p = vector(p, "point")?;
                if p.len() != 3 {
                    return Err(input_msg(format!("point: {} values, expected 3", p.len())));
                }
                Point3::new(p[0], p[1], p[2])
            }
            None => Point3::origin(),
        };
        let variables: Vec<usize> = match joints {
            Some(names) => names
                .iter()
                .map(|n| {
                    self.model.variable_index(n).ok_or_else(|| {
                        input_msg(format!(
                            "{}: no actuated joint named {n:?}",
                            self.model.source().display()
                        ))
                    })
                })
                .collect::<PyResult<_>>()?,
            None => (0..self.model.variable_count()).collect(),
        };
        let mut j = Jacobian::zeros(variables.len());
        self.model
            .jacobian(&q, index, &point, &variables, &mut j)
            .map_err(|e| input(&e))?;
        let array = Array2::from_shape_fn((6, variables.len()), |(r, c)| j[(r, c)]);
        Ok(array.into_pyarray(py))
    }

    /// The pose of a group's tip link (its TCP frame), shape (4, 4); needs the SRDF.
    fn tcp_pose<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        group: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.joints(q)?;
        let chain = self
            .semantics()?
            .chain(&self.model, group)
            .map_err(|e| input(&e))?;
        Ok(matrix4(py, &chain.pose(&q)))
    }

    /// Inverse kinematics of a group's tip (needs the SRDF) to `pose` (4x4 `root_from_tcp`),
    /// from `seed_q` (default: the SRDF's `home` state, else zero), as `pickplace robot ik`.
    /// `free_axis` (3 values) leaves rotation about that TCP axis free; `seed` seeds the
    /// random restarts. Joints outside the group keep their seed values.
    ///
    /// Returns an IkSolution; `success` is False when no attempt met the tolerances.
    #[pyo3(signature = (pose, group, seed_q=None, *, free_axis=None, seed=0, position_tolerance=1e-4, orientation_tolerance=1e-3))]
    #[allow(clippy::too_many_arguments)]
    fn ik(
        &self,
        py: Python<'_>,
        pose: &Bound<'_, PyAny>,
        group: &str,
        seed_q: Option<&Bound<'_, PyAny>>,
        free_axis: Option<&Bound<'_, PyAny>>,
        seed: u64,
        position_tolerance: f64,
        orientation_tolerance: f64,
    ) -> PyResult<IkSolution> {
        let target: Isometry3 = isometry(pose, "pose")?;
        let semantics = self.semantics()?;
        let solver = IkSolver::for_group(&self.model, semantics, group).map_err(|e| input(&e))?;
        let q = match seed_q {
            Some(q) => self.joints(q)?,
            None => {
                let mut q = self.model.zero_configuration();
                if semantics
                    .srdf()
                    .group_states
                    .iter()
                    .any(|s| s.name == "home")
                {
                    semantics
                        .apply_state(&self.model, "home", &mut q)
                        .map_err(|e| input(&e))?;
                }
                q
            }
        };
        let free_axis = free_axis
            .map(|a| -> PyResult<UnitVector3> {
                let a = vector(a, "free_axis")?;
                if a.len() != 3 {
                    return Err(input_msg(format!(
                        "free_axis: {} values, expected 3",
                        a.len()
                    )));
                }
                UnitVector3::try_new(Vector3::new(a[0], a[1], a[2]), 1e-9)
                    .ok_or_else(|| input_msg("free_axis has zero length"))
            })
            .transpose()?;
        let options = IkOptions {
            free_axis,
            seed,
            position_tolerance,
            orientation_tolerance,
            ..IkOptions::default()
        };
        let solution = py
            .detach(|| solver.solve(&target, &q, &options))
            .map_err(|e| input(&e))?;
        Ok(IkSolution { solution })
    }

    fn __repr__(&self) -> String {
        format!(
            "Robot({:?}, {} joints, {} links, {} groups)",
            self.model.name(),
            self.model.variable_count(),
            self.model.links().len(),
            self.semantics.as_ref().map_or(0, |s| s.groups().len())
        )
    }
}

/// The result of `Robot.ik`.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct IkSolution {
    solution: pickplace_robot::IkSolution,
}

#[pymethods]
impl IkSolution {
    /// True when both tolerances are met.
    #[getter]
    fn success(&self) -> bool {
        self.solution.success
    }

    /// Every joint of the model, shape (J,): the solution, or the best configuration found
    /// when `success` is False.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.solution.positions.to_pyarray(py)
    }

    /// TCP position error, m.
    #[getter]
    fn position_error(&self) -> f64 {
        self.solution.position_error
    }

    /// TCP orientation error, rad (with a free axis, the angle between the axes).
    #[getter]
    fn orientation_error(&self) -> f64 {
        self.solution.orientation_error
    }

    /// Attempts made (1 + random restarts).
    #[getter]
    fn attempts(&self) -> usize {
        self.solution.attempts
    }

    fn __bool__(&self) -> bool {
        self.solution.success
    }

    fn __repr__(&self) -> String {
        format!(
            "IkSolution(success={}, position_error={:.2e}, orientation_error={:.2e}, attempts={})",
            if self.solution.success {
                "True"
            } else {
                "False"
            },
            self.solution.position_error,
            self.solution.orientation_error,
            self.solution.attempts
        )
    }
}
