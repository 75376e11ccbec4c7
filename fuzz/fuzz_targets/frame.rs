//! Fuzzes the frame decoder: any bytes between two delimiters, and any raw
//! frame. A frame that decodes must re-encode to a frame that decodes to the
//! same value (the codec is canonical), and nothing may panic.
#![no_main]

use core_algo::protocol::frame::{Frame, MAX_FRAME_LEN};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = Frame::decode_raw(data);
    if let Ok(f) = Frame::decode(data) {
        let mut wire = [0u8; MAX_FRAME_LEN];
        let n = f.encode(&mut wire).expect("a decoded frame re-encodes");
        let again = Frame::decode(&wire[1..n - 1]).expect("re-encoded frame decodes");
        assert_eq!(again, f);
    }
});
