//! Number and flag arguments read strictly, each refusal naming its argument: floats that
//! refuse `True` and `False` (Python's `bool` and NumPy's `bool_`, which convert to 1.0 and 0.0
//! and would be read as a height of 1 m, a minimum score of 1 or 1 frame a second without a
//! word), flags that take only a bool, counts that take only a whole number. Each is read with
//! `#[pyo3(from_py_with = ...)]`, so the signature keeps its plain default.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBool;

/// `value` as a float (a `float`, an `int`, a NumPy scalar), or a `TypeError` naming the
/// argument `name` when it is a bool or not a number (a string such as `"30"`).
fn number(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    if is_bool(value)? {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number, not a bool"
        )));
    }
    value.extract::<f64>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected a number, got {}",
            type_name(value)
        ))
    })
}

/// Whether `value` is Python's `bool` or NumPy's `bool_`.
pub(crate) fn is_bool(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    let numpy_bool = value.py().import("numpy")?.getattr("bool_")?;
    Ok(value.is_instance_of::<PyBool>() || value.is_instance(&numpy_bool)?)
}

/// The `min_score` argument.
pub(crate) fn min_score(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    number(value, "min_score")
}

/// The `fps` argument (frames a second), one the command line's `--fps` takes
/// ([`camloc::frame_rate_problem`]), else a `ValueError`.
pub(crate) fn fps(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    let fps = number(value, "fps")?;
    match camloc::frame_rate_problem(fps) {
        None => Ok(fps),
        Some(problem) => Err(PyValueError::new_err(format!(
            "fps: {problem}, got {fps:?}"
        ))),
    }
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

/// The name of `value`'s type, for messages.
pub(crate) fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "another type".to_owned(), |n| n.to_string())
}

/// `value` as a bool (Python's `bool` or NumPy's `bool_`), or a `TypeError` naming the
/// argument `name` (`1` for `True` is refused, as the type hints say).
fn flag(value: &Bound<'_, PyAny>, name: &str) -> PyResult<bool> {
    if is_bool(value)? {
        return value.is_truthy();
    }
    Err(PyTypeError::new_err(format!(
        "{name}: expected True or False, got {}",
        type_name(value)
    )))
}

/// The `sequence` argument.
pub(crate) fn sequence(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    flag(value, "sequence")
}

/// The `derive_torso` argument.
pub(crate) fn derive_torso(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    flag(value, "derive_torso")
}

/// The `recursive` argument.
pub(crate) fn recursive(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    flag(value, "recursive")
}

/// `value` as a whole number of at least `least` (an `int` or a NumPy integer; not a bool, not
/// a float such as `1e5`), or a `TypeError` or `ValueError` naming the argument `name`.
fn count(value: &Bound<'_, PyAny>, name: &str, least: u64) -> PyResult<u64> {
    let numpy_integer = value.py().import("numpy")?.getattr("integer")?;
    let whole =
        value.is_instance_of::<pyo3::types::PyInt>() || value.is_instance(&numpy_integer)?;
    if value.is_instance_of::<PyBool>() || !whole {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a whole number (an int), got {}",
            type_name(value)
        )));
    }
    (value.extract::<u64>().ok())
        .filter(|&n| n >= least)
        .ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "{name}: expected a whole number >= {least}, got {value}"
            ))
        })
}

/// The `sequence_max_rows` argument.
pub(crate) fn sequence_max_rows(value: &Bound<'_, PyAny>) -> PyResult<usize> {
    let rows = count(value, "sequence_max_rows", 0)?;
    usize::try_from(rows).map_err(|_| {
        pyo3::exceptions::PyValueError::new_err(format!("sequence_max_rows: {rows} is too large"))
    })
}

/// The `max_input_bytes` argument.
pub(crate) fn max_input_bytes(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    count(value, "max_input_bytes", 1)
}
