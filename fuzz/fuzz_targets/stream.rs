//! Fuzzes the stream decoder with arbitrary bytes in arbitrary chunks: the
//! first byte picks the chunk size. The counters must add up to the
//! results reported, and nothing may panic.
#![no_main]

use core_algo::protocol::StreamDecoder;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&chunk, bytes)) = data.split_first() else {
        return;
    };
    let mut d = StreamDecoder::new();
    let (mut ok, mut err) = (0u32, 0u32);
    for c in bytes.chunks(usize::from(chunk).max(1)) {
        d.push(c, |r| match r {
            Ok(_) => ok += 1,
            Err(_) => err += 1,
        });
    }
    let s = d.stats();
    assert_eq!(s.frames, ok);
    assert_eq!(s.errors(), err);
});
