//! Float arguments that refuse `True` and `False` (Python's `bool` and NumPy's `bool_`, which
//! convert to 1.0 and 0.0 and would be read as a height of 1 m, a minimum score of 1 or 1
//! frame a second without a word). Each is read with `#[pyo3(from_py_with = ...)]`, so the
//! signature keeps its plain default and the refusal names the argument.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyBool;

/// `value` as a float (a `float`, an `int`, a NumPy scalar), or a `TypeError` naming the
/// argument `name` when it is a bool or not a number (a string such as `"30"`).
fn number(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    let numpy_bool = value.py().import("numpy")?.getattr("bool_")?;
    if value.is_instance_of::<PyBool>() || value.is_instance(&numpy_bool)? {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number, not a bool"
        )));
    }
    value.extract::<f64>().map_err(|_| {
        let kind = value
            .get_type()
            .name()
            .map_or_else(|_| "another type".to_owned(), |n| n.to_string());
        PyTypeError::new_err(format!("{name}: expected a number, got {kind}"))
    })
}

/// The `min_score` argument.
pub(crate) fn min_score(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    number(value, "min_score")
}

/// The `fps` argument (frames a second).
pub(crate) fn fps(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    number(value, "fps")
}

/// The `unit_m` argument (metres per BVH unit).
pub(crate) fn unit_m(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    number(value, "unit_m")
}

/// The `person_height` argument (metres), `None` for none.
pub(crate) fn person_height(value: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
    if value.is_none() {
        return Ok(None);
    }
    number(value, "person_height").map(Some)
}
