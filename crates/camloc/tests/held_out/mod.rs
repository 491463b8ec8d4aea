//! The subjects the project's evaluations hold out (`xtask/src/generalise.rs`), for the tests
//! that need poses of people no default file was fitted on.

/// The held-out subjects' ids.
pub const HELD_OUT: [&str; 9] = ["06", "09", "16", "17", "35", "47", "113", "127", "141"];
