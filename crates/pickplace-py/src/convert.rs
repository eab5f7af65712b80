//! Conversions between Rust values and Python ones: numpy arrays, 4 × 4 homogeneous
//! transforms, and serde documents as Python dicts and lists.

use crate::errors::input_msg;
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2};
use pickplace::plan::TrajectoryPoint;
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::math::{Isometry3, Matrix3, Point3, Real, Translation3, UnitQuaternion};
use pyo3::prelude::*;

/// A serde value as Python objects (dicts, lists, str, float, int, None), through JSON: the
/// same document the CLI prints with `--json`.
pub fn to_python<'py, T: serde::Serialize + ?Sized>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A vector of floats from a 1-D float64 numpy array or any sequence of numbers.
pub fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Real>> {
    let values = if let Ok(array) = obj.extract::<PyReadonlyArray1<'_, Real>>() {
        array.as_array().to_vec()
    } else {
        obj.extract::<Vec<Real>>()
            .map_err(|_| input_msg(format!("{what}: expected a 1-D array of numbers")))?
    };
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(input_msg(format!(
            "{what}[{i}] = {} is not finite",
            values[i]
        )));
    }
    Ok(values)
}

/// Rows of equal length as a 2-D float64 array (`columns` gives the width of an empty one).
pub fn rows<'py>(
    py: Python<'py>,
    rows: &[&[Real]],
    columns: usize,
) -> PyResult<Bound<'py, PyArray2<Real>>> {
    let mut flat = Vec::with_capacity(rows.len() * columns);
    for row in rows {
        flat.extend_from_slice(row);
    }
    let array = Array2::from_shape_vec((rows.len(), columns), flat)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// The sample times of a trajectory, shape (N,).
pub fn times<'py>(py: Python<'py>, points: &[TrajectoryPoint]) -> Bound<'py, PyArray1<Real>> {
    let t: Vec<Real> = points.iter().map(|p| p.time_from_start).collect();
    t.into_pyarray(py)
}

/// One field of a trajectory's samples (positions, velocities, accelerations), shape (N, J).
pub fn samples<'py>(
    py: Python<'py>,
    points: &[TrajectoryPoint],
    columns: usize,
    field: impl Fn(&TrajectoryPoint) -> &Vec<Real>,
) -> PyResult<Bound<'py, PyArray2<Real>>> {
    let r: Vec<&[Real]> = points.iter().map(|p| field(p).as_slice()).collect();
    rows(py, &r, columns)
}

/// The 4 × 4 homogeneous matrix of a pose (row-major numpy array).
pub fn matrix4<'py>(py: Python<'py>, pose: &Isometry3) -> Bound<'py, PyArray2<Real>> {
    let h = pose.to_homogeneous();
    let array = Array2::from_shape_fn((4, 4), |(r, c)| h[(r, c)]);
    array.into_pyarray(py)
}

/// Fills `out` (shape (L, 4, 4), row-major) with the homogeneous matrices of `poses`.
fn fill_matrices(poses: &[Isometry3], out: &mut [Real]) {
    for (pose, block) in poses.iter().zip(out.chunks_exact_mut(16)) {
        let h = pose.to_homogeneous();
        for r in 0..4 {
            for c in 0..4 {
                block[4 * r + c] = h[(r, c)];
            }
        }
    }
}

/// The homogeneous matrices of `poses`, shape (L, 4, 4).
pub fn matrices<'py>(py: Python<'py>, poses: &[Isometry3]) -> Bound<'py, PyArray3<Real>> {
    let mut out = Array3::<Real>::zeros((poses.len(), 4, 4));
    if let Some(flat) = out.as_slice_mut() {
        fill_matrices(poses, flat);
    }
    out.into_pyarray(py)
}

/// A triangle mesh as numpy arrays: vertices (V, 3) float64 and faces (F, 3) int64.
pub type MeshArrays<'py> = (Bound<'py, PyArray2<Real>>, Bound<'py, PyArray2<i64>>);

/// A triangle mesh as numpy arrays ([`MeshArrays`]).
pub fn mesh_arrays<'py>(
    py: Python<'py>,
    vertices: &[Point3],
    triangles: &[[u32; 3]],
) -> PyResult<MeshArrays<'py>> {
    let points: Vec<[Real; 3]> = vertices.iter().map(|v| [v.x, v.y, v.z]).collect();
    let points: Vec<&[Real]> = points.iter().map(|v| v.as_slice()).collect();
    let faces: Vec<i64> = triangles
        .iter()
        .flat_map(|t| t.iter().map(|&i| i64::from(i)))
        .collect();
    let faces = Array2::from_shape_vec((triangles.len(), 3), faces)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok((rows(py, &points, 3)?, faces.into_pyarray(py)))
}

/// Largest deviation tolerated from a rotation matrix (orthonormal, determinant 1) and from
/// the last row `[0, 0, 0, 1]`.
const ROTATION_TOLERANCE: Real = 1e-6;

/// A pose from a 4 × 4 homogeneous matrix (any nested sequence or array of that shape).
pub fn isometry(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Isometry3> {
    let m: Vec<Vec<Real>> = if let Ok(array) = obj.extract::<PyReadonlyArray2<'_, Real>>() {
        array
            .as_array()
            .rows()
            .into_iter()
            .map(|r| r.to_vec())
            .collect()
    } else {
        obj.extract::<Vec<Vec<Real>>>()
            .map_err(|_| input_msg(format!("{what}: expected a 4x4 homogeneous matrix")))?
    };
    if m.len() != 4 || m.iter().any(|r| r.len() != 4) {
        return Err(input_msg(format!(
            "{what}: expected a 4x4 homogeneous matrix, got {} rows",
            m.len()
        )));
    }
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(input_msg(format!("{what}: the matrix is not finite")));
    }
    let last = [0.0, 0.0, 0.0, 1.0];
    if m[3]
        .iter()
        .zip(last)
        .any(|(a, b)| (a - b).abs() > ROTATION_TOLERANCE)
    {
        return Err(input_msg(format!(
            "{what}: the last row must be [0, 0, 0, 1], not {:?}",
            m[3]
        )));
    }
    let r = Matrix3::from_fn(|i, j| m[i][j]);
    let orthonormal = (r.transpose() * r - Matrix3::identity()).amax() <= ROTATION_TOLERANCE;
    if !orthonormal || r.determinant() <= 0.0 {
        return Err(input_msg(format!(
            "{what}: the upper-left 3x3 block is not a rotation matrix"
        )));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Isometry3::from_parts(
        Translation3::new(m[0][3], m[1][3], m[2][3]),
        rotation,
    ))
}
