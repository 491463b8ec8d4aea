//! The common driver of the JSON readers: the top level is parsed as it is read, and every
//! entry of its lists (a pose, an instance, a frame, an annotation, a person) is parsed on its
//! own (at most [`MAX_ENTRY_VALUES`](crate::MAX_ENTRY_VALUES) values), turned into its
//! records and handed to a callback at once. Memory is that of one entry, whatever the number of
//! entries: the same code reads text in memory ([`collect`]) and streams
//! ([`KeypointStream`](crate::KeypointStream)).

use std::fmt;
use std::io;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::ReadOptions;
use crate::error::{KeypointError, Location};
use crate::json::{self, Json, SkipVisitor, Skipped, wrong_type};
use crate::record::KeypointRecord;
use crate::stream::Item;

/// Why a reader stopped before the end of its input.
pub(crate) enum Stop {
    /// The input is invalid.
    Invalid(KeypointError),
    /// Reading failed (an I/O error of the reader, e.g. its size limit).
    Io(io::Error),
    /// The callback returned `false`: nobody wants more records.
    Closed,
}

/// Where records go, and why reading stopped.
pub(crate) struct Sink<'a> {
    /// The input's name.
    pub(crate) file: &'a str,
    /// The reader options.
    pub(crate) options: &'a ReadOptions,
    emit: &'a mut dyn FnMut(Item) -> bool,
    stop: Option<Stop>,
}

impl Sink<'_> {
    /// Gives a record, or the error of one pose ([`KeypointError::is_pose_error`]), to the
    /// callback; another error, or a callback that wants no more, records why reading stops
    /// and returns an error that ends parsing.
    pub(crate) fn send<E: de::Error>(&mut self, item: Item) -> Result<(), E> {
        match item {
            Err(e) if !e.is_pose_error() => Err(self.stop(Stop::Invalid(e))),
            item => {
                if (self.emit)(item) {
                    Ok(())
                } else {
                    Err(self.stop(Stop::Closed))
                }
            }
        }
    }

    /// Ends parsing with `error`.
    pub(crate) fn fail<E: de::Error>(&mut self, error: KeypointError) -> E {
        self.stop(Stop::Invalid(error))
    }

    fn stop<E: de::Error>(&mut self, stop: Stop) -> E {
        self.stop = Some(stop);
        E::custom("reading stopped")
    }
}

/// How a format reads its top-level value. A value of another type than the format takes is
/// parsed to its end (so that a syntax error in it is reported first) and then refused as
/// [`KeypointError::WrongType`] with [`TopLevel::EXPECTED`].
pub(crate) trait TopLevel {
    /// What the top level must be, e.g. `a list of MPII annotations`.
    const EXPECTED: &'static str;

    /// Reads a top-level array.
    fn list<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error>
    where
        Self: Sized,
    {
        let found = SkipVisitor.visit_seq(seq)?;
        Err(sink.fail(wrong_type(sink.file, "", Self::EXPECTED, &found)))
    }

    /// Reads a top-level object.
    fn object<'de, A: MapAccess<'de>>(self, map: A, sink: &mut Sink) -> Result<(), A::Error>
    where
        Self: Sized,
    {
        let found = SkipVisitor.visit_map(map)?;
        Err(sink.fail(wrong_type(sink.file, "", Self::EXPECTED, &found)))
    }
}

/// Reads the JSON document of `read` with `top` and gives each record, or a pose's error, to
/// `emit` (which returns `false` to stop). Errors come in input order, after the records
/// before them.
pub(crate) fn drive<'de, R: serde_json::de::Read<'de>>(
    read: R,
    file: &str,
    options: &ReadOptions,
    emit: &mut dyn FnMut(Item) -> bool,
    top: impl TopLevel,
) -> Result<(), Stop> {
    let mut sink = Sink {
        file,
        options,
        emit,
        stop: None,
    };
    let mut deserializer = serde_json::Deserializer::new(read);
    let parsed = deserializer
        .deserialize_any(Top(top, &mut sink))
        .and_then(|()| deserializer.end());
    match parsed {
        Ok(()) => Ok(()),
        Err(e) => Err(match sink.stop {
            Some(stop) => stop,
            None if e.is_io() => Stop::Io(e.into()),
            None => Stop::Invalid(json::syntax_error(&e, file)),
        }),
    }
}

/// The records and pose errors ([`KeypointError::is_pose_error`]) `read` gives (a reader such
/// as [`drive`] called with a callback), or the error that stopped it.
pub(crate) fn collect(
    file: &str,
    read: impl FnOnce(&mut dyn FnMut(Item) -> bool) -> Result<(), Stop>,
) -> Result<Vec<Item>, KeypointError> {
    let mut items = Vec::new();
    match read(&mut |item| {
        items.push(item);
        true
    }) {
        // `Closed` cannot happen: the callback above never stops.
        Ok(()) | Err(Stop::Closed) => Ok(items),
        Err(Stop::Invalid(e)) => Err(e),
        Err(Stop::Io(source)) => Err(KeypointError::Io {
            file: file.to_owned(),
            source,
        }),
    }
}

