//! The C ABI of the fixes and the set-up checks against the Rust functions they wrap: the
//! fixes' argument parsing (`dpdnl::grammar::fix`), the Euler step and the PeX pick and kick
//! (`dpdnl::engine::fixes`), the blow-up check (`dpdnl::engine::check_atoms`) and the box check
//! (`dpdnl::init::check_box_images`): the same numbers bit for bit, the same verdict and
//! message, and null pointers as `DpdnlStatus::NullPointer`.

use std::ffi::{CStr, CString, c_char};
use std::ptr::{null, null_mut};

use dpdnl::engine::check_atoms;
use dpdnl::engine::fixes::{PexPick, PexSlabs, euler_update, pex_apply};
use dpdnl::grammar::fix;
use dpdnl::init::check_box_images;
use dpdnl::rng::keyed_uniform;
use dpdnl_capi::*;

fn last_error() -> String {
    // SAFETY: a valid NUL-terminated string owned by this thread.
    unsafe { CStr::from_ptr(dpdnl_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// A uniform in [lo, hi) keyed by (a, b): deterministic test data.
fn uniform(a: u32, b: u32, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * keyed_uniform(17, 2024, 3, a, b)
}

fn cwords(words: &[&str]) -> (Vec<CString>, Vec<*const c_char>) {
    let c: Vec<CString> = words.iter().map(|w| CString::new(*w).unwrap()).collect();
    let p = c.iter().map(|s| s.as_ptr()).collect();
    (c, p)
}

/// The C verdict as the Rust one: `Ok(())` or the message of an `InvalidArgument`.
fn verdict(st: DpdnlStatus) -> Result<(), String> {
    match st {
        DpdnlStatus::Ok => {
            assert_eq!(last_error(), "", "a success leaves no message");
            Ok(())
        }
        DpdnlStatus::InvalidArgument => Err(last_error()),
        other => panic!("unexpected status {other:?}: {}", last_error()),
    }
}

#[test]
fn version_is_the_crate_version() {
    // SAFETY: a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(dpdnl_version()) }.to_str().unwrap();
    assert_eq!(v, concat!("dpdnl-capi ", env!("CARGO_PKG_VERSION")));
    assert_eq!(dpdnl_version(), dpdnl_version(), "one static string");
}

#[test]
fn parse_fix_integrator_as_grammar() {
    let cases: [(&str, &[&str]); 6] = [
        ("nve", &[]),
        ("nve/euler", &[]),
        ("nve", &["extra"]),
        ("nve/euler", &["1", "2"]),
        (
            "nve/euler",
            &["a-word-longer-than-forty-characters-is-shortened-in-messages"],
        ),
        ("nve", &[""]),
    ];
    for (style, words) in cases {
        let s = CString::new(style).unwrap();
        let (_c, p) = cwords(words);
        // SAFETY: valid strings that outlive the call.
        let st = unsafe { dpdnl_parse_fix_integrator(s.as_ptr(), p.len() as i32, p.as_ptr()) };
        assert_eq!(
            verdict(st),
            fix::integrator(style, words),
            "{style} {words:?}"
        );
    }
    let nve = c"nve";
    // SAFETY: null pointers are reported, never read.
    unsafe {
        assert_eq!(
            dpdnl_parse_fix_integrator(null(), 0, null()),
            DpdnlStatus::NullPointer
        );
        assert_eq!(last_error(), "style is a null pointer");
        assert_eq!(
            dpdnl_parse_fix_integrator(nve.as_ptr(), 1, null()),
            DpdnlStatus::NullPointer
        );
        assert_eq!(last_error(), "arg is a null pointer");
        let one_null = [null::<c_char>()];
        assert_eq!(
            dpdnl_parse_fix_integrator(nve.as_ptr(), 1, one_null.as_ptr()),
            DpdnlStatus::NullPointer
        );
        assert_eq!(last_error(), "arg[0] is a null pointer");
        // No words: a null `arg` is allowed.
        assert_eq!(
            dpdnl_parse_fix_integrator(nve.as_ptr(), 0, null()),
            DpdnlStatus::Ok
        );
        assert_eq!(
            dpdnl_parse_fix_integrator(nve.as_ptr(), -1, null()),
            DpdnlStatus::InvalidArgument
        );
        assert_eq!(last_error(), "narg = -1 must be >= 0");
    }
    // Bytes that are not UTF-8 are refused with a message, not read as text.
    let bad = [0xffu8, 0xfe, 0];
    let bad_arg = [bad.as_ptr().cast::<c_char>()];
    // SAFETY: a NUL-terminated byte string.
    let st = unsafe { dpdnl_parse_fix_integrator(nve.as_ptr(), 1, bad_arg.as_ptr()) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert_eq!(last_error(), "arg[0] is not valid UTF-8");
}

#[test]
fn parse_fix_pex_push_as_grammar() {
    let cases: [(i32, &[&str]); 14] = [
        (3, &["0.05"]),
        (3, &["0.05", "width", "0.8", "every", "4"]),
        (3, &["1e-3", "every", "2147483647"]),
        (3, &["0.5", "width", "1.25"]),
        (2, &["0.05"]),
        (3, &[]),
        (3, &["-0.05"]),
        (3, &["0"]),
        (3, &["nan"]),
        (3, &["0.05", "every"]),
        (3, &["0.05", "every", "0"]),
        (3, &["0.05", "every", "4294967297"]),
        (3, &["0.05", "width", "-1"]),
        (3, &["0.05", "depth", "1"]),
    ];
    for (dim, words) in cases {
        let (_c, p) = cwords(words);
        let mut out = DpdnlPexArgs {
            dp: -7.0,
            width: -7.0,
            every: -7,
        };
        // SAFETY: valid strings; `out` is valid for writing.
        let st = unsafe { dpdnl_parse_fix_pex_push(dim, p.len() as i32, p.as_ptr(), &mut out) };
        match fix::pex_push(words, dim as usize) {
            Ok(want) => {
                assert_eq!(st, DpdnlStatus::Ok, "{words:?}: {}", last_error());
                assert_eq!(out.dp.to_bits(), want.dp.to_bits(), "{words:?}");
                assert_eq!(
                    out.width.to_bits(),
                    want.width.unwrap_or(0.0).to_bits(),
                    "{words:?}"
                );
                assert_eq!(i64::from(out.every), want.every as i64, "{words:?}");
            }
            Err(message) => {
                assert_eq!(st, DpdnlStatus::InvalidArgument, "{words:?}");
                assert_eq!(last_error(), message, "{words:?}");
            }
        }
    }
    let (_c, p) = cwords(&["0.05"]);
    let mut out = DpdnlPexArgs::default();
    // SAFETY: null pointers are reported, never read or written.
    unsafe {
        assert_eq!(
            dpdnl_parse_fix_pex_push(3, 1, p.as_ptr(), null_mut()),
            DpdnlStatus::NullPointer
        );
        assert_eq!(last_error(), "out is a null pointer");
        assert_eq!(
            dpdnl_parse_fix_pex_push(3, 1, null(), &mut out),
            DpdnlStatus::NullPointer
        );
        assert_eq!(last_error(), "arg is a null pointer");
        // A negative dimension is no dimension: the grammar's refusal of anything but 3.
        assert_eq!(
            verdict(dpdnl_parse_fix_pex_push(-3, 1, p.as_ptr(), &mut out)),
            fix::pex_push(&["0.05"], 0).map(|_| ())
        );
    }
}

#[test]
fn pex_box_check_as_grammar() {
    for width in [0.0, -1.0, 0.2, 1.9, 2.0, 2.0001, 9.0] {
        for lx in [4.0, 3.9, 40.0] {
            for triclinic in [0, 1] {
                for x_periodic in [0, 1] {
                    let args = DpdnlPexArgs {
                        dp: 0.1,
                        width,
                        every: 1,
                    };
                    // SAFETY: `args` is valid for reading.
                    let st = unsafe { dpdnl_pex_box_check(&args, lx, triclinic, x_periodic) };
                    // Width 0 (or below) in C is the default, `None` in Rust.
                    let want = fix::pex_box_check(
                        (width > 0.0).then_some(width),
                        lx,
                        triclinic != 0,
                        x_periodic != 0,
                    );
                    assert_eq!(
                        verdict(st),
                        want.map(|_| ()),
                        "width {width} lx {lx} triclinic {triclinic} periodic {x_periodic}"
                    );
                }
            }
        }
    }
    // SAFETY: a null `args` is reported, never read.
    let st = unsafe { dpdnl_pex_box_check(null(), 4.0, 0, 1) };
    assert_eq!(st, DpdnlStatus::NullPointer);
    assert_eq!(last_error(), "args is a null pointer");
}

/// One rank's atoms for the fix entry points, LAMMPS layout (`&x[0][0]`, 1-based types).
struct Rank {
    x: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    f: Vec<[f64; 3]>,
    tag: Vec<i32>,
    typ: Vec<i32>,
    mask: Vec<i32>,
    /// Per type, entry 0 unused.
    mass: Vec<f64>,
    rmass: Vec<f64>,
}

const XLO: f64 = -1.5;
const XHI: f64 = 6.5;

/// `n` atoms in x ∈ [XLO − 0.5, XHI + 0.5) (some outside the box, wrapped by the slabs),
/// velocities with ties in v_z, group bits 1 and 2, three types.
fn rank(n: u32) -> Rank {
    let mut r = Rank {
        x: vec![],
        v: vec![],
        f: vec![],
        tag: vec![],
        typ: vec![],
        mask: vec![],
        mass: vec![0.0, 1.0, 2.5, 0.75],
        rmass: vec![],
    };
    for i in 0..n {
        let u = |k: u32, lo: f64, hi: f64| uniform(i, k, lo, hi);
        r.x.push([u(0, XLO - 0.5, XHI + 0.5), u(1, 0.0, 3.0), u(2, 0.0, 3.0)]);
        // v_z on a coarse grid so that slabs hold ties (broken by the lowest tag).
        let vz = (u(5, -4.0, 4.0) * 2.0).round() / 2.0;
        r.v.push([u(3, -2.0, 2.0), u(4, -2.0, 2.0), vz]);
        r.f.push([u(6, -50.0, 50.0), u(7, -50.0, 50.0), u(8, -50.0, 50.0)]);
        // Tags unique but not in storage order.
        r.tag.push(((i * 37) % 1009 + 1) as i32);
        r.typ.push(1 + (i % 3) as i32);
        r.mask.push(1 | if i % 4 == 0 { 0 } else { 2 });
        r.rmass.push(u(9, 0.5, 2.0));
    }
    r
}

fn flat(rows: &[[f64; 3]]) -> Vec<f64> {
    rows.iter().flatten().copied().collect()
}

fn bits(rows: &[[f64; 3]]) -> Vec<u64> {
    rows.iter().flatten().map(|q| q.to_bits()).collect()
}

#[test]
fn pex_select_as_engine() {
    let r = rank(300);
    let tags: Vec<u32> = r.tag.iter().map(|&t| t as u32).collect();
    for width in [0.0, 0.05, 0.4, 2.0] {
        for groupbit in [1, 2, 4] {
            let args = DpdnlPexArgs {
                dp: 0.3,
                width,
                every: 1,
            };
            let mut out = DpdnlPexPick::default();
            // SAFETY: arrays of `n` rows / ints; `args` and `out` valid.
            let st = unsafe {
                dpdnl_pex_select(
                    &args,
                    r.x.len() as i32,
                    flat(&r.x).as_ptr(),
                    flat(&r.v).as_ptr(),
                    r.tag.as_ptr(),
                    r.mask.as_ptr(),
                    groupbit,
                    XLO,
                    XHI,
                    &mut out,
                )
            };
            assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
            let w = if width > 0.0 {
                width
            } else {
                (XHI - XLO) / 20.0
            };
            let slabs = PexSlabs::new(XLO, XHI, w);
            let want = PexPick::select(&slabs, &r.x, &r.v, &tags, |i| r.mask[i] & groupbit != 0);
            let none = i32::MAX;
            let (slow_v, slow_tag) = want
                .slow
                .map_or((f64::INFINITY, none), |(v, t)| (v, t as i32));
            let (fast_v, fast_tag) = want
                .fast
                .map_or((f64::NEG_INFINITY, none), |(v, t)| (v, t as i32));
            assert_eq!(
                out.slow_v.to_bits(),
                slow_v.to_bits(),
                "w {width} g {groupbit}"
            );
            assert_eq!(out.slow_tag, slow_tag, "w {width} g {groupbit}");
            assert_eq!(
                out.fast_v.to_bits(),
                fast_v.to_bits(),
                "w {width} g {groupbit}"
            );
            assert_eq!(out.fast_tag, fast_tag, "w {width} g {groupbit}");
            if groupbit == 4 {
                // Nobody in the group: both slabs empty, the MINLOC/MAXLOC identities.
                assert_eq!(
                    (out.slow_v, out.slow_tag, out.fast_v, out.fast_tag),
                    (f64::INFINITY, none, f64::NEG_INFINITY, none)
                );
            } else {
                assert!(want.slow.is_some() && want.fast.is_some(), "w {width}");
            }
        }
    }
    let args = DpdnlPexArgs {
        dp: 0.3,
        width: 0.4,
        every: 1,
    };
    let (x, v) = (flat(&r.x), flat(&r.v));
    let mut out = DpdnlPexPick::default();
    let n = r.x.len() as i32;
    // SAFETY: every null pointer below is reported, never read or written.
    unsafe {
        for (st, what) in [
            (
                dpdnl_pex_select(
                    null(),
                    n,
                    x.as_ptr(),
                    v.as_ptr(),
                    r.tag.as_ptr(),
                    r.mask.as_ptr(),
                    1,
                    XLO,
                    XHI,
                    &mut out,
                ),
                "args",
            ),
            (
                dpdnl_pex_select(
                    &args,
                    n,
                    null(),
                    v.as_ptr(),
                    r.tag.as_ptr(),
                    r.mask.as_ptr(),
                    1,
                    XLO,
                    XHI,
                    &mut out,
                ),
                "x",
            ),
            (
                dpdnl_pex_select(
                    &args,
                    n,
                    x.as_ptr(),
                    v.as_ptr(),
                    null(),
                    r.mask.as_ptr(),
                    1,
                    XLO,
                    XHI,
                    &mut out,
                ),
                "tag",
            ),
            (
                dpdnl_pex_select(
                    &args,
                    n,
                    x.as_ptr(),
                    v.as_ptr(),
                    r.tag.as_ptr(),
                    r.mask.as_ptr(),
                    1,
                    XLO,
                    XHI,
                    null_mut(),
                ),
                "out",
            ),
        ] {
            assert_eq!(st, DpdnlStatus::NullPointer, "{what}");
        }
        let st = dpdnl_pex_select(
            &args,
            -1,
            null(),
            null(),
            null(),
            null(),
            1,
            XLO,
            XHI,
            &mut out,
        );
        assert_eq!(st, DpdnlStatus::InvalidArgument);
        assert_eq!(last_error(), "nlocal = -1 must be >= 0");
        // No atoms on this rank: null arrays are fine, both slabs empty.
        let st = dpdnl_pex_select(
            &args,
            0,
            null(),
            null(),
            null(),
            null(),
            1,
            XLO,
            XHI,
            &mut out,
        );
        assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
        assert_eq!(
            (out.slow_v, out.slow_tag, out.fast_v, out.fast_tag),
            (f64::INFINITY, i32::MAX, f64::NEG_INFINITY, i32::MAX)
        );
    }
}

#[test]
fn pex_apply_as_engine() {
    let r = rank(64);
    let tags: Vec<u32> = r.tag.iter().map(|&t| t as u32).collect();
    let args = DpdnlPexArgs {
        dp: 0.37,
        width: 0.0,
        every: 1,
    };
    // (slow, fast): both here, one here, neither here, the same atom.
    let (a, b) = (r.tag[5], r.tag[40]);
    for (slow, fast) in [(a, b), (a, 100_000), (99_999, 100_000), (b, b)] {
        for per_atom in [false, true] {
            let mut v = flat(&r.v);
            let rmass = if per_atom { r.rmass.as_ptr() } else { null() };
            // SAFETY: arrays of `n` rows / ints / doubles; `mass` covers every type.
            let st = unsafe {
                dpdnl_pex_apply(
                    &args,
                    r.v.len() as i32,
                    v.as_mut_ptr(),
                    r.tag.as_ptr(),
                    r.typ.as_ptr(),
                    r.mass.as_ptr(),
                    rmass,
                    slow,
                    fast,
                )
            };
            assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
            let mut want = r.v.clone();
            let mass = |i: usize| {
                if per_atom {
                    r.rmass[i]
                } else {
                    r.mass[r.typ[i] as usize]
                }
            };
            pex_apply(&mut want, &tags, mass, args.dp, slow as u32, fast as u32);
            let got: Vec<u64> = v.iter().map(|q| q.to_bits()).collect();
            assert_eq!(got, bits(&want), "slow {slow} fast {fast} rmass {per_atom}");
            if slow != 99_999 && slow != fast {
                assert_ne!(got, bits(&r.v), "the push changed something");
            }
        }
    }
    let mut v = flat(&r.v);
    let n = r.v.len() as i32;
    // SAFETY: every null pointer below is reported, never read or written.
    unsafe {
        let st = dpdnl_pex_apply(
            null(),
            n,
            v.as_mut_ptr(),
            r.tag.as_ptr(),
            r.typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            a,
            b,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "args is a null pointer")
        );
        let st = dpdnl_pex_apply(
            &args,
            n,
            null_mut(),
            r.tag.as_ptr(),
            r.typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            a,
            b,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "v is a null pointer")
        );
        let st = dpdnl_pex_apply(
            &args,
            n,
            v.as_mut_ptr(),
            r.tag.as_ptr(),
            r.typ.as_ptr(),
            null(),
            null(),
            a,
            b,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "mass is a null pointer")
        );
        // A type below 1 cannot index the per-type masses.
        let mut typ = r.typ.clone();
        typ[3] = 0;
        let st = dpdnl_pex_apply(
            &args,
            n,
            v.as_mut_ptr(),
            r.tag.as_ptr(),
            typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            a,
            b,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::InvalidArgument, "an atom type is < 1")
        );
    }
    assert_eq!(
        v.iter().map(|q| q.to_bits()).collect::<Vec<_>>(),
        bits(&r.v),
        "refused calls change nothing"
    );
}

