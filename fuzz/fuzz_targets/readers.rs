//! The text readers on arbitrary input: data files, LAMMPS/dpdnl logs, text dumps. The first
//! byte chooses the reader (so one corpus holds all three kinds); the property is that each
//! returns a value or an error, never a panic.
#![no_main]

use dpdnl::io::{data, dump_read, lammps_log};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Some((&sel, rest)) = bytes.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    match sel % 3 {
        0 => {
            if let Ok(d) = data::parse_data(&text, "fuzz.data") {
                // What the reader accepted, written and read again.
                let _ = data::parse_data(&data::format_data(&d, "fuzz"), "again.data");
            }
        }
        1 => {
            let _ = lammps_log::parse_log(&text);
            let _ = lammps_log::neighbor_summary(&text);
            let _ = lammps_log::looks_like_dump(&text);
        }
        _ => {
            let _ = dump_read::parse_dump(&text);
        }
    }
});
