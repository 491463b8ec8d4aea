//! A walking person for the sequence tests: the example's standing person moved across the
//! image frame by frame.

use serde_json::Value;

use crate::common::fixture;

/// Pixels a frame the person of [`walk_document`] moves to the right.
pub const WALK_STEP_PX: f64 = 8.0;

/// A `camloc-keypoints` document of the example's standing person moving across the image by
/// [`WALK_STEP_PX`] a frame, with the frames of `numbers` (frame numbers kept).
pub fn walk_document(numbers: impl Iterator<Item = usize>) -> Value {
    let example: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("keypoints/example.json")).unwrap())
            .unwrap();
    let standing = &example["poses"][0]["landmarks"];
    let poses: Vec<Value> = numbers
        .map(|t| {
            let moved: serde_json::Map<String, Value> = standing
                .as_object()
                .unwrap()
                .iter()
                .map(|(name, p)| {
                    let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
                    (
                        name.clone(),
                        serde_json::json!([x + WALK_STEP_PX * t as f64, y]),
                    )
                })
                .collect();
            serde_json::json!({"id": format!("f{t}"), "frame": t, "person": 0, "landmarks": moved})
        })
        .collect();
    serde_json::json!({"format": "camloc-keypoints", "version": 1, "poses": poses})
}
