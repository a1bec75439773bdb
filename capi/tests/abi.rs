//! The C ABI against the Rust kernels it wraps: per-pair results bit-for-bit, the batch driver
//! against a direct loop, newton on/off and half/full lists against each other, and bad input
//! coming back as codes plus text.

use std::ffi::{CStr, CString, c_char};
use std::ptr::{null, null_mut};

use dpdnl::kernel::{Friction, Noise, PairCoeff, PairInput, PairModel, Weight, pair_force};
use dpdnl::rng::{keyed_uniform, pair_gaussian};
use dpdnl_capi::*;

const SEED: u32 = 4242;
const DT: f64 = 0.01;
const KT: f64 = 0.7;

fn last_error() -> String {
    // SAFETY: dpdnl_last_error returns a valid NUL-terminated string owned by this thread.
    unsafe { CStr::from_ptr(dpdnl_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// A uniform in [lo, hi) keyed by (a, b): deterministic test data.
fn uniform(a: u32, b: u32, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * keyed_uniform(99, 1000, 7, a, b)
}

struct Params(*mut DpdnlParams);

impl Drop for Params {
    fn drop(&mut self) {
        // SAFETY: the pointer came from dpdnl_params_new and is freed once.
        unsafe { dpdnl_params_free(self.0) };
    }
}

/// Two-type table: (1,1), (1,2), (2,2) with different coefficients.
fn params(friction: &str, noise: &str, s: f64) -> (Params, [[PairCoeff; 3]; 3]) {
    let (f, n) = (
        CString::new(friction).unwrap(),
        CString::new(noise).unwrap(),
    );
    let mut p = null_mut();
    // SAFETY: valid strings and out pointer.
    let st = unsafe { dpdnl_params_new(KT, i64::from(SEED), f.as_ptr(), n.as_ptr(), s, 2, &mut p) };
    assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
    let c = |a, g0, g1, rc| PairCoeff {
        a,
        gamma0: g0,
        gamma1: g1,
        rc,
    };
    let zero = c(0.0, 0.0, 0.0, 0.0);
    let mut table = [[zero; 3]; 3];
    for (i, j, cc) in [
        (1, 1, c(25.0, 4.5, 1.0, 1.0)),
        (1, 2, c(10.0, 3.0, 0.5, 1.2)),
        (2, 2, c(0.0, 5.0, 2.0, 0.9)),
    ] {
        // SAFETY: live table.
        let st = unsafe { dpdnl_params_set_coeff(p, i, j, cc.a, cc.gamma0, cc.gamma1, cc.rc) };
        assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
        table[i as usize][j as usize] = cc;
        table[j as usize][i as usize] = cc;
    }
    (Params(p), table)
}

const MODELS: [(&str, &str); 5] = [
    ("none", "plain"),
    ("cross", "plain"),
    ("dot", "plain"),
    ("dot", "corrected"),
    ("dot", "twostep"),
];

#[test]
fn per_pair_equals_kernel_bit_for_bit() {
    for (fr, no) in MODELS {
        for s in [2.0, 1.0, 0.37] {
            let (p, table) = params(fr, no, s);
            let model = PairModel::new(
                KT,
                Friction::from_keyword(fr).unwrap(),
                Noise::from_keyword(no).unwrap(),
                Weight::new(s).unwrap(),
                DT,
            );
            for k in 0..200u32 {
                let (ti, tj) = (1 + k % 2, 1 + (k / 2) % 2);
                let dr = [0, 1, 2].map(|d| uniform(k, d, -0.8, 0.8));
                let dv = [0, 1, 2].map(|d| uniform(k, 10 + d, -1.5, 1.5));
                let inv_mass_sum = uniform(k, 20, 0.5, 3.0);
                let xi = pair_gaussian(SEED, u64::from(k), k, k + 1);
                let mut out = DpdnlPairForce::default();
                // SAFETY: live table, 3-double arrays, valid out pointer.
                let st = unsafe {
                    dpdnl_pair_force(
                        p.0,
                        ti as i32,
                        tj as i32,
                        dr.as_ptr(),
                        dv.as_ptr(),
                        inv_mass_sum,
                        xi,
                        DT,
                        &mut out,
                    )
                };
                assert_eq!(st, DpdnlStatus::Ok, "{}", last_error());
                let input = PairInput {
                    dr,
                    dv,
                    inv_mass_sum,
                    xi,
                };
                let want = pair_force(&model, &table[ti as usize][tj as usize], &input);
                let got = [out.fc, out.fd, out.fr, out.fa, out.energy, out.inv_r];
                let exp = [want.fc, want.fd, want.fr, want.fa, want.energy, want.inv_r];
                for (g, e) in got.iter().zip(exp) {
                    assert_eq!(g.to_bits(), e.to_bits(), "{fr}/{no} s={s} pair {k}");
                }
            }
        }
    }
}

#[test]
fn gaussian_matches_rng() {
    for k in 0..50u32 {
        let (a, b, step) = (k * 7 + 1, k * 13 + 2, u64::from(k) << 33 | 5);
        assert_eq!(
            dpdnl_pair_gaussian(SEED, step, a, b).to_bits(),
            pair_gaussian(SEED, step, a, b).to_bits()
        );
    }
}

/// A periodic cube of `n` owned atoms plus ghost images within `cut` of the box (one rank).
struct System {
    x: Vec<f64>,
    v: Vec<f64>,
    tag: Vec<i32>,
    ty: Vec<i32>,
    nlocal: usize,
    /// Index of the owner of each atom (itself for owned atoms).
    owner: Vec<usize>,
}

impl System {
    fn new(n: usize, len: f64, cut: f64) -> System {
        let mut s = System {
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
            // Tags deliberately not in index order.
            s.tag.push(((i * 37) % n + 1) as i32);
            s.ty.push(1 + (i % 3 == 0) as i32);
            s.owner.push(i);
        }
        for (dx, dy, dz) in (0..27).map(|k| (k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1)) {
            if (dx, dy, dz) == (0, 0, 0) {
                continue;
            }
            for i in 0..n {
                let p = [
                    s.x[3 * i] + f64::from(dx) * len,
                    s.x[3 * i + 1] + f64::from(dy) * len,
                    s.x[3 * i + 2] + f64::from(dz) * len,
                ];
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
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum ListKind {
    HalfNewtonOn,
    HalfNewtonOff,
    Full,
}

struct Result {
    f: Vec<f64>,
    energy: f64,
    virial: [f64; 6],
    eatom: Vec<f64>,
    vatom: Vec<f64>,
}

fn run(p: &Params, s: &System, kind: ListKind, cut: f64, step: i64) -> Result {
    let lists = s.list(kind, cut);
    let ilist: Vec<i32> = (0..s.nlocal as i32).collect();
    let numneigh: Vec<i32> = lists.iter().map(|l| l.len() as i32).collect();
    let firstneigh: Vec<*const i32> = lists.iter().map(|l| l.as_ptr()).collect();
    let mass = [0.0, 1.0, 2.5];
    let atoms = DpdnlAtoms {
        x: s.x.as_ptr(),
        v: s.v.as_ptr(),
        tag: s.tag.as_ptr(),
        atom_type: s.ty.as_ptr(),
        mass: mass.as_ptr(),
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
    };
    let mut r = Result {
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
    let code = unsafe { dpdnl_compute(p.0, &atoms, &list, &st, r.f.as_mut_ptr(), &mut tally) };
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
fn batch_equals_direct_loop() {
    let (len, cut) = (3.0, 1.2);
    let s = System::new(60, len, cut);
    for (fr, no) in MODELS {
        let (p, table) = params(fr, no, 2.0);
        let model = PairModel::new(
            KT,
            Friction::from_keyword(fr).unwrap(),
            Noise::from_keyword(no).unwrap(),
            Weight::STANDARD,
            DT,
        );
        let step = 17;
        let got = run(&p, &s, ListKind::HalfNewtonOn, cut, step);
        // The direct loop: every physical pair (owned i, any image j) seen from i.
        let mut f = vec![0.0; 3 * s.nlocal];
        let mut energy = 0.0;
        let mut virial = [0.0; 6];
        let inv_m = |t: i32| if t == 1 { 1.0 } else { 1.0 / 2.5 };
        for i in 0..s.nlocal {
            for j in 0..s.nall() {
                if j == i {
                    continue;
                }
                let dr = [0, 1, 2].map(|d| s.x[3 * i + d] - s.x[3 * j + d]);
                let input = PairInput {
                    dr,
                    dv: [0, 1, 2].map(|d| s.v[3 * i + d] - s.v[3 * j + d]),
                    inv_mass_sum: inv_m(s.ty[i]) + inv_m(s.ty[j]),
                    xi: pair_gaussian(SEED, step as u64, s.tag[i] as u32, s.tag[j] as u32),
                };
                let pf = pair_force(&model, &table[s.ty[i] as usize][s.ty[j] as usize], &input);
                let fv = pf.vector(dr);
                for d in 0..3 {
                    f[3 * i + d] += fv[d];
                }
                energy += 0.5 * pf.energy;
                let fp = 0.5 * pf.total() * pf.inv_r;
                let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
                for (k, (a, b)) in pairs.into_iter().enumerate() {
                    virial[k] += dr[a] * dr[b] * fp;
                }
            }
        }
        assert!(f.iter().any(|&x| x != 0.0));
        assert_close(&got.f, &f, &format!("{fr}/{no} force"));
        assert_close(&[got.energy], &[energy], "energy");
        assert_close(&got.virial, &virial, "virial");
        // Momentum: the pair forces sum to zero.
        for d in 0..3 {
            let total: f64 = (0..s.nlocal).map(|i| got.f[3 * i + d]).sum();
            assert!(total.abs() < 1e-10, "net force {total}");
        }
    }
}

#[test]
fn newton_on_off_and_full_lists_agree() {
    let (len, cut) = (3.0, 1.2);
    let s = System::new(60, len, cut);
    let (p, _) = params("dot", "twostep", 2.0);
    let on = run(&p, &s, ListKind::HalfNewtonOn, cut, 3);
    for kind in [ListKind::HalfNewtonOff, ListKind::Full] {
        let other = run(&p, &s, kind, cut, 3);
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
fn bad_parameters_give_codes_and_text() {
    let s = |x: &str| CString::new(x).unwrap();
    let (none, plain) = (s("none"), s("plain"));
    let new = |kt, seed, fr: *const c_char, no: *const c_char, w, nt| {
        status_of(|| {
            let mut p = null_mut();
            // SAFETY: the strings are valid or null (checked), out is valid.
            let st = unsafe { dpdnl_params_new(kt, seed, fr, no, w, nt, &mut p) };
            assert_eq!(st == DpdnlStatus::Ok, !p.is_null());
            // SAFETY: null or a live table.
            unsafe { dpdnl_params_free(p) };
            st
        })
    };
    let bogus = s("bogus");
    let cases = [
        (new(-1.0, 1, none.as_ptr(), plain.as_ptr(), 2.0, 1), "kT"),
        (
            new(f64::NAN, 1, none.as_ptr(), plain.as_ptr(), 2.0, 1),
            "kT",
        ),
        (new(1.0, 0, none.as_ptr(), plain.as_ptr(), 2.0, 1), "seed"),
        (
            new(1.0, 1 << 32, none.as_ptr(), plain.as_ptr(), 2.0, 1),
            "seed",
        ),
        (
            new(1.0, 1, bogus.as_ptr(), plain.as_ptr(), 2.0, 1),
            "friction 'bogus'",
        ),
        (
            new(1.0, 1, none.as_ptr(), bogus.as_ptr(), 2.0, 1),
            "noise 'bogus'",
        ),
        (new(1.0, 1, none.as_ptr(), plain.as_ptr(), 0.0, 1), "weight"),
        (
            new(1.0, 1, none.as_ptr(), plain.as_ptr(), 2.0, 0),
            "atom types",
        ),
    ];
    for ((st, msg), want) in cases {
        assert_eq!(st, DpdnlStatus::InvalidArgument, "{msg}");
        assert!(msg.contains(want), "'{msg}' should mention {want}");
    }
    let (st, msg) = new(1.0, 1, null(), plain.as_ptr(), 2.0, 1);
    assert_eq!(st, DpdnlStatus::NullPointer);
    assert!(msg.contains("friction"), "{msg}");

    // SAFETY: a null out pointer is reported, not written.
    let st = unsafe { dpdnl_params_new(1.0, 1, none.as_ptr(), plain.as_ptr(), 2.0, 1, null_mut()) };
    assert_eq!(st, DpdnlStatus::NullPointer);

    let (p, _) = params("none", "plain", 2.0);
    let coeff = |i, j, a, g0, g1, rc| {
        // SAFETY: live table.
        status_of(|| unsafe { dpdnl_params_set_coeff(p.0, i, j, a, g0, g1, rc) })
    };
    for ((st, msg), want) in [
        (coeff(1, 1, 1.0, -1.0, 0.0, 1.0), "gamma0"),
        (coeff(1, 1, 1.0, 1.0, -0.5, 1.0), "gamma1"),
        (coeff(1, 1, 1.0, 1.0, 0.0, 0.0), "rc"),
        (coeff(1, 1, f64::INFINITY, 1.0, 0.0, 1.0), "a = inf"),
        (coeff(3, 1, 1.0, 1.0, 0.0, 1.0), "type I = 3"),
        (coeff(1, 0, 1.0, 1.0, 0.0, 1.0), "type J = 0"),
    ] {
        assert_eq!(st, DpdnlStatus::InvalidArgument, "{msg}");
        assert!(msg.contains(want), "'{msg}' should mention {want}");
    }
    assert_eq!(dpdnl_coeff_check(1.0, 1.0, 0.0, 1.0), DpdnlStatus::Ok);
    assert_eq!(last_error(), "");
    assert_eq!(
        dpdnl_coeff_check(1.0, 1.0, 0.0, -1.0),
        DpdnlStatus::InvalidArgument
    );
    // SAFETY: null is reported.
    assert_eq!(
        unsafe { dpdnl_params_set_coeff(null_mut(), 1, 1, 1.0, 1.0, 0.0, 1.0) },
        DpdnlStatus::NullPointer
    );

    // An incomplete table names the missing pair, in check_complete and in compute.
    let mut q = null_mut();
    // SAFETY: valid strings and out pointer.
    let st = unsafe { dpdnl_params_new(1.0, 5, none.as_ptr(), plain.as_ptr(), 2.0, 2, &mut q) };
    assert_eq!(st, DpdnlStatus::Ok);
    let q = Params(q);
    // SAFETY: live table.
    unsafe { dpdnl_params_set_coeff(q.0, 1, 1, 1.0, 1.0, 0.0, 1.0) };
    // SAFETY: live table.
    let (st, msg) = status_of(|| unsafe { dpdnl_params_check_complete(q.0) });
    assert_eq!(st, DpdnlStatus::Incomplete);
    assert!(msg.contains("types 1 2"), "{msg}");
}

#[test]
fn bad_compute_arguments_give_codes_and_text() {
    let (p, _) = params("cross", "plain", 2.0);
    let x = [0.0, 0.0, 0.0, 0.5, 0.0, 0.0];
    let v = [0.0; 6];
    let tag = [1, 2];
    let mass = [0.0, 1.0, 1.0];
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
        mass: mass.as_ptr(),
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
    };
    let mut call = |a: &DpdnlAtoms, l: &DpdnlNeighList, st: &DpdnlStep| {
        // SAFETY: every array above is sized for nall = 2.
        status_of(|| unsafe { dpdnl_compute(p.0, a, l, st, f.as_mut_ptr(), null_mut()) })
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
    let st = unsafe { dpdnl_compute(null(), null(), null(), null(), null_mut(), null_mut()) };
    assert_eq!(st, DpdnlStatus::NullPointer);
}
