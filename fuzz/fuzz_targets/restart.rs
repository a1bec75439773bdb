//! The restart reader on arbitrary bytes: a restart or an error, never a panic; what it
//! accepts re-encodes to bytes that decode again to the same bytes (compared as bytes, so NaNs
//! compare equal). Each input is decoded twice: as it is, and with its last 8 bytes replaced by
//! the FNV-1a checksum of the rest, so mutated payloads get past the checksum and reach the
//! payload reader.
#![no_main]

use dpdnl::io::restart;
use libfuzzer_sys::fuzz_target;

fn check(bytes: &[u8]) {
    if let Ok(r) = restart::decode(bytes) {
        let once = restart::encode(&r);
        let again = restart::decode(&once).expect("a re-encoded restart decodes");
        assert!(
            restart::encode(&again) == once,
            "restart round trip changed the bytes"
        );
    }
}

fuzz_target!(|bytes: &[u8]| {
    check(bytes);
    if bytes.len() >= 8 {
        let (body, _) = bytes.split_at(bytes.len() - 8);
        let mut fixed = body.to_vec();
        fixed.extend_from_slice(&restart::fnv1a64(body).to_le_bytes());
        check(&fixed);
    }
});
