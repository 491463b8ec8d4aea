//! Streamed text input: a producer thread parses the input and sends its records, in small
//! batches, through a bounded channel that [`KeypointStream`](crate::KeypointStream) drains,
//! so that memory is bounded by the channel, not by the number of poses.

use std::cell::RefCell;
use std::io::{self, Read};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use crate::error::KeypointError;
use crate::record::KeypointRecord;

/// One item of a keypoint stream.
pub(crate) type Item = Result<KeypointRecord, KeypointError>;

/// Records per message of the channel.
const BATCH: usize = 256;
/// Messages the channel holds before the producer waits: with [`BATCH`], at most about
/// 1,500 records are in flight.
const CAPACITY: usize = 4;

/// The consumer end: records in input order, then `None` after the last record or the first
/// error.
pub(crate) struct Received {
    receiver: Receiver<Vec<Item>>,
    batch: std::vec::IntoIter<Item>,
    producer: Option<JoinHandle<()>>,
}

impl Received {
    /// The next record.
    pub(crate) fn next_item(&mut self) -> Option<Item> {
        loop {
            if let Some(item) = self.batch.next() {
                return Some(item);
            }
            match self.receiver.recv() {
                Ok(batch) => self.batch = batch.into_iter(),
                Err(_) => {
                    // The producer has finished: a panic there is passed on, not hidden as
                    // a short input.
                    if let Some(Err(panic)) = self.producer.take().map(JoinHandle::join) {
                        std::panic::resume_unwind(panic);
                    }
                    return None;
                }
            }
        }
    }
}

/// The producer end, given to the parser: it batches records and sends them.
pub(crate) struct Sender {
    sender: SyncSender<Vec<Item>>,
    batch: RefCell<Vec<Item>>,
}

impl Sender {
    /// Queues `item`; returns `false` when the consumer has gone (stop producing).
    pub(crate) fn send(&self, item: Item) -> bool {
        let full = {
            let mut batch = self.batch.borrow_mut();
            batch.push(item);
            batch.len() >= BATCH
        };
        !full || self.flush()
    }

    /// Sends the queued records; `false` when the consumer has gone.
    fn flush(&self) -> bool {
        let batch = std::mem::replace(&mut *self.batch.borrow_mut(), Vec::with_capacity(BATCH));
        batch.is_empty() || self.sender.send(batch).is_ok()
    }

    /// `inner`, at most `limit` bytes of it ([`Capped`]), buffered (64 KiB) through a reader
    /// that sends the records queued here before a read that may wait ([`Flushing`]): a live
    /// input (a detector writing to standard input) has each record answered as it comes,
    /// where a batch had waited for 256 records.
    pub(crate) fn buffered<R: Read>(
        &self,
        inner: R,
        limit: u64,
    ) -> io::BufReader<Flushing<'_, Capped<R>>> {
        let flushing = Flushing {
            inner: Capped::new(inner, limit),
            sender: self,
            short: false,
        };
        io::BufReader::with_capacity(1 << 16, flushing)
    }
}

/// A reader that sends its [`Sender`]'s queued records before a read that may wait
/// ([`Sender::buffered`]): one after a read that got less than it asked for (a pipe or
/// standard input that had no more yet; a file's reads are full, and its records keep going
/// in whole batches).
pub(crate) struct Flushing<'a, R> {
    inner: R,
    sender: &'a Sender,
    /// The last read got less than it asked for.
    short: bool,
}

impl<R: Read> Read for Flushing<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.short {
            // (A consumer that has gone is found by the next send.)
            self.sender.flush();
        }
        let n = self.inner.read(buf)?;
        self.short = n < buf.len();
        Ok(n)
    }
}

/// Starts `produce` on its own thread (named after the input) and returns the consumer end.
///
/// The first message is awaited here, so that an error found before the first record (an
/// invalid document, an unreadable start) is returned as this function's error, as for inputs
/// that are read whole; a first pose the reader refused
/// ([`KeypointError::refused_pose`]) stays the stream's first item.
pub(crate) fn spawn(
    file: &str,
    produce: impl FnOnce(&Sender) + Send + 'static,
) -> Result<Received, KeypointError> {
    let (sender, receiver) = sync_channel(CAPACITY);
    let producer = std::thread::Builder::new()
        .name(format!(
            "camloc-keypoints reader of {}",
            crate::error::clip(file)
        ))
        .spawn(move || {
            let sender = Sender {
                sender,
                batch: RefCell::new(Vec::with_capacity(BATCH)),
            };
            produce(&sender);
            sender.flush();
        })
        .map_err(|source| KeypointError::Io {
            file: file.to_owned(),
            source,
        })?;
    // Empty when the producer ended without a message (a panic: passed on by `next_item`).
    let first = receiver.recv().unwrap_or_default();
    let mut batch = first.into_iter();
    // (A pose the reader refused is that pose's error, the next poses are still read.)
    if let Some(Err(e)) = batch.as_slice().first()
        && e.refused_pose().is_none()
        && let Some(Err(e)) = batch.next()
    {
        return Err(e);
    }
    Ok(Received {
        receiver,
        batch,
        producer: Some(producer),
    })
}

/// The error a [`Capped`] reader returns past its limit.
#[derive(Debug, thiserror::Error)]
#[error("more than {limit} bytes")]
pub(crate) struct OverLimit {
    /// Bytes read so far (more than the limit).
    pub(crate) read: u64,
    /// The limit in bytes.
    pub(crate) limit: u64,
}

/// A reader that fails with [`OverLimit`] once more than `limit` bytes have been read.
pub(crate) struct Capped<R> {
    inner: R,
    read: u64,
    limit: u64,
}

impl<R> Capped<R> {
    /// `inner`, limited to `limit` bytes.
    pub(crate) fn new(inner: R, limit: u64) -> Self {
        Capped {
            inner,
            read: 0,
            limit,
        }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read = self.read.saturating_add(n as u64);
        if self.read > self.limit {
            return Err(io::Error::other(OverLimit {
                read: self.read,
                limit: self.limit,
            }));
        }
        Ok(n)
    }
}