#[test]
fn euler_step_as_engine() {
    let r = rank(200);
    let (dtv, dtf) = (0.004, 0.004 * 1.0);
    for groupbit in [1, 2] {
        for per_atom in [false, true] {
            let (mut x, mut v) = (flat(&r.x), flat(&r.v));
            let rmass = if per_atom { r.rmass.as_ptr() } else { null() };
            // SAFETY: arrays of `n` rows / ints / doubles; `x` and `v` distinct.
            let st = unsafe {
                dpdnl_euler_step(
                    r.x.len() as i32,
                    x.as_mut_ptr(),
                    v.as_mut_ptr(),
                    flat(&r.f).as_ptr(),
                    r.typ.as_ptr(),
                    r.mass.as_ptr(),
                    rmass,
                    r.mask.as_ptr(),
                    groupbit,
                    dtv,
                    dtf,
                )
            };
            assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
            let (mut wx, mut wv) = (r.x.clone(), r.v.clone());
            for i in 0..r.x.len() {
                if r.mask[i] & groupbit != 0 {
                    let m = if per_atom {
                        r.rmass[i]
                    } else {
                        r.mass[r.typ[i] as usize]
                    };
                    euler_update(&mut wx[i], &mut wv[i], &r.f[i], dtv, dtf / m);
                }
            }
            let gx: Vec<u64> = x.iter().map(|q| q.to_bits()).collect();
            let gv: Vec<u64> = v.iter().map(|q| q.to_bits()).collect();
            assert_eq!(gx, bits(&wx), "x: group {groupbit} rmass {per_atom}");
            assert_eq!(gv, bits(&wv), "v: group {groupbit} rmass {per_atom}");
            // Atoms outside the group (every fourth is not in group 2) keep their state.
            if groupbit == 2 {
                assert_eq!(gx[..3], bits(&r.x)[..3]);
            }
            assert_ne!(gx, bits(&r.x));
        }
    }
    let (mut x, mut v, f) = (flat(&r.x), flat(&r.v), flat(&r.f));
    let n = r.x.len() as i32;
    // SAFETY: every null pointer below is reported, never read or written.
    unsafe {
        let st = dpdnl_euler_step(
            n,
            null_mut(),
            v.as_mut_ptr(),
            f.as_ptr(),
            r.typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            r.mask.as_ptr(),
            1,
            dtv,
            dtf,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "x is a null pointer")
        );
        let st = dpdnl_euler_step(
            n,
            x.as_mut_ptr(),
            v.as_mut_ptr(),
            null(),
            r.typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            r.mask.as_ptr(),
            1,
            dtv,
            dtf,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "f is a null pointer")
        );
        let st = dpdnl_euler_step(
            n,
            x.as_mut_ptr(),
            v.as_mut_ptr(),
            f.as_ptr(),
            r.typ.as_ptr(),
            r.mass.as_ptr(),
            null(),
            null(),
            1,
            dtv,
            dtf,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "mask is a null pointer")
        );
        let st = dpdnl_euler_step(
            -2,
            null_mut(),
            null_mut(),
            null(),
            null(),
            null(),
            null(),
            null(),
            1,
            dtv,
            dtf,
        );
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::InvalidArgument, "nlocal = -2 must be >= 0")
        );
    }
    assert_eq!(
        (
            x.iter().map(|q| q.to_bits()).collect::<Vec<_>>(),
            v.iter().map(|q| q.to_bits()).collect::<Vec<_>>()
        ),
        (bits(&r.x), bits(&r.v)),
        "refused calls change nothing"
    );
}

