//! The camera's intrinsics as `reconstruct` and `Localizer.localize` take them (`focal_px`,
//! `principal_point`), read strictly.

use camloc::reconstruct::{Intrinsics, MIN_FOCAL_PX};
use pyo3::prelude::*;

use crate::value_error;

/// The camera's intrinsics of the `focal_px` and `principal_point` arguments (a tuple, list
/// or array of the two pixel coordinates), `None` without a focal length; a `ValueError` for
/// a principal point without a focal length or not of two numbers, a `TypeError` saying what
/// is expected for one that is not a sequence of numbers (a text "960,540", say).
pub(crate) fn intrinsics_arg(
    focal_px: Option<&Bound<'_, PyAny>>,
    principal_point: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Intrinsics>> {
    // A number (a NumPy scalar too), named in the error otherwise; `True` (or NumPy's) is
    // not a focal length.
    let focal_px = focal_px
        .map(|f| {
            crate::arrays::refuse_complex(f)?;
            let number = (!crate::number::is_bool(f)?)
                .then(|| f.extract::<f64>().ok())
                .flatten();
            number.ok_or_else(|| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "focal_px: a number of pixels such as 1000.0; got a {}",
                    crate::number::type_name(f)
                ))
            })
        })
        .transpose()?;
    let numbers = |point: &Bound<'_, PyAny>| -> PyResult<Vec<f64>> {
        crate::arrays::refuse_complex(point)?;
        // `True` and `False` (or NumPy's) are no pixel coordinates.
        let has_bool = point.try_iter().is_ok_and(|items| {
            items
                .flatten()
                .take(3)
                .any(|item| crate::number::is_bool(&item).unwrap_or(false))
        });
        let numbers = (!point.is_instance_of::<pyo3::types::PyString>() && !has_bool)
            .then(|| point.extract::<Vec<f64>>().ok())
            .flatten();
        numbers.ok_or_else(|| {
            let type_name = crate::number::type_name(point);
            let shown: String = point
                .repr()
                .map_or_else(|_| String::new(), |r| r.to_string())
                .chars()
                .take(60)
                .collect();
            pyo3::exceptions::PyTypeError::new_err(format!(
                "principal_point: two numbers (u, v) in pixels, as a tuple, list or array such \
                 as (960, 540); got a {type_name}: {shown}"
            ))
        })
    };
    if let Some(focal) = focal_px.filter(|f| !(f.is_finite() && *f >= MIN_FOCAL_PX)) {
        return Err(value_error(format!(
            "focal_px must be a finite number of pixels >= {MIN_FOCAL_PX}, got {focal:?}"
        )));
    }
    let principal_point = match principal_point.map(numbers).transpose()?.as_deref() {
        None => None,
        Some(_) if focal_px.is_none() => {
            return Err(value_error("principal_point needs focal_px"));
        }
        Some(&[u, v]) => Some([u, v]),
        Some(other) => {
            return Err(value_error(format!(
                "principal_point: 2 numbers (u, v), got {}",
                other.len()
            )));
        }
    };
    Ok(focal_px.map(|focal_px| Intrinsics {
        focal_px,
        principal_point,
    }))
}
