//! Fuzzes the field readers, the way a file named by the user or uploaded
//! to the web UI reaches them (`phone_sim::field::parse_bytes`): the first
//! byte picks the format (`.field`, `.sim`, `.sep`, `.map`, the last read
//! both ways), the rest is the file. Nothing may panic, and a field that
//! reads is a valid one (only `Field::new` builds one), so it must write
//! back: as a native `.field` it reads back equal, name, spacing and all,
//! and in the 2010 formats, where it can be written at all, with the same
//! nodes, and in `.sim` the same starts (`.sep` holds none).
#![no_main]

use libfuzzer_sys::fuzz_target;
use phone_sim::field::{Field, LoadOptions, MapReading, parse_bytes, to_text};

const NAMES: [&str; 5] = ["fuzz.field", "fuzz.sim", "fuzz.sep", "fuzz.map", "fuzz.map"];

fn reads_back(field: &Field, file: &str) {
    let Ok(text) = to_text(field, file) else {
        // `.sim` and `.sep` cannot hold every field (their lattice has
        // limits of its own); the writer says so instead of writing.
        assert!(!file.ends_with(".field"), "every field writes as .field");
        return;
    };
    let again = parse_bytes(text.as_bytes(), file, LoadOptions::default())
        .unwrap_or_else(|e| panic!("a field written as {file} reads back: {e}\n{text}"));
    assert_eq!(again.nodes(), field.nodes(), "{text}");
    if file.ends_with(".field") {
        assert_eq!(&again, field, "{text}");
    } else if file.ends_with(".sim") {
        assert_eq!(again.starts(), field.starts(), "{text}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, file)) = data.split_first() else {
        return;
    };
    let which = usize::from(pick) % NAMES.len();
    let map_reading = if which == 4 {
        MapReading::Corners
    } else {
        MapReading::Cells
    };
    let name = NAMES[which];
    if let Ok(field) = parse_bytes(file, name, LoadOptions { map_reading }) {
        for out in ["fuzz.field", "fuzz.sim", "fuzz.sep"] {
            reads_back(&field, out);
        }
    }
});