/// `dpdnl_check_health` on `r`'s atoms (x, v, tag, f) against `check_atoms` on the same.
fn health(r: &Rank, step: i64, dt: f64, len: [f64; 3], dimension: i32) -> Result<(), String> {
    let (x, v, f) = (flat(&r.x), flat(&r.v), flat(&r.f));
    let atoms = DpdnlAtoms {
        x: x.as_ptr(),
        v: v.as_ptr(),
        tag: r.tag.as_ptr(),
        atom_type: r.typ.as_ptr(),
        mass: r.mass.as_ptr(),
        rmass: null(),
        nlocal: r.x.len() as i32,
        nall: r.x.len() as i32,
    };
    // SAFETY: arrays of `nlocal` rows / ints; `len` 3 doubles.
    let got = verdict(unsafe {
        dpdnl_check_health(&atoms, f.as_ptr(), step, dt, len.as_ptr(), dimension)
    });
    let want = check_atoms(
        step as u64,
        dt,
        if dimension == 2 { 2 } else { 3 },
        len,
        r.x.len(),
        |i| (r.tag[i] as u32, r.x[i], r.v[i], r.f[i]),
    );
    assert_eq!(got, want, "step {step} dt {dt} len {len:?} dim {dimension}");
    got
}

#[test]
fn check_health_as_engine() {
    let len = [8.0, 3.0, 3.0];
    let mut r = rank(50);
    assert_eq!(health(&r, 10, 0.01, len, 3), Ok(()));
    // Too fast along z (v_z δt > Lz/2): refused in 3-D, ignored in 2-D.
    r.v[17][2] = 200.0;
    let e = health(&r, 11, 0.01, len, 3).unwrap_err();
    assert!(e.contains(&format!("atom {}", r.tag[17])), "{e}");
    assert_eq!(health(&r, 11, 0.01, len, 2), Ok(()));
    r.v[17][2] = 0.0;
    // Non-finite position, velocity, force: each named.
    for (k, what) in [(0, "position"), (1, "velocity"), (2, "force")] {
        let mut bad = rank(50);
        match k {
            0 => bad.x[9][1] = f64::NAN,
            1 => bad.v[9][0] = f64::INFINITY,
            _ => bad.f[9][2] = f64::NEG_INFINITY,
        }
        let e = health(&bad, 123, 0.01, len, 3).unwrap_err();
        assert!(e.contains(what) && e.contains("step 123"), "{e}");
    }
    let (x, v, f) = (flat(&r.x), flat(&r.v), flat(&r.f));
    let atoms = DpdnlAtoms {
        x: x.as_ptr(),
        v: v.as_ptr(),
        tag: r.tag.as_ptr(),
        atom_type: r.typ.as_ptr(),
        mass: r.mass.as_ptr(),
        rmass: null(),
        nlocal: r.x.len() as i32,
        nall: r.x.len() as i32,
    };
    // SAFETY: every null pointer below is reported, never read.
    unsafe {
        let st = dpdnl_check_health(null(), f.as_ptr(), 0, 0.01, len.as_ptr(), 3);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "atoms is a null pointer")
        );
        let st = dpdnl_check_health(&atoms, null(), 0, 0.01, len.as_ptr(), 3);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "f is a null pointer")
        );
        let st = dpdnl_check_health(&atoms, f.as_ptr(), 0, 0.01, null(), 3);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "len is a null pointer")
        );
        let no_v = DpdnlAtoms { v: null(), ..atoms };
        let st = dpdnl_check_health(&no_v, f.as_ptr(), 0, 0.01, len.as_ptr(), 3);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "v is a null pointer")
        );
    }
}

