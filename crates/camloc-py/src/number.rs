//! [`Number`]: `reconstruct`'s `person_height`, a float that refuses `True` and `False`
//! (Python's `bool` and NumPy's `bool_`, which convert to 1.0 and 0.0 and would be read as a
//! height of 1 m without a word).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyBool;
use pyo3::{Borrowed, FromPyObject};

/// A number of metres given as `person_height` (a `float`, an `int`, a NumPy scalar), not a
/// bool.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Number(pub(crate) f64);

impl<'a, 'py> FromPyObject<'a, 'py> for Number {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let numpy_bool = ob.py().import("numpy")?.getattr("bool_")?;
        if ob.is_instance_of::<PyBool>() || ob.is_instance(&numpy_bool)? {
            return Err(PyTypeError::new_err(
                "person_height: a number of metres, not a bool",
            ));
        }
        Ok(Number(ob.extract::<f64>()?))
    }
}
