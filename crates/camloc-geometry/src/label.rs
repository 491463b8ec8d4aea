//! [`CameraLabel`]: the 1-based class label of a camera (Table 1 numbering).

use std::fmt;
use std::num::NonZeroU16;

use serde::{Deserialize, Serialize};

use crate::GeometryError;

/// The label of one camera of a [`CameraSet`](crate::CameraSet): 1-based, as in Table 1 of the
/// paper (`01` lower front ... `12` upper right for [`CameraSet::table1`](crate::CameraSet::table1)).
///
/// Construction rejects 0, so a `CameraLabel` always names a class; whether that class exists
/// in a given camera set is checked by [`CameraSet::label`](crate::CameraSet::label).
/// Displayed with two digits (`07`); serialised as the plain number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(try_from = "u16", into = "u16")]
pub struct CameraLabel(NonZeroU16);

impl CameraLabel {
    /// The label `value` (1-based).
    ///
    /// # Errors
    /// [`GeometryError::InvalidLabel`] for 0.
    pub fn new(value: u16) -> Result<CameraLabel, GeometryError> {
        NonZeroU16::new(value)
            .map(CameraLabel)
            .ok_or(GeometryError::InvalidLabel {
                label: value,
                cameras: None,
            })
    }

    /// The label of the class with 0-based index `index` (label `index + 1`).
    ///
    /// # Errors
    /// [`GeometryError::InvalidLabel`] when `index + 1` does not fit a `u16`.
    pub fn from_index(index: usize) -> Result<CameraLabel, GeometryError> {
        u16::try_from(index + 1)
            .map_err(|_| GeometryError::InvalidLabel {
                label: u16::MAX,
                cameras: None,
            })
            .and_then(CameraLabel::new)
    }

    /// The 1-based number.
    pub fn get(self) -> u16 {
        self.0.get()
    }

    /// The 0-based class index (`label - 1`), e.g. into a probability vector.
    pub fn index(self) -> usize {
        usize::from(self.0.get()) - 1
    }
}

impl fmt::Display for CameraLabel {
    /// Two digits, as in Table 1: `01` ... `12`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:02}", self.0.get())
    }
}

impl TryFrom<u16> for CameraLabel {
    type Error = GeometryError;
    fn try_from(value: u16) -> Result<CameraLabel, GeometryError> {
        CameraLabel::new(value)
    }
}

impl From<CameraLabel> for u16 {
    fn from(label: CameraLabel) -> u16 {
        label.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_is_rejected_and_labels_print_with_two_digits() {
        assert!(CameraLabel::new(0).is_err());
        let seven = CameraLabel::new(7).unwrap();
        assert_eq!(seven.to_string(), "07");
        assert_eq!(seven.index(), 6);
        assert_eq!(CameraLabel::from_index(6).unwrap(), seven);
        assert_eq!(CameraLabel::new(123).unwrap().to_string(), "123");
        assert!(CameraLabel::from_index(usize::from(u16::MAX)).is_err());
    }
}
