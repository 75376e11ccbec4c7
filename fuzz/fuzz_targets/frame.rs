//! Fuzzes the frame decoder. The input is tried three ways: as the bytes
//! between two delimiters (what the stream decoder passes on), as a raw
//! frame, and as header and body with a correct CRC appended, so that the
//! fuzzer also reaches the header and message parsers behind the CRC check
//! (random bytes almost never carry a matching CRC-32). A frame that
//! decodes must re-encode to one that decodes to the same value (the codec
//! is canonical); nothing may panic.
#![no_main]

use core_algo::protocol::frame::{CRC, CRC_LEN, Frame, FrameError, MAX_FRAME_LEN, MAX_RAW_LEN};
use core_algo::protocol::message::Message;
use libfuzzer_sys::fuzz_target;

fn check(r: Result<Frame, FrameError>) {
    if let Ok(f) = r {
        let mut wire = [0u8; MAX_FRAME_LEN];
        let n = f.encode(&mut wire).expect("a decoded frame re-encodes");
        let again = Frame::decode(&wire[1..n - 1]).expect("re-encoded frame decodes");
        assert_eq!(again, f);
    }
}

fuzz_target!(|data: &[u8]| {
    check(Frame::decode(data));
    check(Frame::decode_raw(data));
    if data.len() <= MAX_RAW_LEN - CRC_LEN {
        let mut raw = data.to_vec();
        raw.extend_from_slice(&CRC.checksum(data).to_le_bytes());
        check(Frame::decode_raw(&raw));
    }
    if let Ok(m) = Message::decode(data) {
        let mut buf = [0u8; 256];
        let enc = m.encode(&mut buf).expect("a decoded message re-encodes");
        assert_eq!(Message::decode(enc), Ok(m));
    }
});
