use std::path::Path;

use camloc::CameraLocalizer;
use camloc::keypoints::{KeypointFormat, ReadOptions, open_keypoints};
use camloc::skeleton::Landmark;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use super::*;
use crate::cli::stream::json_line;

/// The probabilities as serde_json wrote them: a map from camera label text to probability.
struct Probabilities<'a>(&'a [String], &'a [f64]);

impl Serialize for Probabilities<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.1.len()))?;
        for (label, p) in self.0.iter().zip(self.1) {
            map.serialize_entry(label, p)?;
        }
        map.end()
    }
}

/// What serde_json wrote for a localization before [`LocalizationJson`] (its reference): the
/// same keys in the same order, each value serialised by serde.
struct BySerde<'a> {
    labels: &'a [String],
    record: &'a KeypointRecord,
    loc: &'a Localization,
}

impl Serialize for BySerde<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let (record, loc) = (self.record, self.loc);
        let names = |landmarks: &[Landmark]| landmarks.iter().map(|l| l.name()).collect::<Vec<_>>();
        let r = &loc.rotation;
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry("id", &record.id)?;
        map.serialize_entry("source", &record.source)?;
        for (key, place) in [("frame", record.frame), ("person", record.person)] {
            if let Some(place) = place {
                map.serialize_entry(key, &place)?;
            }
        }
        map.serialize_entry("label", &loc.label)?;
        map.serialize_entry("level", loc.level.name())?;
        map.serialize_entry("side", loc.side.name())?;
        map.serialize_entry("probability", &loc.probability)?;
        map.serialize_entry("folded_label", &loc.folded_label)?;
        let direction = [
            ("azimuth_deg", loc.azimuth_deg),
            ("elevation_deg", loc.elevation_deg),
            ("uncertainty_deg", loc.uncertainty_deg),
        ];
        for (key, degrees) in direction.iter().filter_map(|&(key, d)| Some((key, d?))) {
            map.serialize_entry(key, &degrees)?;
        }
        let rows = [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]);
        map.serialize_entry("rotation", &rows)?;
        let probabilities = Probabilities(self.labels, &loc.probabilities);
        map.serialize_entry("probabilities", &probabilities)?;
        map.serialize_entry("missing", &names(&loc.missing))?;
        map.serialize_entry("derived", &names(&record.derived))?;
        map.end()
    }
}

fn by_serde(labels: &[String], record: &KeypointRecord, loc: &Localization) -> String {
    json_line(&BySerde {
        labels,
        record,
        loc,
    })
}

/// The default model, its JSON writer and its camera label texts (camera order).
fn setup() -> (CameraLocalizer, LocalizationJson, Vec<String>) {
    let localizer = CameraLocalizer::default_model().unwrap();
    let objects = LocalizationJson::new(localizer.cameras());
    let labels = localizer
        .cameras()
        .viewpoints()
        .iter()
        .map(|v| v.label_text())
        .collect();
    (localizer, objects, labels)
}

/// The fixture poses of `fixtures/keypoints/example.json`, each also moved by a few pixels and
/// with one landmark dropped (about 200 poses in all, many different numbers).
fn records() -> Vec<KeypointRecord> {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/example.json");
    let options = ReadOptions::default();
    let read: Vec<KeypointRecord> = open_keypoints(&file, Some(KeypointFormat::Camloc), &options)
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let mut out = read.clone();
    // A fixed pseudo-random walk (a linear congruential generator), no dependency needed.
    let mut state = 12345u64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 6.0 - 3.0
    };
    for k in 0..200 {
        let mut record = read[k % read.len()].clone();
        for [u, v] in record.pose.points.iter_mut().flatten() {
            *u += noise();
            *v += noise();
        }
        record.pose.points[2 + k % 13] = None;
        record.id = format!("pose {k}");
        out.push(record);
    }
    out
}

#[test]
fn every_object_is_byte_for_byte_what_serde_json_wrote() {
    let (localizer, objects, labels) = setup();
    let mut compared = 0;
    for record in records() {
        let Ok(loc) = localizer.localize_partial(&record.pose) else {
            continue;
        };
        let ours = objects.object(&record, &loc);
        assert_eq!(ours, by_serde(&labels, &record, &loc));
        compared += 1;
    }
    assert!(compared > 150, "{compared} poses localized");
}

/// Ids and sources with every kind of character JSON escapes, frames and persons, missing
/// direction heads and the numbers that are printed differently (NaN and infinities as null,
/// negative zero, the smallest and largest, exponents).
#[test]
fn escapes_absent_fields_and_special_numbers_are_written_as_serde_json_wrote_them() {
    let (localizer, objects, labels) = setup();
    let mut record = records().remove(0);
    let loc = localizer.localize_partial(&record.pose).unwrap();
    let ids = [
        String::new(),
        "quote \" backslash \\ slash / tab \t newline \n cr \r".to_owned(),
        (0u8..0x20).map(char::from).collect::<String>() + "\u{7f}",
        "é ü 人 🙂 \u{2028}".to_owned(),
    ];
    let numbers = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -0.0,
        f64::MIN_POSITIVE,
        5e-324,
        f64::MAX,
        1e21,
        1e-7,
        0.1 + 0.2,
        123456789.0,
    ];
    for (k, id) in ids.iter().enumerate() {
        record.id.clone_from(id);
        record.source = format!("{id}: [{k}]");
        record.frame = (k % 2 == 0).then_some(k as u64 * 1_000_000_007);
        record.person = (k > 1).then_some(u64::MAX - k as u64);
        record.derived = vec![Landmark::Pelvis, Landmark::Neck][..k % 3].to_vec();
        for (n, &x) in numbers.iter().enumerate() {
            let mut loc = loc.clone();
            loc.probability = x;
            loc.rotation[(n % 3, (n + k) % 3)] = x;
            loc.probabilities[n % labels.len()] = x;
            loc.azimuth_deg = (n % 3 != 0).then_some(x);
            loc.elevation_deg = (n % 3 != 1).then_some(-x);
            loc.uncertainty_deg = (n % 2 == 0).then_some(x);
            loc.missing = Landmark::ALL[..n % 4].to_vec();
            let ours = objects.object(&record, &loc);
            assert_eq!(ours, by_serde(&labels, &record, &loc), "id {id:?}, {x}");
        }
    }
}
