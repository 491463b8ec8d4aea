//! The reconstructor of camloc's defaults, made once for the process.

use std::sync::OnceLock;

use camloc::PoseReconstructor;
use pyo3::PyResult;

/// The reconstructor of the defaults (`PoseReconstructor::default_reconstructor`), made once.
pub(crate) fn default_reconstructor() -> PyResult<&'static PoseReconstructor> {
    static DEFAULT: OnceLock<Result<PoseReconstructor, String>> = OnceLock::new();
    DEFAULT
        .get_or_init(|| PoseReconstructor::default_reconstructor().map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|message| crate::CamlocError::new_err(message.clone()))
}
