//! The interactive page of `--html`: one self-contained HTML file (no network, no server) with
//! the poses of a run as JSON and a small script (`viewer.js`, documented there) that draws
//! the 2D input and reprojection, the 3D skeleton and the camera sphere, with a timeline.

use camloc::geometry::CameraSet;
use camloc::keypoints::KeypointRecord;
use camloc::reconstruct::Reconstruction;
use camloc::skeleton::{LIMBS, Landmark};
use camloc::{CameraLabel, Localization};
use serde::Serialize;

/// The script of the page.
const SCRIPT: &str = include_str!("viewer.js");

/// One pose of the page.
#[derive(Clone, Debug, Serialize)]
pub struct ViewFrame {
    /// The pose's id.
    id: String,
    /// Its video frame, when the input has one.
    frame: Option<u64>,
    /// Its person, when the input has one.
    person: Option<u64>,
    /// The input landmarks (image units, v down), `None` where missing or far off the others
    /// (read as missing and filled in: the page rings them).
    input: Vec<Option<[f64; 2]>>,
    /// The reconstruction projected by its camera (image units).
    reprojection: Option<Vec<[f64; 2]>>,
    /// The 3D landmarks, metres, canonical frame.
    pose: Option<Vec<[f64; 3]>>,
    /// The most probable camera.
    label: Option<CameraLabel>,
    /// Every camera's probability, in label order.
    probabilities: Option<Vec<f64>>,
    /// Azimuth, elevation and uncertainty radius of the continuous viewpoint, degrees.
    direction: Option<[f64; 3]>,
    /// The camera smoothed over the sequence.
    smoothed: Option<CameraLabel>,
    /// The continuous viewpoint smoothed over the sequence: azimuth and elevation, degrees.
    smoothed_direction: Option<[f64; 2]>,
    /// Why the pose could not be localized or reconstructed.
    error: Option<String>,
}

impl ViewFrame {
    /// The page's record of `record` with what was found for it; `error` says what failed.
    pub fn new(
        record: &KeypointRecord,
        localization: Option<&Localization>,
        reconstruction: Option<&Reconstruction>,
        error: Option<String>,
    ) -> ViewFrame {
        let direction =
            localization.and_then(|l| Some([l.azimuth_deg?, l.elevation_deg?, l.uncertainty_deg?]));
        ViewFrame {
            // Control and bidirectional formatting characters escaped, as in every other
            // output (a right-to-left override turned the page's caption around).
            id: camloc::store::escaped(&record.id).into_owned(),
            frame: record.frame,
            person: record.person,
            input: camloc::without_far_off_landmarks(&record.pose)
                .0
                .points
                .to_vec(),
            reprojection: reconstruction.map(|r| r.reprojection().to_vec()),
            pose: reconstruction.map(|r| r.pose.points.to_vec()),
            label: localization.map(|l| l.label),
            probabilities: localization.map(|l| l.probabilities.clone()),
            direction,
            smoothed: None,
            smoothed_direction: None,
            error,
        }
    }

    /// Records the camera and the continuous viewpoint (azimuth, elevation, degrees)
    /// smoothed over the sequence.
    pub fn set_smoothed(&mut self, label: CameraLabel, direction: Option<(f64, f64)>) {
        self.smoothed = Some(label);
        self.smoothed_direction = direction.map(|(a, e)| [a, e]);
    }
}

/// A camera of the sphere.
#[derive(Serialize)]
struct CameraJson {
    label: u16,
    azimuth: f64,
    elevation: f64,
}

/// A group of frames the timeline runs over: a person of a sequence, or the whole input.
#[derive(Serialize)]
pub struct Group {
    /// Shown in the group menu.
    pub name: String,
    /// Indices into the page's frames, in play order.
    pub frames: Vec<usize>,
}