#[test]
fn box_check_as_engine() {
    for len in [
        [2.0, 2.0, 2.0],
        [1.99, 5.0, 5.0],
        [5.0, 1.5, 5.0],
        [5.0, 5.0, 1.0],
        [0.99, 5.0, 5.0],
        [5.0, 0.5, 5.0],
    ] {
        for periodic in [[1, 1, 1], [0, 1, 1], [1, 0, 1], [1, 1, 0], [0, 0, 0]] {
            for dimension in [2, 3] {
                for rc_max in [1.0, 0.5, 0.99] {
                    // SAFETY: 3 values each.
                    let st = unsafe {
                        dpdnl_box_check(len.as_ptr(), periodic.as_ptr(), dimension, rc_max)
                    };
                    let want =
                        check_box_images(len, periodic.map(|p| p != 0), dimension as usize, rc_max);
                    assert_eq!(
                        verdict(st),
                        want,
                        "len {len:?} periodic {periodic:?} dim {dimension} rc {rc_max}"
                    );
                }
            }
        }
    }
    // The refusal is real: a box shorter than rc along a periodic axis.
    let (len, per) = ([0.99, 5.0, 5.0], [1, 1, 1]);
    // SAFETY: 3 values each.
    let st = unsafe { dpdnl_box_check(len.as_ptr(), per.as_ptr(), 3, 1.0) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(
        last_error().contains("in x is shorter than the largest cut-off rc = 1"),
        "{}",
        last_error()
    );
    // SAFETY: null pointers are reported, never read.
    unsafe {
        let st = dpdnl_box_check(null(), per.as_ptr(), 3, 1.0);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "len is a null pointer")
        );
        let st = dpdnl_box_check(len.as_ptr(), null(), 3, 1.0);
        assert_eq!(
            (st, last_error().as_str()),
            (DpdnlStatus::NullPointer, "periodic is a null pointer")
        );
    }
}

