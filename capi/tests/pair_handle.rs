//! The one pair handle (`dpdnl_pair_*`), the C API of the LAMMPS styles: its forces, energy and
//! virial against the direct pair loop with the kernel, a restart text that gives the same style
//! back, sDPD's pre-pass against a direct sum, and bad calls as codes plus text.

use std::ffi::{CStr, c_void};
use std::ptr::{null, null_mut};

use dpdnl::forces::dpd::kernel::{
    Friction, Noise, PairCoeff, PairInput, PairModel, Weight, pair_force,
};
use dpdnl::rng::{keyed_uniform, pair_gaussian};
use dpdnl_capi::*;

mod common;
use common::*;

const SEED: u32 = 4242;
const DT: f64 = 0.01;

/// `n` owned atoms in a cube of side `len`, two types, ghosts: the periodic images within
/// `cut` of the box.
struct Atoms {
    x: Vec<f64>,
    v: Vec<f64>,
    tag: Vec<i32>,
    ty: Vec<i32>,
    nlocal: usize,
    owner: Vec<usize>,
}

fn uniform(a: u32, b: u32, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * keyed_uniform(99, 1000, 7, a, b)
}

impl Atoms {
    fn new(n: usize, len: f64, cut: f64) -> Atoms {
        let mut s = Atoms {
            x: vec![],
            v: vec![],
            tag: vec![],
            ty: vec![],
            nlocal: n,
            owner: vec![],
        };
        for i in 0..n {
            let k = i as u32;
            s.x.extend([0, 1, 2].map(|d| uniform(k, 100 + d, 0.0, len)));
            s.v.extend([0, 1, 2].map(|d| uniform(k, 200 + d, -1.0, 1.0)));
            s.tag.push(((i * 37) % n + 1) as i32);
            s.ty.push(1 + (i % 3 == 0) as i32);
            s.owner.push(i);
        }
        for k in 0..27 {
            let sh = [k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1];
            if sh == [0, 0, 0] {
                continue;
            }
            for i in 0..n {
                let p = [0, 1, 2].map(|d| s.x[3 * i + d] + f64::from(sh[d]) * len);
                if p.iter().all(|&c| c > -cut && c < len + cut) {
                    s.x.extend(p);
                    s.v.extend_from_within(3 * i..3 * i + 3);
                    s.tag.push(s.tag[i]);
                    s.ty.push(s.ty[i]);
                    s.owner.push(i);
                }
            }
        }
        s
    }

    fn nall(&self) -> usize {
        self.tag.len()
    }

    /// The C view of the atoms (per-type masses `MASS`).
    fn c_atoms(&self) -> DpdnlAtoms {
        DpdnlAtoms {
            x: self.x.as_ptr(),
            v: self.v.as_ptr(),
            tag: self.tag.as_ptr(),
            atom_type: self.ty.as_ptr(),
            mass: MASS.as_ptr(),
            rmass: null(),
            nlocal: self.nlocal as i32,
            nall: self.nall() as i32,
        }
    }

    /// A half list with newton on (each physical pair once) within `cut`.
    fn rsq(&self, i: usize, j: usize) -> f64 {
        (0..3)
            .map(|d| (self.x[3 * i + d] - self.x[3 * j + d]).powi(2))
            .sum()
    }

    /// A LAMMPS-like neighbour list within `cut`: `Half(newton)` or `Full`.
    fn list(&self, kind: ListKind, cut: f64) -> Vec<Vec<i32>> {
        let mut lists = vec![vec![]; self.nlocal];
        for (i, li) in lists.iter_mut().enumerate() {
            for j in 0..self.nall() {
                if j == i || self.rsq(i, j) >= cut * cut {
                    continue;
                }
                let keep = match kind {
                    ListKind::Full => true,
                    ListKind::HalfNewtonOff => j >= self.nlocal || j > i,
                    // Each physical pair once: ghosts only towards the larger tag.
                    ListKind::HalfNewtonOn => {
                        if j < self.nlocal {
                            j > i
                        } else {
                            self.tag[i] < self.tag[j]
                        }
                    }
                };
                if keep {
                    // Set a special-bond bit the driver must mask away.
                    li.push(j as i32 | (1 << 30));
                }
            }
        }
        lists
    }

    fn half_list(&self, cut: f64) -> Vec<Vec<i32>> {
        let rsq = |i: usize, j: usize| -> f64 {
            (0..3)
                .map(|d| (self.x[3 * i + d] - self.x[3 * j + d]).powi(2))
                .sum()
        };
        (0..self.nlocal)
            .map(|i| {
                (0..self.nall())
                    .filter(|&j| j != i && rsq(i, j) < cut * cut)
                    .filter(|&j| {
                        if j < self.nlocal {
                            j > i
                        } else {
                            self.tag[i] < self.tag[j]
                        }
                    })
                    .map(|j| j as i32)
                    .collect()
            })
            .collect()
    }
}

/// A LAMMPS neighbour list in C form: the rows `ilist` of `lists` (row k for atom k) and the
/// arrays `view` points into, kept alive together.
struct CList {
    ilist: Vec<i32>,
    numneigh: Vec<i32>,
    firstneigh: Vec<*const i32>,
}

impl CList {
    fn new(ilist: Vec<i32>, lists: &[Vec<i32>]) -> CList {
        CList {
            ilist,
            numneigh: lists.iter().map(|l| l.len() as i32).collect(),
            firstneigh: lists.iter().map(|l| l.as_ptr()).collect(),
        }
    }

    /// The rows 0..n of `lists`.
    fn first(n: usize, lists: &[Vec<i32>]) -> CList {
        CList::new((0..n as i32).collect(), lists)
    }

    fn view(&self, neighmask: i32, full: bool) -> DpdnlNeighList {
        DpdnlNeighList {
            inum: self.ilist.len() as i32,
            ilist: self.ilist.as_ptr(),
            numneigh: self.numneigh.as_ptr(),
            firstneigh: self.firstneigh.as_ptr(),
            neighmask,
            full: i32::from(full),
            build: 0,
            skin: 0.0,
        }
    }
}

/// Forces (owned atoms, ghosts folded in), energy and virial of one evaluation.
#[derive(Debug, PartialEq)]
struct Out {
    f: Vec<f64>,
    energy: f64,
    virial: [f64; 6],
}

/// The step of [`evaluate`] and `special_step`: step 7, newton on, 3-D, no image key.
fn step_seven() -> DpdnlStep {
    DpdnlStep {
        step: 7,
        dt: DT,
        newton_pair: 1,
        dimension: 3,
        boxlen: [0.0; 3],
        tilt: [0.0; 3],
        periodic: [0; 3],
        beginstep: 0,
        endstep: 0,
    }
}

/// One force evaluation of `a` over its newton-on half list: `call(atoms, list, step, f,
/// tally)` is the entry point under test.
fn evaluate(
    a: &Atoms,
    cut: f64,
    call: impl FnOnce(
        &DpdnlAtoms,
        &DpdnlNeighList,
        &DpdnlStep,
        *mut f64,
        &mut DpdnlTally,
    ) -> DpdnlStatus,
) -> Out {
    let lists = a.half_list(cut);
    let rows = CList::first(a.nlocal, &lists);
    let atoms = a.c_atoms();
    let list = rows.view(0x3FFF_FFFF, false);
    let st = step_seven();
    let mut out = Out {
        f: vec![0.0; 3 * a.nall()],
        energy: 0.0,
        virial: [0.0; 6],
    };
    let mut tally = DpdnlTally {
        eflag_global: 1,
        vflag_global: 1,
        eng_vdwl: &mut out.energy,
        virial: out.virial.as_mut_ptr(),
        eatom: null_mut(),
        vatom: null_mut(),
    };
    let code = call(&atoms, &list, &st, out.f.as_mut_ptr(), &mut tally);
    assert_eq!(code, DpdnlStatus::Ok, "{}", last_error());
    for g in a.nlocal..a.nall() {
        let o = a.owner[g];
        for d in 0..3 {
            out.f[3 * o + d] += out.f[3 * g + d];
        }
    }
    out.f.truncate(3 * a.nlocal);
    out
}

const MODELS: [(&str, &str); 4] = [
    ("none", "plain"),
    ("cross", "plain"),
    ("dot", "corrected"),
    ("dot", "twostep"),
];

/// The handle of `dpd/nonlinear` for a friction/noise pair, with three type pairs set.
fn dpd_handle(fr: &str, no: &str) -> Handle {
    let seed = SEED.to_string();
    let h = new_style(
        "dpd/nonlinear",
        &[
            "0.7", "1.0", &seed, "friction", fr, "noise", no, "weight", "0.5",
        ],
        2,
    )
    .expect("style");
    let g1 = |g: &'static str| if fr == "none" { "0" } else { g };
    for line in [
        ["1", "1", "25", "4.5", g1("1.0"), "1.0"],
        ["1", "2", "10", "3.0", g1("0.5"), "1.2"],
        ["2", "2", "0", "5.0", g1("2.0"), "0.9"],
    ] {
        coeff(&h, 2, &line).expect("coeff");
    }
    h
}