/// Everything the script reads.
#[derive(Serialize)]
struct PageData<'a> {
    title: &'a str,
    fps: f64,
    cameras: Vec<CameraJson>,
    landmarks: Vec<&'static str>,
    limbs: Vec<[usize; 2]>,
    groups: &'a [Group],
    frames: &'a [ViewFrame],
}

/// The page: `frames` in `groups` (each a person of a sequence, or one group of every pose),
/// the cameras of `cameras`, played at `fps` frames per second.
pub fn page(
    title: &str,
    cameras: &CameraSet,
    frames: &[ViewFrame],
    groups: &[Group],
    fps: f64,
) -> String {
    let data = PageData {
        title,
        fps,
        cameras: cameras
            .viewpoints()
            .iter()
            .map(|v| CameraJson {
                label: v.label,
                azimuth: v.azimuth_deg,
                elevation: v.elevation_deg,
            })
            .collect(),
        landmarks: Landmark::ALL.iter().map(|l| l.name()).collect(),
        limbs: LIMBS.iter().map(|(a, b)| [a.index(), b.index()]).collect(),
        groups,
        frames,
    };
    // In a script element `</script` ends it and `<!--` changes how the parser looks for
    // that end: every `<` (only ever inside a JSON string) is written `\u003c`.
    let json = serde_json::to_string(&data)
        .unwrap_or_else(|_| "{}".to_owned())
        .replace('<', "\\u003c");
    let title = camloc::store::markup_escaped(title);
    format!(
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 12px; color: #333; }}
.panels {{ display: flex; gap: 12px; flex-wrap: wrap; }}
figure {{ margin: 0; }} figcaption {{ font-size: 13px; color: #555; }}
canvas {{ border: 1px solid #ddd; }} #skeleton, #sphere {{ cursor: grab; }}
#errors {{ color: #c00; }} #caption {{ margin: 8px 0; }}
</style></head>
<body data-status="loading">
<h3 id="title"></h3>
<div id="timeline"><select id="group"></select> <button id="play">play</button>
<input id="scrub" type="range" min="0" max="0" value="0" style="width: 60%"> <span id="position"></span></div>
<div id="caption"></div>
<div class="panels">
<figure><canvas id="image" width="360" height="420"></canvas><figcaption>2D input (pale band) and reprojection (thin)</figcaption></figure>
<figure><canvas id="skeleton" width="420" height="420"></canvas><figcaption>3D skeleton (metres; drag to turn, wheel to zoom)</figcaption></figure>
<figure><canvas id="sphere" width="420" height="420"></canvas><figcaption>cameras (dot size: probability), direction and uncertainty (orange)</figcaption></figure>
</div>
<p style="font-size: 13px"><span style="color: #1f77b4">left</span> / <span style="color: #d62728">right</span> limbs</p>
<pre id="errors"></pre>
<script type="application/json" id="data">{json}</script>
<script>
{SCRIPT}
</script>
</body></html>
"#
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_holds_its_data_safely_and_the_script() {
        let groups = [Group {
            name: "<!--<script> </script>".into(),
            frames: vec![],
        }];
        let html = page(
            "a </script> title & <b>",
            &CameraSet::table1(),
            &[],
            &groups,
            30.0,
        );
        // The title appears escaped, and the data cannot close its script element.
        assert!(html.contains("a &lt;/script&gt; title &amp; &lt;b&gt;"));
        assert_eq!(html.matches("</script>").count(), 2);
        assert!(html.contains("function drawSphere"));
        let start = html.find(r#"id="data">"#).unwrap_or(0) + 10;
        let end = start + html[start..].find("</script>").unwrap_or(0);
        let data: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
        assert_eq!(data["cameras"].as_array().map(Vec::len), Some(12));
        assert_eq!(data["limbs"].as_array().map(Vec::len), Some(14));
        // A name that opens an HTML comment in the script element (which kept the page from
        // loading) is kept as it was, in an escape.
        assert!(!html.contains("<!--"));
        assert_eq!(data["groups"][0]["name"], "<!--<script> </script>");
    }
}
