//! Cutting a byte stream into frames.
//!
//! A UART or RFCOMM socket delivers bytes in arbitrary chunks, with bytes
//! lost, doubled or garbled on the way. [`StreamDecoder`] takes them in any
//! chunking, splits at every 0x00 and decodes what lies between. A chunk
//! that is not a valid frame is dropped and counted; the next delimiter
//! starts afresh, so after garbage the decoder is back in step at the next
//! frame (at most the frame the garbage ran into is lost). Its only memory is
//! one encoded frame ([`MAX_ENCODED_LEN`] bytes) and the counters.

use super::frame::{Frame, FrameError, MAX_ENCODED_LEN};

/// Counters of a stream decoder, for diagnostics and tests.
///
/// They saturate instead of wrapping so that a long run never reports a
/// small count.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct Stats {
    /// Frames decoded.
    pub frames: u32,
    /// Runs of more than [`MAX_ENCODED_LEN`] bytes without a delimiter.
    pub too_long: u32,
    /// Chunks that were not valid COBS.
    pub cobs: u32,
    /// Chunks too short for header and CRC.
    pub too_short: u32,
    /// CRC mismatches.
    pub crc: u32,
    /// Frames of another protocol version.
    pub version: u32,
    /// Unknown frame kinds.
    pub kind: u32,
    /// Bodies that were not valid messages.
    pub message: u32,
}

impl Stats {
    /// All rejected chunks together.
    pub fn errors(&self) -> u32 {
        [
            self.too_long,
            self.cobs,
            self.too_short,
            self.crc,
            self.version,
            self.kind,
            self.message,
        ]
        .iter()
        .fold(0u32, |a, b| a.saturating_add(*b))
    }

    fn count(&mut self, e: FrameError) {
        let c = match e {
            FrameError::TooLong => &mut self.too_long,
            FrameError::Cobs | FrameError::BufferFull => &mut self.cobs,
            FrameError::TooShort => &mut self.too_short,
            FrameError::Crc => &mut self.crc,
            FrameError::Version => &mut self.version,
            FrameError::Kind => &mut self.kind,
            FrameError::Message => &mut self.message,
        };
        *c = c.saturating_add(1);
    }
}

/// Splits a byte stream at 0x00 delimiters and decodes the frames.
#[derive(Clone, Debug)]
pub struct StreamDecoder {
    buf: [u8; MAX_ENCODED_LEN],
    len: usize,
    /// Set when the current chunk outgrew `buf`; bytes are then dropped up
    /// to the next delimiter.
    overflow: bool,
    stats: Stats,
}

impl Default for StreamDecoder {
    fn default() -> Self {
        StreamDecoder::new()
    }
}

impl StreamDecoder {
    /// An empty decoder.
    pub const fn new() -> Self {
        StreamDecoder {
            buf: [0; MAX_ENCODED_LEN],
            len: 0,
            overflow: false,
            stats: Stats {
                frames: 0,
                too_long: 0,
                cobs: 0,
                too_short: 0,
                crc: 0,
                version: 0,
                kind: 0,
                message: 0,
            },
        }
    }

    /// The counters so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Takes one byte; returns a frame or an error when the byte ends a
    /// chunk. Empty chunks (two delimiters in a row) are not reported.
    pub fn push_byte(&mut self, byte: u8) -> Option<Result<Frame, FrameError>> {
        if byte != 0 {
            if self.overflow {
                return None;
            }
            match self.buf.get_mut(self.len) {
                Some(slot) => {
                    *slot = byte;
                    self.len += 1;
                }
                None => self.overflow = true,
            }
            return None;
        }
        let len = core::mem::take(&mut self.len);
        let result = if core::mem::take(&mut self.overflow) {
            Err(FrameError::TooLong)
        } else if len == 0 {
            return None;
        } else {
            match self.buf.get_mut(..len) {
                Some(chunk) => Frame::decode_in_place(chunk),
                None => Err(FrameError::TooLong),
            }
        };
        match &result {
            Ok(_) => self.stats.frames = self.stats.frames.saturating_add(1),
            Err(e) => self.stats.count(*e),
        }
        Some(result)
    }

    /// Takes a chunk of bytes and calls `on_frame` for every frame or error
    /// completed by it, in stream order.
    pub fn push(&mut self, mut bytes: &[u8], mut on_frame: impl FnMut(Result<Frame, FrameError>)) {
        while let Some(r) = self.next_frame(&mut bytes) {
            on_frame(r);
        }
    }

    /// Takes bytes from the front of `bytes` up to the first frame or error
    /// they complete, and returns it; `None` once they are all taken
    /// without completing one. The same as [`StreamDecoder::push_byte`] for
    /// each byte, a run between delimiters copied at once: byte by byte,
    /// the copy was a fifth of a link's receiving time.
    pub fn next_frame(&mut self, bytes: &mut &[u8]) -> Option<Result<Frame, FrameError>> {
        loop {
            let end = bytes.iter().position(|&b| b == 0);
            let (run, rest) = bytes.split_at(end.unwrap_or(bytes.len()));
            if !self.overflow {
                let stored = self
                    .buf
                    .get_mut(self.len..)
                    .and_then(|free| free.get_mut(..run.len()));
                match stored {
                    Some(slot) => {
                        slot.copy_from_slice(run);
                        self.len += run.len();
                    }
                    None => self.overflow = true,
                }
            }
            let Some((_, after)) = rest.split_first() else {
                *bytes = rest;
                return None;
            };
            *bytes = after;
            if let Some(r) = self.push_byte(0) {
                return Some(r);
            }
        }
    }

    /// Drops a partly received chunk, e.g. after the link was reopened.
    pub fn reset(&mut self) {
        self.len = 0;
        self.overflow = false;
    }
}