/// Parses the elements of the list `seq` one at a time, each as one entry, and gives each with
/// its index to `records`, whose records (or errors: [`Sink::send`]) go to the sink in order.
pub(crate) fn entries<'de, A, I>(
    mut seq: A,
    sink: &mut Sink,
    mut records: impl FnMut(Json, usize) -> Result<I, KeypointError>,
) -> Result<(), A::Error>
where
    A: SeqAccess<'de>,
    I: IntoIterator,
    I::Item: IntoItem,
{
    let mut index = 0;
    while let Some(entry) = seq.next_element::<Json>()? {
        match records(entry, index) {
            Ok(batch) => {
                for item in batch {
                    sink.send(item.into_item())?;
                }
            }
            Err(e) => sink.send(Err(e))?,
        }
        index += 1;
    }
    Ok(())
}

/// What an entry's reader gives per record: the record, or the record's own outcome (a pose
/// refused on its own, [`KeypointError::is_pose_error`]).
pub(crate) trait IntoItem {
    /// The record's item.
    fn into_item(self) -> Item;
}

impl IntoItem for KeypointRecord {
    fn into_item(self) -> Item {
        Ok(self)
    }
}

impl IntoItem for Item {
    fn into_item(self) -> Item {
        self
    }
}

/// Reads the elements of a list as they are parsed (see [`ListSeed`]).
pub(crate) trait ListReader {
    /// Reads the array `seq`.
    fn read<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error>;
}

/// The value of a key that should hold a list: an array is read by the [`ListReader`] as it is
/// parsed (its placeholder is an empty array), another value is skipped (its placeholder has
/// its type, for the caller's error).
pub(crate) struct ListSeed<'s, 'a, L>(pub(crate) L, pub(crate) &'s mut Sink<'a>);

impl<'de, L: ListReader> DeserializeSeed<'de> for ListSeed<'_, '_, L> {
    type Value = Json;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Json, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de, L: ListReader> Visitor<'de> for ListSeed<'_, '_, L> {
    type Value = Json;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a list")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Json, A::Error> {
        self.0.read(seq, self.1)?;
        Ok(Json::Array(Vec::new()))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Json, A::Error> {
        SkipVisitor.visit_map(map)
    }

    fn visit_unit<E: de::Error>(self) -> Result<Json, E> {
        SkipVisitor.visit_unit()
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Json, E> {
        SkipVisitor.visit_bool(v)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Json, E> {
        SkipVisitor.visit_i64(v)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Json, E> {
        SkipVisitor.visit_u64(v)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Json, E> {
        SkipVisitor.visit_f64(v)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Json, E> {
        SkipVisitor.visit_str(v)
    }
}

/// Reads the top-level object `map` whose list under `key` (`what` names its type for the
/// error) is read by `list` as it is parsed; other keys are skipped. The key given twice, missing
/// or not holding an array is an error.
pub(crate) fn object_with_list<'de, A: MapAccess<'de>>(
    mut map: A,
    sink: &mut Sink,
    key: &'static str,
    what: &'static str,
    list: impl ListReader,
) -> Result<(), A::Error> {
    let mut list = Some(list);
    let mut found = None;
    while let Some(name) = map.next_key::<String>()? {
        if name != key {
            map.next_value::<Skipped>()?;
        } else if let Some(list) = list.take() {
            found = Some(map.next_value_seed(ListSeed(list, &mut *sink))?);
        } else {
            let (file, at) = (sink.file.to_owned(), Location::Path(name));
            return Err(sink.fail(KeypointError::DuplicateKey { file, at }));
        }
    }
    let error = match found {
        Some(Json::Array(_)) => return Ok(()),
        Some(other) => wrong_type(sink.file, key, what, &other),
        None => KeypointError::MissingKey {
            file: sink.file.to_owned(),
            at: Location::Path(String::new()),
            key,
            read_as_coco: false,
        },
    };
    Err(sink.fail(error))
}

/// The top-level visitor: arrays and objects to the format, other values refused.
struct Top<'s, 'a, T>(T, &'s mut Sink<'a>);

macro_rules! refuse_scalar {
    ($($method:ident($($arg:ty)?) => $found:expr;)*) => {$(
        fn $method<E: de::Error>(self $(, _: $arg)?) -> Result<(), E> {
            let sink = self.1;
            Err(sink.fail(wrong_type(sink.file, "", T::EXPECTED, &$found)))
        }
    )*};
}

impl<'de, T: TopLevel> Visitor<'de> for Top<'_, '_, T> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(T::EXPECTED)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<(), A::Error> {
        self.0.list(seq, self.1)
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<(), A::Error> {
        self.0.object(map, self.1)
    }

    refuse_scalar! {
        visit_unit() => Json::Null;
        visit_bool(bool) => Json::Bool(false);
        visit_i64(i64) => Json::Number(0.into());
        visit_u64(u64) => Json::Number(0.into());
        visit_f64(f64) => Json::Number(0.into());
        visit_str(&str) => Json::String(String::new());
    }
}
