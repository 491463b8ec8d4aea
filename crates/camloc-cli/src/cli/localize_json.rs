//! The JSON object of one pose of `localize --json` / `--jsonl`, written straight into a string
//! with the float and integer formatters serde_json uses (zmij, itoa): the same bytes as
//! serde_json would write for these fields, without its per-value calls (this is most of the
//! time of a large `--jsonl` run).

use camloc::Localization;
use camloc::keypoints::KeypointRecord;

/// Room for a typical object at once (no regrowth while writing it).
const CAPACITY: usize = 1024;

/// The object of `loc`, the localization of `record`, on one line without its newline. Keys in
/// this order: `id`, `source`, `frame` and `person` (when the record has them), `label`,
/// `level`, `side`, `probability`, `folded_label`, `azimuth_deg`, `elevation_deg` and
/// `uncertainty_deg` (when the model has direction heads), `rotation` (rows), `probabilities`
/// (camera label text from `labels`, in camera order, to probability), `missing`, `derived`
/// (landmark names).
pub fn localization_json(labels: &[String], record: &KeypointRecord, loc: &Localization) -> String {
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
    json.float(loc.probability);
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
    json.raw(",\"rotation\":[");
    for row in 0..3 {
        json.raw(if row == 0 { "[" } else { ",[" });
        for column in 0..3 {
            if column > 0 {
                json.raw(",");
            }
            json.float(loc.rotation[(row, column)]);
        }
        json.raw("]");
    }
    json.raw("],\"probabilities\":{");
    for (k, (label, p)) in labels.iter().zip(&loc.probabilities).enumerate() {
        if k > 0 {
            json.raw(",");
        }
        json.string(label);
        json.raw(":");
        json.float(*p);
    }
    json.raw("},\"missing\":");
    json.strings(loc.missing.iter().map(|l| l.name()));
    json.raw(",\"derived\":");
    json.strings(record.derived.iter().map(|l| l.name()));
    json.raw("}");
    json.0
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
        if value.is_finite() {
            self.0.push_str(zmij::Buffer::new().format_finite(value));
        } else {
            self.0.push_str("null");
        }
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