#[test]
fn parse_fix_flip_momentum_as_grammar() {
    let cases: [&[&str]; 5] = [
        &[],
        &["mode", "jump"],
        &["mode", "check"],
        &["mode", "both"],
        &["every", "2"],
    ];
    for words in cases {
        let (_keep, ptrs) = cwords(words);
        let mut jump = -1;
        // SAFETY: `ptrs` holds `words.len()` valid strings; `jump` is valid.
        let st =
            unsafe { dpdnl_parse_fix_flip_momentum(ptrs.len() as i32, ptrs.as_ptr(), &mut jump) };
        let want = fix::flip_momentum(words);
        assert_eq!(verdict(st), want.map(|_| ()), "{words:?}");
        if let Ok(j) = fix::flip_momentum(words) {
            assert_eq!(jump, i32::from(j), "{words:?}");
        }
    }
    // SAFETY: a null output pointer is reported, not written.
    let st = unsafe { dpdnl_parse_fix_flip_momentum(0, null(), null_mut()) };
    assert_eq!(st, DpdnlStatus::NullPointer);
}

#[test]
fn flip_momentum_setup_as_grammar() {
    let id = CString::new("3").unwrap();
    for (remap, group, xy) in [(1, 1, 1), (0, 1, 1), (1, 0, 1), (1, 1, 0)] {
        // SAFETY: a valid NUL-terminated ID.
        let st = unsafe { dpdnl_flip_momentum_setup(id.as_ptr(), remap, group, xy) };
        let want = fix::flip_momentum_setup(Some(("3", remap != 0, group != 0, xy != 0)));
        assert_eq!(verdict(st), want, "{remap} {group} {xy}");
    }
    // SAFETY: null: no fix deform.
    let st = unsafe { dpdnl_flip_momentum_setup(null(), 1, 1, 1) };
    assert_eq!(verdict(st), fix::flip_momentum_setup(None));
}

