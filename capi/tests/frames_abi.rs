//! The C ABI of `fix dpdnl/frames` (`dpdnl_frames_*`): its words parsed by
//! `dpdnl::grammar::fix::frames` (the same verdict and message), the due steps, and a frame
//! written through it read back by `dpdnl::io::frames` with every number, the style's name and
//! its settings.

use std::ffi::{CStr, CString, c_char};
use std::ptr::null_mut;

use dpdnl::grammar::fix;
use dpdnl::io::frames::FrameReader;
use dpdnl_capi::*;

fn last_error() -> String {
    // SAFETY: a valid NUL-terminated string owned by this thread.
    unsafe { CStr::from_ptr(dpdnl_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn cwords(words: &[&str]) -> (Vec<CString>, Vec<*const c_char>) {
    let c: Vec<CString> = words.iter().map(|w| CString::new(*w).unwrap()).collect();
    let p = c.iter().map(|s| s.as_ptr()).collect();
    (c, p)
}

/// `fix ID GROUP dpdnl/frames WORDS` through the C ABI: the handle or the message.
fn frames(group: &str, words: &[&str], writer: i32) -> Result<*mut DpdnlFrames, String> {
    let g = CString::new(group).unwrap();
    let (_c, p) = cwords(words);
    let mut h = null_mut();
    // SAFETY: valid strings that outlive the call; `h` valid for writing.
    let st = unsafe { dpdnl_frames_new(g.as_ptr(), p.len() as i32, p.as_ptr(), writer, &mut h) };
    match st {
        DpdnlStatus::Ok => Ok(h),
        _ => {
            assert!(h.is_null(), "a failure leaves no handle");
            Err(last_error())
        }
    }
}

#[test]
fn words_as_the_grammar() {
    let cases: [(&str, &[&str]); 5] = [
        ("all", &["0", "f.bin"]),
        ("all", &["10"]),
        ("all", &["10", "f.bin", "extra"]),
        ("mobile", &["10", "f.bin"]),
        ("all", &["2147483648", "f.bin"]),
    ];
    for (group, words) in cases {
        let want = fix::frames(group, words).unwrap_err();
        assert_eq!(
            frames(group, words, 0).unwrap_err(),
            want,
            "{group} {words:?}"
        );
    }
}

#[test]
fn a_frame_written_through_the_abi_reads_back() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("frames_abi");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("frames.bin");
    let h = frames("all", &["5", path.to_str().unwrap()], 1).unwrap();
    let due = |step: i64| {
        let mut d = -1;
        // SAFETY: a live handle; `d` valid for writing.
        assert_eq!(
            unsafe { dpdnl_frames_due(h, step, &mut d) },
            DpdnlStatus::Ok
        );
        d
    };
    assert_eq!((due(0), due(5), due(7), due(-5)), (1, 1, 0, 0));

    let (_c, p) = cwords(&["1.0", "1.0", "34387"]);
    let name = c"dpd/nonlinear";
    let mut pair = null_mut();
    // SAFETY: valid strings; `pair` valid for writing.
    let st = unsafe { dpdnl_pair_new(name.as_ptr(), 3, p.as_ptr(), 2, &mut pair) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    let (_c, p) = cwords(&["*", "*", "25.0", "4.5", "0.0"]);
    // SAFETY: a live handle and valid strings.
    let st = unsafe { dpdnl_pair_coeff(pair, 2, 5, p.as_ptr()) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());

    let head = DpdnlFrameHead {
        step: 10,
        dimension: 3,
        ntypes: 2,
        periodic: [1, 1, 0],
        euler: 1,
        boxlo: [0.0, 0.0, -1.0],
        boxhi: [4.0, 5.0, 6.0],
        dt: 0.01,
        beginstep: 0,
        endstep: 100,
        special_lj: [1.0, 0.0, 0.5, 1.0],
        ..Default::default()
    };
    let tag = [7, 3];
    let typ = [2, 1];
    let mass = [2.0, 1.0];
    let x = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0];
    let v = [0.1, -0.2, 0.3, -0.4, 0.5, -0.6];
    let f = [1.0, 2.0, 3.0, -1.0, -2.0, -3.0];
    // SAFETY: live handles; the arrays hold 2 (or 6) values.
    let st = unsafe {
        dpdnl_frames_write(
            h,
            pair,
            &head,
            2,
            tag.as_ptr(),
            typ.as_ptr(),
            mass.as_ptr(),
            x.as_ptr(),
            v.as_ptr(),
            f.as_ptr(),
        )
    };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    // SAFETY: live handles, not used afterwards.
    unsafe {
        dpdnl_frames_free(h);
        dpdnl_pair_free(pair);
    }

    let mut r = FrameReader::open(&path).unwrap();
    let fr = r.next_frame().unwrap().unwrap();
    assert!(r.next_frame().unwrap().is_none());
    let hd = &fr.head;
    assert_eq!((hd.step, hd.dimension, hd.ntypes, hd.dt), (10, 3, 2, 0.01));
    assert_eq!(
        (hd.boxlo, hd.boxhi, hd.special_lj),
        (head.boxlo, head.boxhi, head.special_lj)
    );
    assert!(hd.periodic(0) && hd.periodic(1) && !hd.periodic(2));
    assert_eq!(
        hd.flags & dpdnl::io::frames::flags::EULER,
        dpdnl::io::frames::flags::EULER
    );
    assert_eq!((hd.beginstep, hd.endstep), (0, 100));
    assert_eq!(hd.style, "dpd/nonlinear");
    assert!(
        hd.settings.starts_with("pair_style dpd/nonlinear 1"),
        "{}",
        hd.settings
    );
    assert!(hd.settings.contains("pair_coeff"), "{}", hd.settings);
    assert_eq!(
        (fr.tag, fr.typ, fr.mass),
        (vec![7, 3], vec![2, 1], vec![2.0, 1.0])
    );
    assert_eq!(fr.x, vec![[0.5, 1.0, 1.5], [2.0, 2.5, 3.0]]);
    assert_eq!(fr.v, vec![[0.1, -0.2, 0.3], [-0.4, 0.5, -0.6]]);
    assert_eq!(fr.f, vec![[1.0, 2.0, 3.0], [-1.0, -2.0, -3.0]]);

    // A rank without the file (writer 0) has nothing to write to.
    let h = frames("all", &["5", "unused.bin"], 0).unwrap();
    // SAFETY: null arrays with n = 0 are allowed; `pair` null is reported.
    let st = unsafe {
        dpdnl_frames_write(
            h,
            null_mut(),
            &head,
            0,
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert_eq!(st, DpdnlStatus::NullPointer, "{}", last_error());
    // SAFETY: a live handle, not used afterwards.
    unsafe { dpdnl_frames_free(h) };
    assert!(!std::path::Path::new("unused.bin").exists());
}
