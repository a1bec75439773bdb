//! The argument grammar of the project's styles on arbitrary word lists, directly and through
//! the C ABI entry points the LAMMPS styles call (`dpdnl_pair_new`/`_coeff`/`_restart`,
//! `dpdnl_parse_fix_*`).
//!
//! Input: a selector byte, then text. The first line is the style's words (`pair_style …` or
//! `fix …` after the style name), every further line one `pair_coeff` line (types first),
//! words split on whitespace. The selector picks the family (bits 0–1) and the number of atom
//! types 1..=8 (bits 2–4). Properties: no panic (a panic inside the C ABI's catch_unwind guard
//! aborts too: libfuzzer-sys's hook runs first); a style the grammar accepts gives itself back
//! through `to_words`; the C ABI agrees with the grammar on accept/refuse.
#![no_main]

use std::ffi::{CString, c_char};

use dpdnl::forces::{dpd::grammar as pair, sdpd::grammar as sdpd};
use dpdnl::grammar::fix;
use dpdnl_capi as capi;
use libfuzzer_sys::fuzz_target;

/// The words as C strings (a word with a NUL byte cannot reach the C ABI: replaced).
fn c_words(words: &[&str]) -> Vec<CString> {
    words
        .iter()
        .map(|w| CString::new(w.replace('\0', "?")).expect("no NUL left"))
        .collect()
}

fn ptrs(c: &[CString]) -> Vec<*const c_char> {
    c.iter().map(|s| s.as_ptr()).collect()
}

fn ok(s: capi::DpdnlStatus) -> bool {
    matches!(s, capi::DpdnlStatus::Ok)
}

/// The C ABI's one pair handle (`dpdnl_pair_*`) on the same words: it agrees with the grammar
/// on accepting the style line, takes every coefficient line without a panic, and its restart
/// text reads back.
fn handle(name: &str, style_words: &[&str], coeff_lines: &[Vec<&str>], ntypes: usize, accepted: bool) {
    let c_name = CString::new(name).expect("no NUL");
    let c = c_words(style_words);
    let p = ptrs(&c);
    let mut h: *mut capi::DpdnlPair = std::ptr::null_mut();
    // SAFETY: `p` holds p.len() NUL-terminated strings that outlive the call; `h` is valid.
    let st = unsafe {
        capi::dpdnl_pair_new(c_name.as_ptr(), p.len() as i32, p.as_ptr(), ntypes as i32, &mut h)
    };
    if !style_words.iter().any(|w| w.contains('\0')) {
        assert_eq!(ok(st), accepted, "C ABI and grammar disagree on pair_style {name}");
    }
    if !ok(st) {
        return;
    }
    for line in coeff_lines {
        let c = c_words(line);
        let p = ptrs(&c);
        // SAFETY: `h` is a live handle; `p` as above.
        let _ = unsafe { capi::dpdnl_pair_coeff(h, ntypes as i32, p.len() as i32, p.as_ptr()) };
    }
    let (mut data, mut len) = (std::ptr::null(), 0i64);
    // SAFETY: `h` is a live handle; the out pointers are valid.
    let st = unsafe { capi::dpdnl_pair_restart(h, 0, &mut data, &mut len) };
    assert!(ok(st), "restart text of a live handle");
    let mut back: *mut capi::DpdnlPair = std::ptr::null_mut();
    // SAFETY: `data` holds `len` bytes until the next call on `h`.
    let st = unsafe { capi::dpdnl_pair_from_restart(data, len, ntypes as i32, &mut back) };
    assert!(ok(st), "the restart text reads back");
    // SAFETY: handles from dpdnl_pair_new / _from_restart, each freed once.
    unsafe {
        capi::dpdnl_pair_free(back);
        capi::dpdnl_pair_free(h);
    }
}

fn dpd(style_words: &[&str], coeff_lines: &[Vec<&str>], ntypes: usize) {
    let parsed = pair::pair_style(style_words);
    if let Ok(s) = &parsed {
        assert_eq!(
            pair::pair_style(&s.to_words()).as_ref(),
            Ok(s),
            "to_words round trip"
        );
        for line in coeff_lines {
            let _ = pair::pair_coeff(line, ntypes, s.friction, s.rc);
        }
    }
    handle("dpd/nonlinear", style_words, coeff_lines, ntypes, parsed.is_ok());
}

fn sdpd(style_words: &[&str], coeff_lines: &[Vec<&str>], ntypes: usize) {
    let parsed = sdpd::pair_style(style_words);
    if let Ok(s) = &parsed {
        assert_eq!(
            sdpd::pair_style(&s.to_words()).as_ref(),
            Ok(s),
            "to_words round trip"
        );
        for line in coeff_lines {
            let _ = sdpd::pair_coeff(line, ntypes, s);
        }
    }
    handle("sdpd", style_words, coeff_lines, ntypes, parsed.is_ok());
}

fn fixes(style_words: &[&str], sel: u8) {
    let (style, args) = match style_words.split_first() {
        Some((s, a)) => (*s, a),
        None => ("nve", &[][..]),
    };
    let _ = fix::integrator(style, args);
    let dim = if sel & 0x20 != 0 { 2 } else { 3 };
    let parsed = fix::pex_push(args, dim);
    if let Ok(p) = parsed {
        for lx in [0.0, 1e-300, 1.0, 10.0, 1e300, f64::INFINITY, f64::NAN] {
            let _ = fix::pex_box_check(p.width, lx, sel & 0x40 != 0, sel & 0x80 == 0);
        }
    }
    let c_style = CString::new(style.replace('\0', "?")).expect("no NUL left");
    let c = c_words(args);
    let p = ptrs(&c);
    // SAFETY: NUL-terminated strings that outlive the calls; `out` is valid.
    let _ =
        unsafe { capi::dpdnl_parse_fix_integrator(c_style.as_ptr(), p.len() as i32, p.as_ptr()) };
    let mut out = capi::DpdnlPexArgs {
        dp: 0.0,
        width: 0.0,
        every: 0,
    };
    // SAFETY: as above.
    let st =
        unsafe { capi::dpdnl_parse_fix_pex_push(dim as i32, p.len() as i32, p.as_ptr(), &mut out) };
    if ok(st) {
        // SAFETY: `out` is valid for reading.
        let _ = unsafe { capi::dpdnl_pex_box_check(&out, 10.0, 0, 1) };
    }
}

fuzz_target!(|bytes: &[u8]| {
    let Some((&sel, rest)) = bytes.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let mut lines = text.lines();
    let style_words: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
    let coeff_lines: Vec<Vec<&str>> = lines
        .take(64)
        .map(|l| l.split_whitespace().collect())
        .collect();
    let ntypes = usize::from((sel >> 2) & 7) + 1;
    match sel & 3 {
        0 => dpd(&style_words, &coeff_lines, ntypes),
        1 => sdpd(&style_words, &coeff_lines, ntypes),
        _ => fixes(&style_words, sel),
    }
});