/// `dpdnl_flip_wrap` moves the atoms outside y by `flip_wrap_y` (with the jump) or only counts
/// them, in the group only, and adds Σ m n h_rate to the momentum it reports; the text of
/// `dpdnl_flip_leak_warning` is the engine's.
#[test]
fn flip_wrap_as_engine() {
    use dpdnl::engine::lees_edwards::{FlipLeak, flip_jump_note, flip_leak_warning, flip_wrap_y};
    let (ylo, yhi, xy, h) = (-2.0, 3.0, 1.7, 2.5);
    let n = 64usize;
    let x0: Vec<[f64; 3]> = (0..n as u32)
        .map(|i| [uniform(i, 0, 0.0, 4.0), uniform(i, 1, -2.6, 3.6), 0.0])
        .collect();
    let v0: Vec<[f64; 3]> = (0..n as u32)
        .map(|i| [uniform(i, 2, -1.0, 1.0), uniform(i, 3, -1.0, 1.0), 0.0])
        .collect();
    let typ: Vec<i32> = (0..n).map(|i| 1 + (i % 2) as i32).collect();
    let mask: Vec<i32> = (0..n).map(|i| if i % 5 == 0 { 1 } else { 3 }).collect();
    let mass = [0.0, 1.0, 2.5];
    for jump in [1, 0] {
        let (mut x, mut v) = (flat(&x0), flat(&v0));
        let mut ny = vec![7; n];
        let (mut atoms, mut momentum) = (0i64, 0.0);
        // SAFETY: every array holds n atoms; the outputs are valid.
        let st = unsafe {
            dpdnl_flip_wrap(
                n as i32,
                x.as_mut_ptr(),
                v.as_mut_ptr(),
                typ.as_ptr(),
                mass.as_ptr(),
                null(),
                mask.as_ptr(),
                2,
                ylo,
                yhi,
                xy,
                h,
                jump,
                ny.as_mut_ptr(),
                &mut atoms,
                &mut momentum,
            )
        };
        assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
        let (mut want_atoms, mut want_p) = (0i64, 0.0);
        for i in 0..n {
            let (mut xi, mut vi) = (x0[i], v0[i]);
            let k = if mask[i] & 2 == 0 {
                0
            } else {
                flip_wrap_y(&mut xi, &mut vi, ylo, yhi, xy, h, true)
            };
            assert_eq!(ny[i], k, "atom {i}");
            if jump == 0 {
                (xi, vi) = (x0[i], v0[i]);
            }
            assert_eq!(
                bits(&[xi, vi]),
                bits(&[
                    [x[3 * i], x[3 * i + 1], x[3 * i + 2]],
                    [v[3 * i], v[3 * i + 1], v[3 * i + 2]]
                ]),
                "atom {i}"
            );
            if k != 0 {
                want_atoms += 1;
                want_p += mass[typ[i] as usize] * f64::from(k) * h;
            }
        }
        assert!(
            want_atoms >= 5,
            "too few atoms outside the box: {want_atoms}"
        );
        assert_eq!((atoms, momentum.to_bits()), (want_atoms, want_p.to_bits()));
        let st = dpdnl_flip_leak_warning(atoms, momentum, jump, 100.0);
        assert_eq!(st, DpdnlStatus::Ok);
        // SAFETY: a valid NUL-terminated string owned by this thread.
        let text = unsafe { CStr::from_ptr(dpdnl_last_message()) }
            .to_string_lossy()
            .into_owned();
        let leak = FlipLeak {
            atoms: atoms as u64,
            momentum,
            conserved: jump != 0,
        };
        let want = match flip_leak_warning(&leak, 100.0) {
            Some(w) => format!("WARNING: {w}"),
            None => flip_jump_note(&leak).unwrap_or_default(),
        };
        assert!(!text.is_empty());
        assert_eq!(text, want);
    }
}