/// The forces, energy and virial of `a` (owned atoms; ghosts folded into their owners, as
/// [`evaluate`] returns them) by the direct loop over every owned i and every image j ≠ i within
/// the cut-off, each pair through `pair_force` with the keyed ξ of step 7, seen from both of its
/// owned atoms (half the energy and virial each).
fn direct(a: &Atoms, model: &PairModel, coeff: impl Fn(i32, i32) -> PairCoeff) -> Out {
    let mut out = Out {
        f: vec![0.0; 3 * a.nlocal],
        energy: 0.0,
        virial: [0.0; 6],
    };
    let inv_m = |t: i32| 1.0 / MASS[t as usize];
    for i in 0..a.nlocal {
        for j in 0..a.nall() {
            if j == i {
                continue;
            }
            let dr = [0, 1, 2].map(|d| a.x[3 * i + d] - a.x[3 * j + d]);
            let input = PairInput {
                dr,
                dv: [0, 1, 2].map(|d| a.v[3 * i + d] - a.v[3 * j + d]),
                inv_mass_sum: inv_m(a.ty[i]) + inv_m(a.ty[j]),
                xi: pair_gaussian(SEED, 7, a.tag[i] as u32, a.tag[j] as u32),
            };
            let pf = pair_force(model, &coeff(a.ty[i], a.ty[j]), &input);
            let fv = pf.vector(dr);
            for (o, v) in out.f[3 * i..3 * i + 3].iter_mut().zip(fv) {
                *o += v;
            }
            out.energy += 0.5 * pf.energy;
            let fp = 0.5 * pf.total() * pf.inv_r;
            for (k, (p, q)) in [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]
                .into_iter()
                .enumerate()
            {
                out.virial[k] += dr[p] * dr[q] * fp;
            }
        }
    }
    out
}

/// `got` equals `want` to 1e-12 of the largest magnitude of each quantity (only the summation
/// order differs: a few tens of terms per atom, each rounding at 1.1e-16 relative).
fn assert_same(got: &Out, want: &Out, what: &str) {
    let close = |a: &[f64], b: &[f64], q: &str| {
        let scale = b.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "{what}: {q}[{k}] {x} vs {y} (scale {scale})"
            );
        }
    };
    close(&got.f, &want.f, "force");
    close(&[got.energy], &[want.energy], "energy");
    close(&got.virial, &want.virial, "virial");
}

/// The dense coefficients of [`dpd_handle`] by type pair.
fn dpd_coeff(fr: &str) -> impl Fn(i32, i32) -> PairCoeff {
    let g1 = if fr == "none" { 0.0 } else { 1.0 };
    move |i, j| {
        let c = |a, gamma0, gamma1: f64, rc| PairCoeff {
            a,
            gamma0,
            gamma1: gamma1 * g1,
            rc,
        };
        match (i.min(j), i.max(j)) {
            (1, 1) => c(25.0, 4.5, 1.0, 1.0),
            (1, 2) => c(10.0, 3.0, 0.5, 1.2),
            _ => c(0.0, 5.0, 2.0, 0.9),
        }
    }
}

/// The handle's forces, energy and virial over a LAMMPS-like half list (newton on, ghosts)
/// equal the direct pair loop with the kernel (formerly checked against the low-level
/// parameter-table API, removed in issue 45).
#[test]
fn dpd_handle_equals_the_direct_pair_loop() {
    let a = Atoms::new(60, 3.0, 1.2);
    for (fr, no) in MODELS {
        let h = dpd_handle(fr, no);
        assert_eq!(init(&h, 60, 27.0).expect("init"), 1.2);
        let mine = evaluate(&a, 1.2, |at, l, st, f, t| {
            // SAFETY: arrays sized as documented, alive across the call.
            unsafe { dpdnl_pair_compute(h.0, at, l, st, null(), f, t) }
        });
        let model = PairModel::new(
            0.7,
            Friction::from_keyword(fr).unwrap(),
            Noise::from_keyword(no).unwrap(),
            Weight::new(0.5).unwrap(),
            DT,
        );
        assert_same(
            &mine,
            &direct(&a, &model, dpd_coeff(fr)),
            &format!("{fr}/{no}"),
        );
        assert!(mine.energy != 0.0 && mine.f.iter().any(|&x| x != 0.0));
        // Momentum: the pair forces sum to zero.
        for d in 0..3 {
            let total: f64 = (0..a.nlocal).map(|i| mine.f[3 * i + d]).sum();
            assert!(total.abs() < 1e-10, "{fr}/{no}: net force {total}");
        }
    }
}

/// In the host's `units real`, T = 300 of the handle is a temperature: its forces are those of
/// the direct loop with kT = boltz · 300 and the unit style's ftm2v (which the two-step kick and
/// the correction take); and they differ from the loop with ftm2v = 1, so the units reach the
/// kernel. A set-up with bad units is refused.
#[test]
fn dpd_handle_takes_the_hosts_units() {
    let a = Atoms::new(60, 3.0, 1.2);
    let u = real_units();
    for (fr, no) in [("dot", "corrected"), ("dot", "twostep"), ("none", "plain")] {
        let seed = SEED.to_string();
        let h = new_style(
            "dpd/nonlinear",
            &["300", "1.0", &seed, "friction", fr, "noise", no],
            2,
        )
        .expect("style");
        let g1 = if fr == "none" { "0" } else { "0.7" };
        coeff(&h, 2, &["*", "*", "2.0", "4.5", g1]).expect("coeff");
        init_in(&h, 60, 27.0, u).expect("init in real");
        assert!(
            last_message().contains("units real: T = 300 is a temperature"),
            "{}",
            last_message()
        );
        let mine = evaluate(&a, 1.0, |at, l, st, f, t| {
            // SAFETY: arrays sized as documented, alive across the call.
            unsafe { dpdnl_pair_compute(h.0, at, l, st, null(), f, t) }
        });
        let loop_with = |ftm2v: f64| {
            let model = PairModel::new(
                dpdnl::Units::REAL.kt(300.0),
                Friction::from_keyword(fr).unwrap(),
                Noise::from_keyword(no).unwrap(),
                Weight::STANDARD,
                DT,
            )
            .with_ftm2v(ftm2v);
            let coeff = |_, _| PairCoeff {
                a: 2.0,
                gamma0: 4.5,
                gamma1: if fr == "none" { 0.0 } else { 0.7 },
                rc: 1.0,
            };
            direct(&a, &model, coeff)
        };
        assert_same(
            &mine,
            &loop_with(u.ftm2v),
            &format!("{fr}/{no} in units real"),
        );
        if fr != "none" {
            let lj = loop_with(1.0);
            let differs = mine.f.iter().zip(&lj.f).any(|(x, y)| (x - y).abs() > 1e-9);
            assert!(differs, "{fr}/{no}: ftm2v must reach the kernel");
        }
    }
    let h = dpd_handle("none", "plain");
    for (what, bad) in [
        (
            "units.style is a null pointer",
            DpdnlUnits { style: null(), ..u },
        ),
        ("boltz = 0", DpdnlUnits { boltz: 0.0, ..u }),
        (
            "'parsec'",
            DpdnlUnits {
                style: c"parsec".as_ptr(),
                ..u
            },
        ),
        (
            "ftm2v = NaN",
            DpdnlUnits {
                ftm2v: f64::NAN,
                ..u
            },
        ),
        ("mvv2e = -1", DpdnlUnits { mvv2e: -1.0, ..u }),
    ] {
        let e = init_in(&h, 60, 27.0, bad).expect_err(what);
        assert!(e.contains(what), "{what}: {e}");
    }
}

