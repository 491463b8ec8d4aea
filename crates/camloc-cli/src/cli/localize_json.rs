//! The JSON objects of the poses of `localize --json` / `--jsonl`, written straight into a string
//! with the float and integer formatters serde_json uses (zmij, itoa): the same bytes as
//! serde_json would write for these fields, without its per-value calls (this is most of the
//! time of a large `--jsonl` run).

use std::ops::Index;

use camloc::keypoints::KeypointRecord;
use camloc::{CameraSet, Localization};

/// Room for a typical object at once (no regrowth while writing it).
const CAPACITY: usize = 1024;

/// The objects of one model's localizations. What depends only on the camera is formatted
/// once, here: the probability keys, and each camera's rotation (a localization's rotation is
/// its camera's, checked bit for bit before the text is reused).
pub struct LocalizationJson {
    /// `"01":`, `"02":`, ...: the camera labels' texts in camera order, quoted, with the colon.
    keys: Vec<String>,
    /// Each camera's rotation, row by row (the bits of its nine entries), and its JSON text.
    rotations: Vec<([u64; 9], String)>,
}

impl LocalizationJson {
    /// The writer of the localizations by a model of `cameras`.
    pub fn new(cameras: &CameraSet) -> LocalizationJson {
        let viewpoints = cameras.viewpoints();
        let keys = viewpoints
            .iter()
            .map(|v| {
                let mut key = Json(String::new());
                key.string(&v.label_text());
                key.raw(":");
                key.0
            })
            .collect();
        let rotations = viewpoints
            .iter()
            .map(|v| {
                let entries = entries(&v.rotation);
                let mut text = Json(String::new());
                text.rotation(&entries);
                (entries.map(f64::to_bits), text.0)
            })
            .collect();
        LocalizationJson { keys, rotations }
    }

    /// The object of `loc`, the localization of `record`, on one line without its newline.
    /// Keys in this order: `id`, `source`, `frame` and `person` (when the record has them),
    /// `label`, `level`, `side`, `probability`, `folded_label`, `azimuth_deg`, `elevation_deg`
    /// and `uncertainty_deg` (when the model has direction heads), `rotation` (rows),
    /// `probabilities` (camera label text, in camera order, to probability), `missing`,
    /// `derived` (landmark names).
    pub fn object(&self, record: &KeypointRecord, loc: &Localization) -> String {
        let mut json = Json(String::with_capacity(CAPACITY));
        json.raw("{\"id\":");
        json.string(&record.id);
        json.raw(",\"source\":");
        json.string(&record.source);
        if let Some(frame) = record.frame {
            json.raw(",\"frame\":");
            json.integer(frame);
        }
        if let Some(person) = record.person {
            json.raw(",\"person\":");
            json.integer(person);
        }
        json.raw(",\"label\":");
        json.integer(loc.label.get().into());
        json.raw(",\"level\":");
        json.string(loc.level.name());
        json.raw(",\"side\":");
        json.string(loc.side.name());
        json.raw(",\"probability\":");
        // The most probable camera's entry of `probabilities` is the same number: one text.
        let mut probability = zmij::Buffer::new();
        let probability = Json::float_text(&mut probability, loc.probability);
        json.raw(probability);
        json.raw(",\"folded_label\":");
        json.integer(loc.folded_label.get().into());
        let direction = [
            (",\"azimuth_deg\":", loc.azimuth_deg),
            (",\"elevation_deg\":", loc.elevation_deg),
            (",\"uncertainty_deg\":", loc.uncertainty_deg),
        ];
        for (key, value) in direction {
            if let Some(value) = value {
                json.raw(key);
                json.float(value);
            }
        }
        json.raw(",\"rotation\":");
        let rotation = entries(&loc.rotation);
        let bits = rotation.map(f64::to_bits);
        match self.rotations.iter().find(|(camera, _)| *camera == bits) {
            Some((_, text)) => json.raw(text),
            None => json.rotation(&rotation),
        }
        json.raw(",\"probabilities\":{");
        for (k, (key, p)) in self.keys.iter().zip(&loc.probabilities).enumerate() {
            if k > 0 {
                json.raw(",");
            }
            json.raw(key);
            if p.to_bits() == loc.probability.to_bits() {
                json.raw(probability);
            } else {
                json.float(*p);
            }
        }
        json.raw("},\"missing\":");
        json.strings(loc.missing.iter().map(|l| l.name()));
        json.raw(",\"derived\":");
        json.strings(record.derived.iter().map(|l| l.name()));
        json.raw("}");
        json.0
    }
}

/// The nine entries of a 3 x 3 matrix, row by row.
fn entries(matrix: &impl Index<(usize, usize), Output = f64>) -> [f64; 9] {
    std::array::from_fn(|k| matrix[(k / 3, k % 3)])
}

/// JSON text being written, value by value, as serde_json's compact formatter writes it.
struct Json(String);

impl Json {
    /// Appends JSON punctuation or keys as they are.
    fn raw(&mut self, text: &str) {
        self.0.push_str(text);
    }

    fn integer(&mut self, value: u64) {
        self.0.push_str(itoa::Buffer::new().format(value));
    }

    /// The shortest text that reads back as `value`; `null` for NaN and infinities.
    fn float(&mut self, value: f64) {
        self.0
            .push_str(Json::float_text(&mut zmij::Buffer::new(), value));
    }

    /// [`Json::float`]'s text of `value`, in `buffer`.
    fn float_text(buffer: &mut zmij::Buffer, value: f64) -> &str {
        if value.is_finite() {
            buffer.format_finite(value)
        } else {
            "null"
        }
    }

    /// A 3 x 3 matrix from its entries row by row, as rows: `[[a,b,c],[d,e,f],[g,h,i]]`.
    fn rotation(&mut self, entries: &[f64; 9]) {
        for (k, value) in entries.iter().enumerate() {
            self.raw(match k {
                0 => "[[",
                3 | 6 => "],[",
                _ => ",",
            });
            self.float(*value);
        }
        self.raw("]]");
    }

    /// A quoted string: `"` and `\` escaped, control characters as `\b`, `\t`, `\n`, `\f`,
    /// `\r` or `\u00xx`.
    fn string(&mut self, text: &str) {
        self.0.push('"');
        let mut rest = text;
        while let Some(at) = rest
            .bytes()
            .position(|b| b < 0x20 || b == b'"' || b == b'\\')
        {
            self.0.push_str(&rest[..at]);
            let byte = rest.as_bytes()[at];
            match byte {
                b'"' => self.0.push_str("\\\""),
                b'\\' => self.0.push_str("\\\\"),
                0x08 => self.0.push_str("\\b"),
                b'\t' => self.0.push_str("\\t"),
                b'\n' => self.0.push_str("\\n"),
                0x0c => self.0.push_str("\\f"),
                b'\r' => self.0.push_str("\\r"),
                _ => {
                    const HEX: &[u8; 16] = b"0123456789abcdef";
                    self.0.push_str("\\u00");
                    self.0.push(char::from(HEX[usize::from(byte >> 4)]));
                    self.0.push(char::from(HEX[usize::from(byte & 0xf)]));
                }
            }
            rest = &rest[at + 1..];
        }
        self.0.push_str(rest);
        self.0.push('"');
    }

    /// An array of strings.
    fn strings<'a>(&mut self, items: impl Iterator<Item = &'a str>) {
        self.raw("[");
        for (k, item) in items.enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.string(item);
        }
        self.raw("]");
    }
}

#[cfg(test)]
mod tests;