fn restart_text(h: &Handle, settings_only: i32) -> Vec<u8> {
    let (mut data, mut len) = (null(), 0i64);
    // SAFETY: a live handle; out pointers valid.
    let st = unsafe { dpdnl_pair_restart(h.0, settings_only, &mut data, &mut len) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    // SAFETY: `len` bytes valid until the next call on `h`.
    unsafe { std::slice::from_raw_parts(data.cast::<u8>(), len as usize) }.to_vec()
}

fn from_restart(text: &[u8], ntypes: i32) -> Result<Handle, String> {
    let mut h = null_mut();
    // SAFETY: `text` holds its length in bytes; `h` valid for writing.
    let st =
        unsafe { dpdnl_pair_from_restart(text.as_ptr().cast(), text.len() as i64, ntypes, &mut h) };
    if st == DpdnlStatus::Ok {
        Ok(Handle(h))
    } else {
        Err(last_error())
    }
}

#[test]
fn restart_text_gives_the_same_style_back() {
    let a = Atoms::new(50, 3.0, 1.2);
    let h = dpd_handle("dot", "twostep");
    // (η, Sc) targets on one pair: stored as targets, resolved again at the next set-up.
    coeff(
        &h,
        2,
        &[
            "2", "2", "0", "eta", "0.5", "sc", "3", "gamma1", "0.7", "rc", "0.9",
        ],
    )
    .unwrap();
    let text = restart_text(&h, 0);
    let back = from_restart(&text, 2).expect("reads back");
    assert_eq!(restart_text(&back, 0), text);
    let mut outs = Vec::new();
    for hh in [&h, &back] {
        let mass1 = [0.0, 1.0, 1.0];
        let s = DpdnlSetup {
            dimension: 3,
            natoms: 50,
            volume: 27.0,
            mass: mass1.as_ptr(),
            dt: DT,
            euler: 0,
            special_lj: null(),
            units: lj_units(),
            substyle: 0,
            per_atom_mass: 0,
        };
        let mut rc = 0.0;
        // SAFETY: a live handle.
        assert_eq!(
            unsafe { dpdnl_pair_init(hh.0, &s, &mut rc) },
            DpdnlStatus::Ok,
            "{}",
            last_error()
        );
        assert!(
            last_message().contains("pair_coeff 2 2: eta 0.5 sc 3"),
            "{}",
            last_message()
        );
        outs.push(evaluate(&a, 1.2, |at, l, st, f, t| {
            // SAFETY: as in `evaluate`.
            unsafe { dpdnl_pair_compute(hh.0, at, l, st, null(), f, t) }
        }));
    }
    assert_eq!(outs[0], outs[1]);
    // The settings alone: a style with no coefficients, whose set-up names the first pair.
    let bare = from_restart(&restart_text(&h, 1), 2).expect("settings");
    assert!(
        init(&bare, 50, 27.0)
            .unwrap_err()
            .contains("types 1 1 are not set")
    );
    // Foreign or damaged text is refused with a reason.
    assert!(from_restart(b"hello", 2).unwrap_err().contains("corrupt"));
    let mut bad = text.clone();
    bad.truncate(text.len() - 3);
    bad.extend(b"\x1fbogus");
    assert!(from_restart(&bad, 2).is_err());
}

#[test]
fn info_single_and_data() {
    let h = dpd_handle("cross", "plain");
    // SAFETY: a live handle (and null, which gives zeros).
    let (i, z) = unsafe { (dpdnl_pair_info(h.0), dpdnl_pair_info(null())) };
    assert_eq!((i.values_per_atom, i.single, i.data), (0, 1, 1));
    assert_eq!((z.values_per_atom, z.single, z.data), (0, 0, 0));
    // single(): the conservative part a (1 − r/rc)/r and a rc (1 − r/rc)²/2, times the factor.
    let (mut f, mut e) = (0.0, 0.0);
    // SAFETY: a live handle; out pointers valid.
    assert_eq!(
        unsafe { dpdnl_pair_single(h.0, 1, 2, 0.36, 0.5, &mut f, &mut e) },
        DpdnlStatus::Ok
    );
    let w = 1.0 - 0.6 / 1.2;
    assert!(
        (f - 0.5 * 10.0 * w / 0.6).abs() < 1e-15
            && (e - 0.5 * 0.5 * 10.0 * 1.2 * w * w).abs() < 1e-15
    );
    // SAFETY: as above.
    assert_eq!(
        unsafe { dpdnl_pair_single(h.0, 1, 2, 1.44, 1.0, &mut f, &mut e) },
        DpdnlStatus::Ok
    );
    assert_eq!((f, e), (0.0, 0.0));
    let mut v = [0.0; 8];
    let mut n = 0;
    // SAFETY: a live handle; `v` holds 8 doubles.
    assert_eq!(
        unsafe { dpdnl_pair_data(h.0, 2, 1, v.as_mut_ptr(), 8, &mut n) },
        DpdnlStatus::Ok
    );
    assert_eq!(&v[..n as usize], &[10.0, 3.0, 0.5, 1.2]);
    // SAFETY: as above, too small a buffer.
    assert_eq!(
        unsafe { dpdnl_pair_data(h.0, 1, 1, v.as_mut_ptr(), 2, &mut n) },
        DpdnlStatus::InvalidArgument
    );
    let mut rc = 0.0;
    let mut set = 0;
    // SAFETY: as above.
    assert_eq!(
        unsafe { dpdnl_pair_cutoff(h.0, 3, 1, &mut rc, &mut set) },
        DpdnlStatus::InvalidArgument
    );
    assert!(last_error().contains("outside 1..=2"));

    let sd = sdpd_handle();
    // SAFETY: a live handle.
    let i = unsafe { dpdnl_pair_info(sd.0) };
    assert_eq!((i.values_per_atom, i.single, i.data), (1, 0, 1));
    // SAFETY: as above.
    assert_eq!(
        unsafe { dpdnl_pair_single(sd.0, 1, 1, 0.5, 1.0, &mut f, &mut e) },
        DpdnlStatus::InvalidArgument
    );
    assert!(last_error().contains("sdpd has no single()"));
}

fn sdpd_handle() -> Handle {
    let seed = SEED.to_string();
    let h = new_style("sdpd", &["1.0", "1.2", &seed, "kernel", "quintic"], 2).unwrap();
    coeff(&h, 2, &["*", "*", "1.0", "8.0", "2.0"]).unwrap();
    coeff(&h, 2, &["2", "2", "1.5", "6.0", "1.0", "1.0"]).unwrap();
    h
}

#[test]
fn sdpd_prepass_is_the_direct_density_sum_and_forces_conserve_momentum() {
    let a = Atoms::new(60, 3.0, 1.2);
    let h = sdpd_handle();
    init(&h, 60, 27.0).expect("init");
    let lists = a.half_list(1.2);
    let rows = CList::first(a.nlocal, &lists);
    let atoms = a.c_atoms();
    let list = rows.view(0x3FFF_FFFF, false);
    let mut rho = vec![0.0; a.nall()];
    // SAFETY: arrays as documented.
    let st = unsafe { dpdnl_pair_prepass(h.0, &atoms, &list, 1, rho.as_mut_ptr()) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    // Reverse communication, the end of the pass, forward communication.
    for g in a.nlocal..a.nall() {
        rho[a.owner[g]] += rho[g];
    }
    let mut energy = 0.0;
    let tally = DpdnlTally {
        eflag_global: 1,
        vflag_global: 0,
        eng_vdwl: &mut energy,
        virial: null_mut(),
        eatom: null_mut(),
        vatom: null_mut(),
    };
    // SAFETY: as above.
    let st = unsafe { dpdnl_pair_prepass_finish(h.0, &atoms, 7, rho.as_mut_ptr(), &tally) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    for g in a.nlocal..a.nall() {
        rho[g] = rho[a.owner[g]];
    }
    // The same densities from the standalone style object, summed directly over every image.
    let mut field = dpdnl::forces::new_pair_style(
        "sdpd",
        &["1.0", "1.2", &SEED.to_string(), "kernel", "quintic"].map(String::from),
        2,
        DT,
    )
    .unwrap();
    field
        .coeff(&["*", "*", "1.0", "8.0", "2.0"].map(String::from))
        .unwrap();
    field
        .coeff(&["2", "2", "1.5", "6.0", "1.0", "1.0"].map(String::from))
        .unwrap();
    let mass = [None, Some(1.0), Some(2.5)];
    field
        .setup(&dpdnl::engine::SetupContext {
            dim: 3,
            natoms: 60,
            density: 60.0 / 27.0,
            mass: &mass,
            dt: DT,
            euler: false,
            special_lj: [1.0; 4],
            units: dpdnl::Units::LJ,
            substyle: false,
            per_atom_mass: false,
        })
        .unwrap();
    let pp = field.prepass().expect("sdpd has a pre-pass");
    for (i, &got) in rho.iter().enumerate().take(a.nlocal) {
        let mut sum = 0.0;
        for j in 0..a.nall() {
            if a.owner[j] == i && j == i {
                continue;
            }
            let rsq: f64 = (0..3)
                .map(|d| (a.x[3 * i + d] - a.x[3 * j + d]).powi(2))
                .sum();
            let k = a.ty[i] as usize * 3 + a.ty[j] as usize;
            if rsq < pp.rcsq()[k] {
                sum += pp.weight(k, rsq);
            }
        }
        let d = pp.complete(a.ty[i] as usize, sum);
        assert!((got - d).abs() <= 1e-12 * d, "atom {i}: {got} vs {d}");
    }
    assert!(energy.is_finite() && energy != 0.0);
    let out = evaluate(&a, 1.2, |at, l, st, f, t| {
        // SAFETY: `rho` holds nall doubles.
        unsafe { dpdnl_pair_compute(h.0, at, l, st, rho.as_ptr(), f, t) }
    });
    let scale = out.f.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for d in 0..3 {
        let p: f64 = (0..a.nlocal).map(|i| out.f[3 * i + d]).sum();
        assert!(
            p.abs() <= 1e-12 * scale * a.nlocal as f64,
            "momentum {d}: {p}"
        );
    }
}

#[test]
fn bad_calls_give_codes_and_text() {
    assert!(
        new_style("lj/cut", &["2.5"], 1)
            .unwrap_err()
            .contains("not supported")
    );
    assert!(
        new_style("dpd/nonlinear", &["1.0"], 1)
            .unwrap_err()
            .contains("missing arguments")
    );
    let h = dpd_handle("dot", "plain");
    assert!(coeff(&h, 2, &["1", "3", "1", "1", "0"]).is_err());
    // The same style again: coefficients kept, cut-offs reset to the new global (LAMMPS's rule).
    let (_c, p) = cwords(&["0.7", "0.8", "5", "friction", "dot"]);
    // SAFETY: a live handle; valid strings.
    assert_eq!(
        unsafe { dpdnl_pair_settings(h.0, p.len() as i32, p.as_ptr()) },
        DpdnlStatus::Ok
    );
    assert_eq!(init(&h, 10, 27.0).expect("init"), 0.8);
    // Friction none with a γ1 kept from the earlier settings is refused (the grammar's rule).
    let (_c, p) = cwords(&["0.7", "0.8", "5"]);
    // SAFETY: as above.
    let st = unsafe { dpdnl_pair_settings(h.0, p.len() as i32, p.as_ptr()) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(
        last_error().contains("must be 0 with friction none"),
        "{}",
        last_error()
    );
    // A pre-pass on a style without one, a compute before set-up, null pointers.
    let d = dpd_handle("dot", "plain");
    let mut v = [0.0; 4];
    // SAFETY: null atoms/list are refused before use.
    let st = unsafe { dpdnl_pair_prepass(d.0, null(), null(), 1, v.as_mut_ptr()) };
    assert_eq!(st, DpdnlStatus::NullPointer);
    // SAFETY: null handle.
    let st = unsafe { dpdnl_pair_coeff(null_mut(), 1, 0, null()) };
    assert_eq!(st, DpdnlStatus::NullPointer);
    let a = Atoms::new(5, 3.0, 1.2);
    let lists = a.half_list(1.2);
    let rows = CList::first(5, &lists);
    let atoms = a.c_atoms();
    let list = rows.view(0x3FFF_FFFF, false);
    let mut rho = vec![0.0; a.nall()];
    // SAFETY: arrays as documented.
    let st = unsafe { dpdnl_pair_prepass(d.0, &atoms, &list, 1, rho.as_mut_ptr()) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(last_error().contains("has not run"), "{}", last_error());
    init(&d, 5, 27.0).unwrap();
    // SAFETY: as above.
    let st = unsafe { dpdnl_pair_prepass(d.0, &atoms, &list, 1, rho.as_mut_ptr()) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(last_error().contains("no pre-pass"), "{}", last_error());
}

#[test]
fn style_registry_names_every_style() {
    let n = dpdnl_pair_style_count();
    let names: Vec<String> = (0..n)
        .map(|k| {
            // SAFETY: a static string for k in range.
            unsafe { CStr::from_ptr(dpdnl_pair_style_name(k)) }
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    // The library's registry, in its order (a new style needs no edit here).
    let registry: Vec<&str> = dpdnl::forces::PAIR_STYLES.iter().map(|s| s.name).collect();
    assert_eq!(names, registry);
    assert!(registry.starts_with(&["dpd/nonlinear", "sdpd", "mdpd/nonlinear"]));
    // SAFETY: a static string.
    let info = unsafe { CStr::from_ptr(dpdnl_pair_style_info(1)) }
        .to_string_lossy()
        .into_owned();
    assert!(info.starts_with("pair_style sdpd (dpdnl: "), "{info}");
    assert!(dpdnl_pair_style_name(n).is_null() && dpdnl_pair_style_name(-1).is_null());
    assert!(dpdnl_pair_style_info(n).is_null());
    // Each name makes a handle (its own grammar answers, not the unknown-style error).
    for name in &names {
        let e = new_style(name, &[], 1).unwrap_err();
        assert!(!e.contains("not supported"), "{name}: {e}");
    }
}

#[test]
fn lammps_style_list_names_the_fixes_and_computes() {
    assert!(dpdnl_pair_style_count() <= DPDNL_PAIR_STYLE_SLOTS);
    let text = |p: *const std::ffi::c_char| {
        // SAFETY: a static string of the list.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    };
    let n = dpdnl_lammps_style_count();
    let listed: Vec<(String, String, String)> = (0..n)
        .map(|k| {
            let e = dpdnl_lammps_style(k);
            (text(e.command), text(e.name), text(e.info))
        })
        .collect();
    let names: Vec<(&str, &str)> = listed
        .iter()
        .map(|(c, n, _)| (c.as_str(), n.as_str()))
        .collect();
    assert_eq!(
        names,
        [
            ("fix", "nve/euler"),
            ("fix", "pex/push"),
            ("fix", "flip/momentum"),
            ("compute", "sdpd/density"),
            ("fix", "dpdnl/frames")
        ]
    );
    for (command, name, info) in &listed {
        assert!(
            info.starts_with(&format!("{command} {name} (dpdnl: ")),
            "{info}"
        );
    }
    for k in [-1, n] {
        let e = dpdnl_lammps_style(k);
        assert!(e.command.is_null() && e.name.is_null() && e.info.is_null());
    }
}

/// The class (0 ordinary, 1–3 a 1-2, 1-3, 1-4 neighbour) this test gives the pair (i, j).
fn class_of(a: &Atoms, i: usize, j: usize) -> usize {
    let (ti, tj) = (a.tag[i] as usize, a.tag[j] as usize);
    (ti + tj) % 5 % 4
}

/// One force-only step (step 7, newton on, energy tallied) of `h` over the half list `lists`
/// of `a`, whose entries carry LAMMPS's special-bond bits (mask 0x1FFFFFFF): the forces on
/// every atom (owned and ghost, not folded) and the energy.
fn special_step(h: &Handle, a: &Atoms, lists: &[Vec<i32>]) -> (Vec<f64>, f64) {
    let rows = CList::first(a.nlocal, lists);
    let atoms = a.c_atoms();
    let list = rows.view(0x1FFF_FFFF, false);
    let st = step_seven();
    let mut f = vec![0.0; 3 * a.nall()];
    let mut energy = 0.0;
    let mut tally = DpdnlTally {
        eflag_global: 1,
        vflag_global: 0,
        eng_vdwl: &mut energy,
        virial: null_mut(),
        eatom: null_mut(),
        vatom: null_mut(),
    };
    // SAFETY: arrays as documented.
    let code =
        unsafe { dpdnl_pair_compute(h.0, &atoms, &list, &st, null(), f.as_mut_ptr(), &mut tally) };
    assert_eq!(code, DpdnlStatus::Ok, "{}", last_error());
    (f, energy)
}

#[test]
fn special_bonds_scale_a_pair_or_leave_it_out() {
    // special_bonds lj 0.5 0 0.25: 1-2 pairs at half strength (a, γ0 and σ² halved), 1-3
    // pairs left out, 1-4 at a quarter (docs/models.md §4.8, P-22).
    let special = [0.0, 0.5, 0.0, 0.25];
    let a = Atoms::new(60, 3.0, 1.2);
    let mut lists = a.half_list(1.2);
    for (i, l) in lists.iter_mut().enumerate() {
        for e in l.iter_mut() {
            *e |= (class_of(&a, i, *e as usize) as i32) << 30;
        }
    }
    for (fr, no) in MODELS {
        let h = dpd_handle(fr, no);
        let s = DpdnlSetup {
            dimension: 3,
            natoms: 60,
            volume: 27.0,
            mass: MASS.as_ptr(),
            dt: DT,
            euler: 0,
            special_lj: special.as_ptr(),
            units: lj_units(),
            substyle: 0,
            per_atom_mass: 0,
        };
        let mut rc = 0.0;
        // SAFETY: a live handle; `s` valid with 4 special factors.
        assert_eq!(
            unsafe { dpdnl_pair_init(h.0, &s, &mut rc) },
            DpdnlStatus::Ok
        );
        let (f, energy) = special_step(&h, &a, &lists);
        // The same pairs one by one through the kernel with scaled coefficients: f a, f γ0.
        let friction = dpdnl::forces::dpd::kernel::Friction::from_keyword(fr).unwrap();
        let noise = dpdnl::forces::dpd::kernel::Noise::from_keyword(no).unwrap();
        let model = dpdnl::forces::dpd::kernel::PairModel::new(
            0.7,
            friction,
            noise,
            dpdnl::forces::dpd::kernel::Weight::new(0.5).unwrap(),
            DT,
        );
        let g1 = |g: f64| if fr == "none" { 0.0 } else { g };
        let coeff = |ti: i32, tj: i32| {
            let (aa, g0, g, rc) = match (ti.min(tj), ti.max(tj)) {
                (1, 1) => (25.0, 4.5, g1(1.0), 1.0),
                (1, 2) => (10.0, 3.0, g1(0.5), 1.2),
                _ => (0.0, 5.0, g1(2.0), 0.9),
            };
            dpdnl::forces::dpd::kernel::PairCoeff {
                a: aa,
                gamma0: g0,
                gamma1: g,
                rc,
            }
        };
        let mut want = vec![0.0; 3 * a.nall()];
        let (mut e_want, mut left_out, mut scaled) = (0.0, 0, 0);
        for (i, l) in lists.iter().enumerate() {
            for &jr in l {
                let j = (jr & 0x1FFF_FFFF) as usize;
                let factor = [1.0, special[1], special[2], special[3]][class_of(&a, i, j)];
                let c = coeff(a.ty[i], a.ty[j]);
                let dr: [f64; 3] = [0, 1, 2].map(|d| a.x[3 * i + d] - a.x[3 * j + d]);
                if dr.iter().map(|x| x * x).sum::<f64>() >= c.rc * c.rc {
                    continue;
                }
                if factor == 0.0 {
                    left_out += 1;
                    continue;
                }
                scaled += usize::from(factor != 1.0);
                let c = dpdnl::forces::dpd::kernel::PairCoeff {
                    a: factor * c.a,
                    gamma0: factor * c.gamma0,
                    ..c
                };
                let input = dpdnl::forces::dpd::kernel::PairInput {
                    dr,
                    dv: [0, 1, 2].map(|d| a.v[3 * i + d] - a.v[3 * j + d]),
                    inv_mass_sum: 1.0 / MASS[a.ty[i] as usize] + 1.0 / MASS[a.ty[j] as usize],
                    xi: dpdnl::rng::pair_gaussian(SEED, 7, a.tag[i] as u32, a.tag[j] as u32),
                };
                let p = dpdnl::forces::dpd::kernel::pair_force(&model, &c, &input);
                let s = (p.fc + p.fd + p.fr + p.fa) * p.inv_r;
                for d in 0..3 {
                    want[3 * i + d] += s * dr[d];
                    want[3 * j + d] -= s * dr[d];
                }
                e_want += p.energy;
            }
        }
        assert!(
            left_out > 10 && scaled > 10,
            "{left_out} left out, {scaled} scaled"
        );
        let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in f.iter().zip(&want).enumerate() {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "{fr}/{no} f[{k}]: {x} vs {y}"
            );
        }
        assert!(
            (energy - e_want).abs() <= 1e-12 * e_want.abs(),
            "{energy} vs {e_want}"
        );
    }
}

#[test]
fn sdpd_refuses_fractional_special_factors() {
    let h = sdpd_handle();
    let mut rc = 0.0;
    for (special, ok) in [([0.0, 0.0, 1.0, 1.0], true), ([0.0, 1.0, 0.5, 1.0], false)] {
        let s = DpdnlSetup {
            dimension: 3,
            natoms: 60,
            volume: 27.0,
            mass: MASS.as_ptr(),
            dt: DT,
            euler: 0,
            special_lj: special.as_ptr(),
            units: lj_units(),
            substyle: 0,
            per_atom_mass: 0,
        };
        // SAFETY: a live handle; `s` valid.
        let st = unsafe { dpdnl_pair_init(h.0, &s, &mut rc) };
        assert_eq!(st == DpdnlStatus::Ok, ok, "{special:?}: {}", last_error());
    }
    assert!(
        last_error().contains("pair_style sdpd cannot weight bonded neighbours"),
        "{}",
        last_error()
    );
    // A factor outside [0, 1] is refused for every style.
    let d = dpd_handle("dot", "plain");
    let special = [0.0, 1.5, 0.0, 0.0];
    let s = DpdnlSetup {
        dimension: 3,
        natoms: 60,
        volume: 27.0,
        mass: MASS.as_ptr(),
        dt: DT,
        euler: 0,
        special_lj: special.as_ptr(),
        units: lj_units(),
        substyle: 0,
        per_atom_mass: 0,
    };
    // SAFETY: as above.
    assert_eq!(
        unsafe { dpdnl_pair_init(d.0, &s, &mut rc) },
        DpdnlStatus::InvalidArgument
    );
    assert!(
        last_error().contains("must be in [0, 1]"),
        "{}",
        last_error()
    );
}

/// One evaluation of the thread test: every array as the entry point left it (ghosts not
/// folded), from non-zero starting values so that the order of the additions shows.
#[derive(Debug)]
struct Sums {
    f: Vec<f64>,
    energy: f64,
    virial: [f64; 6],
    eatom: Vec<f64>,
    vatom: Vec<f64>,
}

impl Sums {
    fn bits(&self) -> Vec<u64> {
        let mut all = self.f.clone();
        all.push(self.energy);
        all.extend(self.virial);
        all.extend(&self.eatom);
        all.extend(&self.vatom);
        all.iter().map(|x| x.to_bits()).collect()
    }
}

/// `dpdnl_pair_compute` of `h` on `threads` threads over the rows `ilist` of `lists`.
#[allow(clippy::too_many_arguments)]
fn compute_threads(
    h: &Handle,
    a: &Atoms,
    ilist: &[i32],
    lists: &[Vec<i32>],
    full: bool,
    newton: bool,
    values: &[f64],
    threads: i32,
    tallies: bool,
) -> Sums {
    let rows = CList::new(ilist.to_vec(), lists);
    compute_list(
        h,
        a,
        &rows,
        (full, newton),
        values,
        threads,
        tallies,
        (0, 0.0),
        11,
    )
}

/// [`compute_threads`] with the list's build number and skin (`copy`: LAMMPS's
/// `neighbor->ncalls` and `skin`; 0 walks the list itself) at `step`.
#[allow(clippy::too_many_arguments)]
fn compute_list(
    h: &Handle,
    a: &Atoms,
    rows: &CList,
    (full, newton): (bool, bool),
    values: &[f64],
    threads: i32,
    tallies: bool,
    copy: (i64, f64),
    step: i64,
) -> Sums {
    // SAFETY: a live handle.
    let st = unsafe { dpdnl_pair_threads(h.0, threads) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    let n = a.nall();
    let start = |k: u32, len: usize| -> Vec<f64> {
        (0..len as u32).map(|i| uniform(k, i, -1.0, 1.0)).collect()
    };
    let mut s = Sums {
        f: start(1, 3 * n),
        energy: 0.375,
        virial: [0.1, -0.2, 0.3, -0.4, 0.5, -0.6],
        eatom: start(2, n),
        vatom: start(3, 6 * n),
    };
    let atoms = a.c_atoms();
    let list = DpdnlNeighList {
        build: copy.0,
        skin: copy.1,
        ..rows.view(0x1FFF_FFFF, full)
    };
    let st = DpdnlStep {
        step,
        dt: DT,
        newton_pair: i32::from(newton),
        dimension: 3,
        boxlen: [0.0; 3],
        tilt: [0.0; 3],
        periodic: [0; 3],
        beginstep: 0,
        endstep: 0,
    };
    // Without tallies: a force-only step (the threaded walk's event path).
    let mut tally = if tallies {
        DpdnlTally {
            eflag_global: 1,
            vflag_global: 1,
            eng_vdwl: &mut s.energy,
            virial: s.virial.as_mut_ptr(),
            eatom: s.eatom.as_mut_ptr(),
            vatom: s.vatom.as_mut_ptr(),
        }
    } else {
        DpdnlTally {
            eflag_global: 0,
            vflag_global: 0,
            eng_vdwl: null_mut(),
            virial: null_mut(),
            eatom: null_mut(),
            vatom: null_mut(),
        }
    };
    // SAFETY: arrays as documented; `values` holds nall doubles or is unused.
    let code = unsafe {
        dpdnl_pair_compute(
            h.0,
            &atoms,
            &list,
            &st,
            if values.is_empty() {
                null()
            } else {
                values.as_ptr()
            },
            s.f.as_mut_ptr(),
            &mut tally,
        )
    };
    assert_eq!(code, DpdnlStatus::Ok, "{}", last_error());
    s
}

/// A launcher that is there ([`DpdnlLaunch`] without its null).
type LaunchFn = unsafe extern "C" fn(DpdnlTeamBody, *mut c_void, i32);

/// A host's launcher on scoped threads, one per team member (what the LAMMPS styles' OpenMP
/// parallel region does).
unsafe extern "C" fn scoped_launch(body: DpdnlTeamBody, ctx: *mut c_void, n: i32) {
    let (Some(body), ctx) = (body, ctx as usize) else {
        return;
    };
    std::thread::scope(|s| {
        for t in 0..n {
            // SAFETY: DpdnlLaunch's contract: `ctx` is valid until this launch returns.
            s.spawn(move || unsafe { body(ctx as *mut c_void, t) });
        }
    });
}

/// A host's launcher that runs only the calling thread (an OpenMP runtime may give fewer
/// threads than asked).
unsafe extern "C" fn one_thread_launch(body: DpdnlTeamBody, ctx: *mut c_void, _n: i32) {
    if let Some(body) = body {
        // SAFETY: DpdnlLaunch's contract.
        unsafe { body(ctx, 0) };
    }
}

#[test]
fn threads_give_the_same_bits_as_one() {
    // 2600 atoms with ghosts (rows in three windows of the threaded walk), rows in a shuffled
    // order, half lists (newton on and off) and a full list, bonded neighbours flagged on a
    // third of the entries (special_bonds lj 0.5 0 0.25 for dpd/nonlinear: scaled, left out;
    // factors 1 for sdpd), all tallies on.
    let a = Atoms::new(2600, 8.6, 1.2);
    let n = a.nlocal;
    let ilist: Vec<i32> = (0..n).map(|k| ((k * 7919) % n) as i32).collect();
    let flagged = |lists: Vec<Vec<i32>>| -> Vec<Vec<i32>> {
        lists
            .into_iter()
            .enumerate()
            .map(|(i, l)| {
                l.into_iter()
                    .map(|j| j | ((class_of(&a, i, j as usize) as i32) << 30))
                    .collect()
            })
            .collect()
    };
    let half = flagged(a.half_list(1.2));
    let full: Vec<Vec<i32>> = flagged(
        (0..n)
            .map(|i| {
                (0..a.nall())
                    .filter(|&j| {
                        let rsq: f64 = (0..3)
                            .map(|d| (a.x[3 * i + d] - a.x[3 * j + d]).powi(2))
                            .sum();
                        j != i && rsq < 1.2 * 1.2
                    })
                    .map(|j| j as i32)
                    .collect()
            })
            .collect(),
    );
    let special = [0.0, 0.5, 0.0, 0.25];
    let setup = |h: &Handle, special: Option<&[f64; 4]>| {
        let s = DpdnlSetup {
            dimension: 3,
            natoms: n as i64,
            volume: 8.6 * 8.6 * 8.6,
            mass: MASS.as_ptr(),
            dt: DT,
            euler: 0,
            special_lj: special.map_or(null(), |s| s.as_ptr()),
            units: lj_units(),
            substyle: 0,
            per_atom_mass: 0,
        };
        let mut rc = 0.0;
        // SAFETY: a live handle; `s` valid, 4 special factors when not null.
        let st = unsafe { dpdnl_pair_init(h.0, &s, &mut rc) };
        assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    };
    let rho: Vec<f64> = (0..a.nall())
        .map(|g| uniform(a.owner[g] as u32, 9, 1.8, 2.6))
        .collect();
    let mut cases = Vec::new();
    for (fr, no) in [("dot", "twostep"), ("none", "plain")] {
        let h = dpd_handle(fr, no);
        setup(&h, Some(&special));
        cases.push((format!("dpd/nonlinear {fr}/{no}"), h, Vec::new()));
    }
    let h = sdpd_handle();
    setup(&h, None);
    cases.push(("sdpd".to_string(), h, rho));
    for (label, h, values) in &cases {
        for (lists, full, newton) in [
            (&half, false, true),
            (&half, false, false),
            (&full, true, false),
        ] {
            let one = compute_threads(h, &a, &ilist, lists, full, newton, values, 1, true);
            // (sDPD's energy is its pre-pass's: the pair pass adds none.)
            assert!(one.virial[0] != 0.1, "{label}: nothing tallied");
            // Force-only steps (no tallies) give the forces of the tallied step.
            let forces = compute_threads(h, &a, &ilist, lists, full, newton, values, 1, false);
            let f_bits = |s: &Sums| s.f.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert!(
                f_bits(&forces) == f_bits(&one),
                "{label}: forces depend on tallying"
            );
            // dpdnl's own pool, then the host's threads (all, or fewer than asked).
            for (host, launch) in [
                ("pool", None),
                ("host", Some(scoped_launch as LaunchFn)),
                ("host, 1 of them", Some(one_thread_launch as LaunchFn)),
            ] {
                // SAFETY: a live handle; the launchers keep DpdnlLaunch's contract.
                let st = unsafe { dpdnl_pair_launcher(h.0, launch) };
                assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
                for threads in [2, 3, 1] {
                    for tallies in [true, false] {
                        let got = compute_threads(
                            h, &a, &ilist, lists, full, newton, values, threads, tallies,
                        );
                        let want = if tallies { &one } else { &forces };
                        assert!(
                            got.bits() == want.bits(),
                            "{label}, full {full}, newton {newton}, tallies {tallies}: \
                             {threads} threads ({host}) differ from 1"
                        );
                    }
                }
            }
            // SAFETY: a live handle.
            assert_eq!(unsafe { dpdnl_pair_launcher(h.0, None) }, DpdnlStatus::Ok);
        }
    }
    // Counts outside 1..=1024 are refused.
    let h = &cases[0].1;
    for bad in [0, -1, 1025] {
        // SAFETY: a live handle.
        let st = unsafe { dpdnl_pair_threads(h.0, bad) };
        assert_eq!(st, DpdnlStatus::InvalidArgument);
        assert!(last_error().contains("threads"), "{}", last_error());
    }
}

#[test]
fn the_working_copy_of_the_list_gives_the_same_bits_as_the_list() {
    // A LAMMPS list of skin 0.6 (cut-off 1.2) taken once, then 60 calls while the atoms move:
    // slowly (0.006 a call at most), and atom 0 straight at an atom 1.65 away, which is in the
    // list but beyond the copy's margin (0.2) when the copy is first taken (call 11), so the
    // pair comes into range (calls 23-33) only through the copy's refreshes. At call 45 the
    // list is built again (a new build number).
    // A handle that keeps the copy (build >= 1) against one that walks the list (build 0),
    // on 1 and 2 threads, force-only and tallied calls: every bit the same.
    let skin = 0.6;
    let mut a = Atoms::new(900, 6.0, 1.2 + skin);
    let n = a.nlocal;
    let ilist: Vec<i32> = (0..n as i32).collect();
    let dist = |a: &Atoms, i: usize, j: usize| -> f64 {
        (0..3)
            .map(|d| (a.x[3 * i + d] - a.x[3 * j + d]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let target = (1..a.nall())
        .filter(|&j| a.owner[j] != 0)
        .min_by(|&p, &q| {
            (dist(&a, 0, p) - 1.65)
                .abs()
                .total_cmp(&(dist(&a, 0, q) - 1.65).abs())
        })
        .expect("a partner");
    let r0 = dist(&a, 0, target);
    assert!((1.55..1.75).contains(&r0), "partner at {r0}");
    let toward: Vec<f64> = (0..3)
        .map(|d| (a.x[3 * target + d] - a.x[d]) / r0)
        .collect();
    let (plain, copying) = (dpd_handle("dot", "twostep"), dpd_handle("dot", "twostep"));
    for h in [&plain, &copying] {
        init(h, n as i64, 216.0).expect("init");
    }
    // The list's arrays stay where they are until it is built again, as in LAMMPS (a copy is
    // kept only while the pointers are the same).
    let mut lists = a.half_list(1.2 + skin);
    let mut rows = CList::new(ilist.clone(), &lists);
    let mut build = 1;
    let mut in_range = false;
    for call in 0..60i64 {
        if call == 45 {
            lists = a.half_list(1.2 + skin);
            rows = CList::new(ilist.clone(), &lists);
            build += 1;
        }
        let threads = if call % 20 < 10 { 1 } else { 2 };
        let tallies = call % 3 == 0;
        let want = compute_list(
            &plain,
            &a,
            &rows,
            (false, true),
            &[],
            threads,
            tallies,
            (0, 0.0),
            call,
        );
        let got = compute_list(
            &copying,
            &a,
            &rows,
            (false, true),
            &[],
            threads,
            tallies,
            (build, skin),
            call,
        );
        assert!(
            got.bits() == want.bits(),
            "call {call} ({threads} threads, tallies {tallies}): the copy's walk differs"
        );
        in_range |= dist(&a, 0, target) < 1.0;
        // Move: every owner by up to 0.006 per axis, atom 0 by 0.02 towards its partner; each
        // ghost with its owner.
        let step: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let k = (i as u32) * 3 + call as u32 * 7919;
                let mut d = [0, 1, 2].map(|c| uniform(k, 300 + c, -0.006, 0.006));
                if i == 0 {
                    for (c, t) in d.iter_mut().zip(&toward) {
                        *c = 0.02 * t;
                    }
                }
                d
            })
            .collect();
        for g in 0..a.nall() {
            for (x, s) in a.x[3 * g..3 * g + 3].iter_mut().zip(step[a.owner[g]]) {
                *x += s;
            }
        }
    }
    assert!(in_range, "atom 0 never reached its partner's cut-off");
}

/// A `dpd/nonlinear/ext` handle of two types (friction `fr`, noise `no`).
fn ext_handle(fr: &str, no: &str) -> Handle {
    let seed = SEED.to_string();
    let h = new_style(
        "dpd/nonlinear/ext",
        &["0.7", "1.0", &seed, "friction", fr, "noise", no],
        2,
    )
    .expect("style");
    for line in [
        [
            "1", "1", "25", "4.5", "2.0", "1.0", "0.5", "1.0", "gamma1", "1.0",
        ],
        [
            "1", "2", "10", "3.0", "1.0", "1.0", "1.0", "1.2", "gamma1", "0.5",
        ],
        [
            "2", "2", "0", "5.0", "3.0", "0.5", "1.0", "0.9", "gamma1", "2.0",
        ],
    ] {
        coeff(&h, 2, &line).expect("coeff");
    }
    h
}

#[test]
fn threads_give_the_same_bits_over_a_long_lived_list() {
    // 1500 atoms whose rows run along x (so the threads' blocks are slabs: most atoms are one
    // block's alone, the rest shared), 40 calls while the atoms move, on 1, 2 and 3 threads,
    // each count on its own handle kept for all the calls; the list built again at call 15,
    // and changed in place at call 28 (same rows, same addresses and lengths: a pair of the
    // first row now reaches the last row's atom, moved beside it). dpd/nonlinear walks the list
    // as it is, dpd/nonlinear/ext its working copy. Half lists, newton on and
    // off, and a full list; tallies on every fourth call. Every bit the same.
    let skin = 0.4;
    let cut = 1.2 + skin;
    for (kind, full, newton) in [
        (ListKind::HalfNewtonOn, false, true),
        (ListKind::HalfNewtonOff, false, false),
        (ListKind::Full, true, false),
    ] {
        let mut a = Atoms::new(1500, 7.5, cut);
        let n = a.nlocal;
        let mut ilist: Vec<i32> = (0..n as i32).collect();
        ilist.sort_by(|&p, &q| a.x[3 * p as usize].total_cmp(&a.x[3 * q as usize]));
        // dpd/nonlinear on LAMMPS's list, dpd/nonlinear/ext (non-central forces) on the copy.
        let handles: Vec<Vec<Handle>> = [dpd_handle, ext_handle]
            .iter()
            .map(|make| {
                (0..3)
                    .map(|_| {
                        let h = make("dot", "twostep");
                        init(&h, n as i64, 7.5f64.powi(3)).expect("init");
                        h
                    })
                    .collect()
            })
            .collect();
        let mut lists = a.list(kind, cut);
        let mut rows = CList::new(ilist.clone(), &lists);
        let mut build = 1;
        for call in 0..40i64 {
            if call == 15 {
                lists = a.list(kind, cut);
                rows = CList::new(ilist.clone(), &lists);
                build += 1;
            }
            if call == 28 {
                let (p, q) = (ilist[0] as usize, ilist[n - 1] as usize);
                let row = &mut lists[p];
                assert!(!row.is_empty(), "row {p} is empty");
                row[0] = q as i32 | (1 << 30);
                for d in 0..3 {
                    a.x[3 * q + d] = a.x[3 * p + d] + [0.5, 0.1, -0.1][d];
                }
            }
            let tallies = call % 4 == 0;
            for (family, copy) in handles.iter().zip([(0, 0.0), (build, skin)]) {
                let sums: Vec<Sums> = family
                    .iter()
                    .zip(1..)
                    .map(|(h, threads)| {
                        compute_list(
                            h,
                            &a,
                            &rows,
                            (full, newton),
                            &[],
                            threads,
                            tallies,
                            copy,
                            call,
                        )
                    })
                    .collect();
                for (s, threads) in sums.iter().zip(1..).skip(1) {
                    assert!(
                        s.bits() == sums[0].bits(),
                        "{kind:?} call {call} (build {}, tallies {tallies}): {threads} threads \
                         differ from 1",
                        copy.0
                    );
                }
            }
            let step: Vec<[f64; 3]> = (0..n)
                .map(|i| {
                    let k = (i as u32) * 3 + call as u32 * 7919;
                    [0, 1, 2].map(|c| uniform(k, 400 + c, -0.01, 0.01))
                })
                .collect();
            for g in 0..a.nall() {
                for (x, s) in a.x[3 * g..3 * g + 3].iter_mut().zip(step[a.owner[g]]) {
                    *x += s;
                }
            }
        }
    }
}

/// `pair_style hybrid` on a subset of type pairs (issue 42): as a sub-style the pairs without
/// coefficients belong to other styles and get no force (the same bits as the pair given zero
/// coefficients), the largest cut-off is over the style's own pairs; as the top-level style the
/// same coefficients are refused as before; a sub-style with no pair, (η, Sc) targets on a
/// subset, sDPD on a cross pair without its types' own lines and single() of a pair not the
/// style's are refused, each naming why.
#[test]
fn a_substyle_covers_a_subset_of_type_pairs() {
    let a = Atoms::new(60, 3.0, 1.2);
    let style = ["0.7", "1.0", "4242", "friction", "none"];
    let subset = new_style("dpd/nonlinear", &style, 2).expect("style");
    coeff(&subset, 2, &["1", "1", "25", "4.5", "0", "1.0"]).unwrap();
    coeff(&subset, 2, &["2", "2", "10", "3.0", "0", "0.9"]).unwrap();
    let top = init_as(&subset, 60, 27.0, lj_units(), 0).unwrap_err();
    assert!(top.contains("types 1 2 are not set (pair_coeff)"), "{top}");
    assert!(top.contains("as the top-level pair style"), "{top}");
    assert!(
        top.contains("under pair_style hybrid or hybrid/overlay"),
        "{top}"
    );
    assert_eq!(
        init_as(&subset, 60, 27.0, lj_units(), 1).expect("sub-style"),
        1.0
    );
    let zero = new_style("dpd/nonlinear", &style, 2).expect("style");
    coeff(&zero, 2, &["1", "1", "25", "4.5", "0", "1.0"]).unwrap();
    coeff(&zero, 2, &["2", "2", "10", "3.0", "0", "0.9"]).unwrap();
    coeff(&zero, 2, &["1", "2", "0", "0", "0", "1.2"]).unwrap();
    assert_eq!(init(&zero, 60, 27.0).expect("all set"), 1.2);
    let [mine, theirs] = [&subset, &zero].map(|h| {
        evaluate(&a, 1.2, |at, l, st, f, t| {
            // SAFETY: arrays sized as documented, alive across the call.
            unsafe { dpdnl_pair_compute(h.0, at, l, st, null(), f, t) }
        })
    });
    assert!(mine.f.iter().any(|&x| x != 0.0));
    assert_eq!(mine.f, theirs.f);
    assert_eq!((mine.energy, mine.virial), (theirs.energy, theirs.virial));
    // single() of a pair of another style.
    let (mut f, mut e) = (0.0, 0.0);
    // SAFETY: a live handle; out pointers valid.
    let st = unsafe { dpdnl_pair_single(subset.0, 1, 2, 0.36, 1.0, &mut f, &mut e) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(
        last_error().contains("no coefficients for types 1 2"),
        "{}",
        last_error()
    );
    // A sub-style with no pair at all.
    let bare = new_style("dpd/nonlinear", &style, 2).expect("style");
    let e = init_as(&bare, 60, 27.0, lj_units(), 1).unwrap_err();
    assert!(e.contains("has no type pair"), "{e}");
    // (η, Sc) targets: the design is for the whole fluid.
    let designed = new_style("dpd/nonlinear", &style, 2).expect("style");
    coeff(&designed, 2, &["1", "1", "25", "eta", "0.5", "sc", "3"]).unwrap();
    let e = init_as(&designed, 60, 27.0, lj_units(), 1).unwrap_err();
    assert!(e.contains("give gamma0 instead of eta and sc"), "{e}");
    // sDPD: a type's equation of state is its own line's; type 3 outside the style is inert.
    let sdpd = || {
        let h = new_style("sdpd", &["1.0", "1.0", "4242"], 3).expect("sdpd");
        coeff(&h, 3, &["1", "1", "3.0", "10.0", "1.0", "1.0"]).unwrap();
        h
    };
    let cross = sdpd();
    coeff(&cross, 3, &["1", "2", "3.0", "10.0", "1.0", "1.0"]).unwrap();
    let e = init_sdpd(&cross, 1).unwrap_err();
    assert!(e.contains("covers type pair 2 1 but not 2 2"), "{e}");
    let own = sdpd();
    assert!(
        init_sdpd(&own, 0)
            .unwrap_err()
            .contains("types 1 2 are not set")
    );
    assert_eq!(init_sdpd(&own, 1).expect("sdpd on 1 1 only"), 1.0);
}

/// Set-up of a 3-type sDPD handle (masses 1, 1, 2), top-level (0) or a sub-style (1).
fn init_sdpd(h: &Handle, substyle: i32) -> Result<f64, String> {
    let mass = [0.0, 1.0, 1.0, 2.0];
    let s = DpdnlSetup {
        dimension: 3,
        natoms: 60,
        volume: 27.0,
        mass: mass.as_ptr(),
        dt: DT,
        euler: 0,
        special_lj: null(),
        units: lj_units(),
        substyle,
        per_atom_mass: 0,
    };
    init_with(h, &s)
}

/// `dpdnl_pair_special` (issue 42: `pair_modify pair NAME special lj …` under `pair_style
/// hybrid`, in force only around the sub-style's compute): a handle set up with other factors
/// and given the new ones before the evaluation gives the bits of a handle set up with them; a
/// style that cannot weight bonded neighbours refuses fractional factors there too.
#[test]
fn special_factors_given_before_a_compute_rebuild_the_blocks() {
    let special = [0.0, 0.5, 0.0, 0.25];
    let a = Atoms::new(60, 3.0, 1.2);
    let mut lists = a.half_list(1.2);
    for (i, l) in lists.iter_mut().enumerate() {
        for e in l.iter_mut() {
            *e |= (class_of(&a, i, *e as usize) as i32) << 30;
        }
    }
    let forces = |h: &Handle, at_setup: [f64; 4], before: Option<[f64; 4]>| {
        let s = DpdnlSetup {
            dimension: 3,
            natoms: 60,
            volume: 27.0,
            mass: MASS.as_ptr(),
            dt: DT,
            euler: 0,
            special_lj: at_setup.as_ptr(),
            units: lj_units(),
            substyle: 1,
            per_atom_mass: 0,
        };
        let mut rc = 0.0;
        // SAFETY: a live handle; `s` valid with 4 special factors.
        assert_eq!(
            unsafe { dpdnl_pair_init(h.0, &s, &mut rc) },
            DpdnlStatus::Ok
        );
        if let Some(f) = before {
            // SAFETY: a live handle; 4 factors.
            let st = unsafe { dpdnl_pair_special(h.0, f.as_ptr()) };
            assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
        }
        // SAFETY: a live handle; null changes nothing.
        assert_eq!(unsafe { dpdnl_pair_special(h.0, null()) }, DpdnlStatus::Ok);
        let (f, energy) = special_step(h, &a, &lists);
        (f, energy)
    };
    for (fr, no) in MODELS {
        let set_up = forces(&dpd_handle(fr, no), special, None);
        let given = forces(&dpd_handle(fr, no), [0.0, 0.75, 0.5, 1.0], Some(special));
        let plain = forces(&dpd_handle(fr, no), [0.0, 0.75, 0.5, 1.0], None);
        assert_eq!(set_up, given, "{fr}/{no}");
        assert_ne!(
            set_up.0, plain.0,
            "{fr}/{no}: the factors change the forces"
        );
    }
    let h = sdpd_handle();
    let ones = [0.0, 1.0, 1.0, 1.0];
    let s = DpdnlSetup {
        dimension: 3,
        natoms: 60,
        volume: 27.0,
        mass: MASS.as_ptr(),
        dt: DT,
        euler: 0,
        special_lj: ones.as_ptr(),
        units: lj_units(),
        substyle: 0,
        per_atom_mass: 0,
    };
    let mut rc = 0.0;
    // SAFETY: a live handle; `s` valid.
    assert_eq!(
        unsafe { dpdnl_pair_init(h.0, &s, &mut rc) },
        DpdnlStatus::Ok
    );
    // SAFETY: a live handle; 4 factors.
    let st = unsafe { dpdnl_pair_special(h.0, special.as_ptr()) };
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(
        last_error().contains("cannot weight bonded neighbours"),
        "{}",
        last_error()
    );
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum ListKind {
    HalfNewtonOn,
    HalfNewtonOff,
    Full,
}

/// One evaluation over a list of `kind`, ghosts folded into their owners (reverse
/// communication), with per-atom tallies.
struct Run {
    f: Vec<f64>,
    energy: f64,
    virial: [f64; 6],
    eatom: Vec<f64>,
    vatom: Vec<f64>,
}

fn run(h: &Handle, s: &Atoms, kind: ListKind, cut: f64, step: i64) -> Run {
    let lists = s.list(kind, cut);
    let ilist: Vec<i32> = (0..s.nlocal as i32).collect();
    let numneigh: Vec<i32> = lists.iter().map(|l| l.len() as i32).collect();
    let firstneigh: Vec<*const i32> = lists.iter().map(|l| l.as_ptr()).collect();
    let atoms = DpdnlAtoms {
        x: s.x.as_ptr(),
        v: s.v.as_ptr(),
        tag: s.tag.as_ptr(),
        atom_type: s.ty.as_ptr(),
        mass: MASS.as_ptr(),
        rmass: null(),
        nlocal: s.nlocal as i32,
        nall: s.nall() as i32,
    };
    let list = DpdnlNeighList {
        inum: s.nlocal as i32,
        ilist: ilist.as_ptr(),
        numneigh: numneigh.as_ptr(),
        firstneigh: firstneigh.as_ptr(),
        neighmask: 0x3FFF_FFFF,
        full: (kind == ListKind::Full) as i32,
        build: 0,
        skin: 0.0,
    };
    let st = DpdnlStep {
        step,
        dt: DT,
        newton_pair: (kind == ListKind::HalfNewtonOn) as i32,
        dimension: 3,
        boxlen: [0.0; 3],
        tilt: [0.0; 3],
        periodic: [0; 3],
        beginstep: 0,
        endstep: 0,
    };
    let mut r = Run {
        f: vec![0.0; 3 * s.nall()],
        energy: 0.0,
        virial: [0.0; 6],
        eatom: vec![0.0; s.nall()],
        vatom: vec![0.0; 6 * s.nall()],
    };
    let mut tally = DpdnlTally {
        eflag_global: 1,
        vflag_global: 1,
        eng_vdwl: &mut r.energy,
        virial: r.virial.as_mut_ptr(),
        eatom: r.eatom.as_mut_ptr(),
        vatom: r.vatom.as_mut_ptr(),
    };
    // SAFETY: every array is sized as documented and lives across the call.
    let code = unsafe {
        dpdnl_pair_compute(
            h.0,
            &atoms,
            &list,
            &st,
            null(),
            r.f.as_mut_ptr(),
            &mut tally,
        )
    };
    assert_eq!(code, DpdnlStatus::Ok, "{}", last_error());
    // Reverse communication: fold ghost forces and per-atom tallies into the owners.
    for g in s.nlocal..s.nall() {
        let o = s.owner[g];
        for d in 0..3 {
            r.f[3 * o + d] += r.f[3 * g + d];
        }
        r.eatom[o] += r.eatom[g];
        for d in 0..6 {
            r.vatom[6 * o + d] += r.vatom[6 * g + d];
        }
    }
    r.f.truncate(3 * s.nlocal);
    r.eatom.truncate(s.nlocal);
    r.vatom.truncate(6 * s.nlocal);
    r
}

fn assert_close(a: &[f64], b: &[f64], what: &str) {
    let scale = a.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-12 * scale,
            "{what}[{k}]: {x} vs {y} (scale {scale})"
        );
    }
}

#[test]
fn newton_on_off_and_full_lists_agree() {
    let (len, cut) = (3.0, 1.2);
    let s = Atoms::new(60, len, cut);
    let h = dpd_handle("dot", "twostep");
    init(&h, 60, 27.0).expect("init");
    let on = run(&h, &s, ListKind::HalfNewtonOn, cut, 3);
    for kind in [ListKind::HalfNewtonOff, ListKind::Full] {
        let other = run(&h, &s, kind, cut, 3);
        assert_close(&other.f, &on.f, &format!("{kind:?} force"));
        assert_close(&[other.energy], &[on.energy], &format!("{kind:?} energy"));
        assert_close(&other.virial, &on.virial, &format!("{kind:?} virial"));
        assert_close(&other.eatom, &on.eatom, &format!("{kind:?} eatom"));
        assert_close(&other.vatom, &on.vatom, &format!("{kind:?} vatom"));
    }
    let esum: f64 = on.eatom.iter().sum();
    assert_close(&[esum], &[on.energy], "sum of per-atom energies");
}

fn status_of(f: impl FnOnce() -> DpdnlStatus) -> (DpdnlStatus, String) {
    let st = f();
    (st, last_error())
}

#[test]
fn bad_compute_arguments_give_codes_and_text() {
    let h = dpd_handle("cross", "plain");
    init(&h, 2, 27.0).expect("init");
    let x = [0.0, 0.0, 0.0, 0.5, 0.0, 0.0];
    let v = [0.0; 6];
    let tag = [1, 2];
    let mut f = [0.0; 6];
    let neigh: [i32; 1] = [1];
    let firstneigh = [neigh.as_ptr(), null()];
    let numneigh = [1, 0];
    let ilist = [0, 1];
    let good_atoms = |ty: &[i32; 2]| DpdnlAtoms {
        x: x.as_ptr(),
        v: v.as_ptr(),
        tag: tag.as_ptr(),
        atom_type: ty.as_ptr(),
        mass: MASS.as_ptr(),
        rmass: null(),
        nlocal: 2,
        nall: 2,
    };
    let list = DpdnlNeighList {
        inum: 2,
        ilist: ilist.as_ptr(),
        numneigh: numneigh.as_ptr(),
        firstneigh: firstneigh.as_ptr(),
        build: 0,
        skin: 0.0,
        neighmask: 0x3FFF_FFFF,
        full: 0,
    };
    let step = |s, dt, dim| DpdnlStep {
        step: s,
        dt,
        newton_pair: 1,
        dimension: dim,
        boxlen: [0.0; 3],
        tilt: [0.0; 3],
        periodic: [0; 3],
        beginstep: 0,
        endstep: 0,
    };
    let mut call = |a: &DpdnlAtoms, l: &DpdnlNeighList, st: &DpdnlStep| {
        // SAFETY: every array above is sized for nall = 2.
        status_of(|| unsafe {
            dpdnl_pair_compute(h.0, a, l, st, null(), f.as_mut_ptr(), null_mut())
        })
    };
    let ty_ok = [1, 2];
    let (st, msg) = call(&good_atoms(&ty_ok), &list, &step(0, 0.01, 3));
    assert_eq!(st, DpdnlStatus::Ok, "{msg}");
    for ((st, msg), want) in [
        (
            call(&good_atoms(&[1, 3]), &list, &step(0, 0.01, 3)),
            "type 3",
        ),
        (call(&good_atoms(&ty_ok), &list, &step(-1, 0.01, 3)), "step"),
        (call(&good_atoms(&ty_ok), &list, &step(0, 0.0, 3)), "dt"),
        (
            call(&good_atoms(&ty_ok), &list, &step(0, 0.01, 4)),
            "dimension",
        ),
    ] {
        assert_eq!(st, DpdnlStatus::InvalidArgument, "{msg}");
        assert!(msg.contains(want), "'{msg}' should mention {want}");
    }
    let far: [i32; 1] = [7];
    let bad_first = [far.as_ptr(), null()];
    let bad_list = DpdnlNeighList {
        firstneigh: bad_first.as_ptr(),
        ..list
    };
    let (st, msg) = call(&good_atoms(&ty_ok), &bad_list, &step(0, 0.01, 3));
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(msg.contains("neighbour index 7"), "{msg}");
    let null_x = DpdnlAtoms {
        x: null(),
        ..good_atoms(&ty_ok)
    };
    let (st, msg) = call(&null_x, &list, &step(0, 0.01, 3));
    assert_eq!(st, DpdnlStatus::NullPointer);
    assert!(msg.contains('x'), "{msg}");
    let zero_mass = [0.0, 1.0, 0.0];
    let bad_mass = DpdnlAtoms {
        mass: zero_mass.as_ptr(),
        ..good_atoms(&ty_ok)
    };
    let (st, msg) = call(&bad_mass, &list, &step(0, 0.01, 3));
    assert_eq!(st, DpdnlStatus::InvalidArgument);
    assert!(msg.contains("mass[2]"), "{msg}");
    // SAFETY: null pointers are reported, not dereferenced.
    let st = unsafe {
        dpdnl_pair_compute(
            null_mut(),
            null(),
            null(),
            null(),
            null(),
            null_mut(),
            null_mut(),
        )
    };
    assert_eq!(st, DpdnlStatus::NullPointer);
}

/// The style's own pair list (`dpdnl_pair_own_list`, issue 44) gives the forces, energy and
/// virial of LAMMPS's half list to round-off (the same pairs, summed in another order), for
/// every friction/noise pair; it needs the handle's set-up; `dpdnl_pair_list_choice` keeps
/// LAMMPS's list under hybrid and with `neigh_modify exclude`.
#[test]
fn the_own_list_gives_the_forces_of_the_lammps_list() {
    let a = Atoms::new(60, 3.0, 1.2);
    for (fr, no) in MODELS {
        let h = dpd_handle(fr, no);
        let mut nl = DpdnlNeighList {
            inum: 0,
            ilist: null(),
            numneigh: null(),
            firstneigh: null(),
            neighmask: 0,
            full: 0,
            build: 0,
            skin: 0.0,
        };
        // Before the set-up there are no cut-offs to build it for.
        let atoms = a.c_atoms();
        let st0 = step_seven();
        // SAFETY: arrays sized as documented, alive across the call.
        let code = unsafe { dpdnl_pair_own_list(h.0, &atoms, null(), &st0, 1, 0.3, &mut nl) };
        assert_eq!(code, DpdnlStatus::InvalidArgument);
        assert!(last_error().contains("dpdnl_pair_init"), "{}", last_error());
        assert_eq!(init(&h, 60, 27.0).expect("init"), 1.2);
        let theirs = evaluate(&a, 1.2, |at, l, st, f, t| {
            // SAFETY: arrays sized as documented, alive across the call.
            unsafe { dpdnl_pair_compute(h.0, at, l, st, null(), f, t) }
        });
        let mine = evaluate(&a, 1.2, |at, _, st, f, t| {
            // SAFETY: arrays sized as documented, alive across the calls; the list's arrays
            // belong to the handle until its next call.
            unsafe {
                let code = dpdnl_pair_own_list(h.0, at, null(), st, 1, 0.3, &mut nl);
                if code != DpdnlStatus::Ok {
                    return code;
                }
                dpdnl_pair_compute(h.0, at, &nl, st, null(), f, t)
            }
        });
        assert_eq!(nl.inum as usize, a.nlocal);
        assert_close(&mine.f, &theirs.f, &format!("{fr}/{no} forces"));
        assert_close(&mine.virial, &theirs.virial, &format!("{fr}/{no} virial"));
        assert!((mine.energy - theirs.energy).abs() <= 1e-12 * theirs.energy.abs());
        assert!(mine.f.iter().any(|&x| x != 0.0));
    }
    // The choice: the own list unless hybrid or exclusions need LAMMPS's (or the environment
    // asks for LAMMPS's, DPDNL_PAIR_LIST=lammps).
    let env_lammps = std::env::var("DPDNL_PAIR_LIST").is_ok_and(|v| v == "lammps");
    for (substyle, exclude, want) in [(0, 0, !env_lammps), (1, 0, false), (0, 1, false)] {
        let mut own = -1;
        // SAFETY: `own` is valid for writing.
        let code = unsafe { dpdnl_pair_list_choice(substyle, exclude, &mut own) };
        assert_eq!(code, DpdnlStatus::Ok, "{}", last_error());
        assert_eq!(
            own,
            i32::from(want),
            "substyle {substyle} exclude {exclude}"
        );
    }
}
