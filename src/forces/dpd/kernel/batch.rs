//! The batched pair kernel: [`pair_forces_batch`] evaluates the same function as
//! [`super::pair_force`] (bit for bit) on up to [`BATCH`] pairs in structure-of-arrays lanes,
//! for the engines' hot loops, with a choice of instruction set ([`Isa`]).

use super::*;
use crate::forces::lanes::{BatchScratch, COEFF_LANES, CoeffLanes, StageArrays, pair_noise};
// DPD's rows of the batch's coefficient lanes ([`CoeffLanes`]): a, γ0, γ1, r_c (the pair's
// coefficients) and 1/r_c, σ0, a r_c / 2 (derived). The stage arrays ([`StageArrays`]) hold
// `g` = the fields of [`Geom`] (r, 1/r, q, w_D, w_R, r·v, S) and `gs` = γ(S), σ(S), σ(S'').
const A: usize = 0;
const GAMMA0: usize = 1;
const GAMMA1: usize = 2;
const RC: usize = 3;
const INV_RC: usize = 4;
const SIGMA0: usize = 5;
const HALF_A_RC: usize = 6;
const _: () = assert!(HALF_A_RC < COEFF_LANES);

/// Evaluate every pair of `b` at `step`: `b.fpair[l]` and `b.energy[l]` become exactly
/// `pair_force(model, &coeff[b.coeff[l]], input_l)` (`table` = `PairTable::new(model, coeff)`) with `input_l.xi = model.dist.pair_xi(seed, step,
/// b.tag_i[l], b.tag_j[l])` (the Gaussian by default; total force / r and energy; 0 out of range). The loop has no calls
/// and no branches, so it runs in SIMD lanes ([`Isa::detect`]).
///
/// Panics if a `coeff` index is outside `table` (a caller bug), or if `table` was prepared for a
/// model with another kT (checked in debug builds).
pub fn pair_forces_batch(
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    pair_forces_batch_isa(Isa::detect(), model, table, seed, step, b);
}

/// [`pair_forces_batch`] with a given instruction set (a lower one than the CPU's best is fine;
/// an unsupported one falls back to [`Isa::Baseline`]). For tests and benchmarks.
pub fn pair_forces_batch_isa(
    isa: Isa,
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    let n = b.len.min(BATCH);
    b.len = n;
    if n == 0 {
        return;
    }
    debug_assert_eq!(
        table.kt.to_bits(),
        model.kt.to_bits(),
        "PairTable of another model"
    );
    let isa = if (isa as u8) > (Isa::best_supported() as u8) {
        Isa::Baseline
    } else {
        isa
    };
    let standard = model.weight == Weight::STANDARD;
    macro_rules! arms {
        ($(($f:ident, $n:ident)),*) => {
            match (model.friction, model.noise, standard) {
                $(
                    (Friction::$f, Noise::$n, true) => {
                        lanes_isa::<{ Friction::$f as u8 }, { Noise::$n as u8 }, true>(isa, model, table, seed, step, b)
                    }
                    (Friction::$f, Noise::$n, false) => {
                        lanes_isa::<{ Friction::$f as u8 }, { Noise::$n as u8 }, false>(isa, model, table, seed, step, b)
                    }
                )*
            }
        };
    }
    arms!(
        (None, Plain),
        (None, Corrected),
        (None, TwoStep),
        (Cross, Plain),
        (Cross, Corrected),
        (Cross, TwoStep),
        (Dot, Plain),
        (Dot, Corrected),
        (Dot, TwoStep)
    );
}

pub(super) fn lanes_isa<const F: u8, const N: u8, const STD: bool>(
    isa: Isa,
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is at most `Isa::best_supported()` (checked by the caller), so the CPU has
        // every feature these functions are compiled for.
        Isa::Avx512 => unsafe { lanes_avx512::<F, N, STD>(model, table, seed, step, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { lanes_avx2::<F, N, STD>(model, table, seed, step, b) },
        _ => lanes::<F, N, STD>(model, table, seed, step, b),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn lanes_avx512<const F: u8, const N: u8, const STD: bool>(
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    lanes::<F, N, STD>(model, table, seed, step, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn lanes_avx2<const F: u8, const N: u8, const STD: bool>(
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    lanes::<F, N, STD>(model, table, seed, step, b)
}

pub(super) const fn friction_of(f: u8) -> Friction {
    match f {
        1 => Friction::Cross,
        2 => Friction::Dot,
        _ => Friction::None,
    }
}

pub(super) const fn noise_of(n: u8) -> Noise {
    match n {
        1 => Noise::Corrected,
        2 => Noise::TwoStep,
        _ => Noise::Plain,
    }
}

/// Gather each pair's coefficients and constants into the lane arrays (a broadcast when the
/// whole batch has one type pair, e.g. one atom type).
#[inline(always)]
pub(super) fn fill_coeff(table: &PairTable, b: &mut PairBatch, n: usize) {
    let first = b.coeff[0];
    let co = &mut b.scratch.co;
    if b.coeff[..n].iter().all(|&k| k == first) {
        let (c, d) = (&table.coeff[first as usize], &table.derived[first as usize]);
        co[A].fill(c.a);
        co[GAMMA0].fill(c.gamma0);
        co[GAMMA1].fill(c.gamma1);
        co[RC].fill(c.rc);
        co[INV_RC].fill(d.inv_rc);
        co[SIGMA0].fill(d.sigma0);
        co[HALF_A_RC].fill(d.half_a_rc);
    } else {
        for l in 0..n {
            let k = b.coeff[l] as usize;
            let (c, d) = (&table.coeff[k], &table.derived[k]);
            co[A][l] = c.a;
            co[GAMMA0][l] = c.gamma0;
            co[GAMMA1][l] = c.gamma1;
            co[RC][l] = c.rc;
            co[INV_RC][l] = d.inv_rc;
            co[SIGMA0][l] = d.sigma0;
            co[HALF_A_RC][l] = d.half_a_rc;
        }
    }
}

/// The per-pair loop of [`pair_forces_batch`], with friction, noise and weight fixed.
// Kept in one piece (over 120 lines) on purpose: the hot loop, so the compiler sees the whole
// lane loop of each (friction, noise, weight) instance at once and vectorises it.
#[inline(always)]
pub(super) fn lanes<const F: u8, const N: u8, const STD: bool>(
    model: &PairModel,
    table: &PairTable,
    seed: u32,
    step: u64,
    b: &mut PairBatch,
) {
    let friction = friction_of(F);
    let noise = noise_of(N);
    let weight = model.weight;
    let n = b.len.min(BATCH);
    fill_coeff(table, b, n);
    // Every loop runs over all BATCH lanes, whatever `n`: lanes past `n` compute garbage from
    // stale inputs (pure arithmetic, no traps) that nobody reads, and no scalar remainder
    // loop is needed.
    let n = BATCH;
    // Three loops (random bits, Gaussians, forces) rather than one: each body is short enough
    // for the processor to overlap several iterations, which hides the long latency chains of
    // Philox, ln and the divisions. The arithmetic of each pair is unchanged.
    pair_noise(b, seed, step, model.dist);
    // The stages of `pair_parts`, one loop each (see there); lane arrays in between.
    let coeff_at = |co: &CoeffLanes, l: usize| {
        (
            PairCoeff {
                a: co[A][l],
                gamma0: co[GAMMA0][l],
                gamma1: co[GAMMA1][l],
                rc: co[RC][l],
            },
            Derived {
                inv_rc: co[INV_RC][l],
                sigma0: co[SIGMA0][l],
                half_a_rc: co[HALF_A_RC][l],
            },
        )
    };
    let input_at = |b: &PairBatch, xi: &[f64; BATCH], l: usize| PairInput {
        dr: [b.dr[0][l], b.dr[1][l], b.dr[2][l]],
        dv: [b.dv[0][l], b.dv[1][l], b.dv[2][l]],
        inv_mass_sum: b.inv_mass_sum[l],
        xi: xi[l],
    };
    // Geometry and σ's between the stages, as lane arrays in the batch's scratch.
    let geom_at = |st: &StageArrays, l: usize| Geom {
        r: st.g[0][l],
        inv_r: st.g[1][l],
        q: st.g[2][l],
        wd: st.g[3][l],
        wr: st.g[4][l],
        rdotv: st.g[5][l],
        s: st.g[6][l],
    };
    {
        let BatchScratch { co, xi, st, .. } = &mut b.scratch;
        let io = (&b.dr, &b.dv, &b.inv_mass_sum);
        let input = |l: usize| PairInput {
            dr: [io.0[0][l], io.0[1][l], io.0[2][l]],
            dv: [io.1[0][l], io.1[1][l], io.1[2][l]],
            inv_mass_sum: io.2[l],
            xi: xi[l],
        };
        for l in 0..n {
            let (_, d) = coeff_at(co, l);
            let p = input(l);
            let rsq = dot(p.dr, p.dr);
            let g = if STD {
                geom(friction, |q| (q * q, q), &d, &p, rsq)
            } else {
                geom(friction, |q| weight.wd_wr(q), &d, &p, rsq)
            };
            st.g[0][l] = g.r;
            st.g[1][l] = g.inv_r;
            st.g[2][l] = g.q;
            st.g[3][l] = g.wd;
            st.g[4][l] = g.wr;
            st.g[5][l] = g.rdotv;
            st.g[6][l] = g.s;
        }
        if friction != Friction::None {
            for l in 0..n {
                let (c, d) = coeff_at(co, l);
                let (gamma, sigma) = friction_at(friction, &c, &d, st.g[6][l]);
                st.gs[0][l] = gamma;
                st.gs[1][l] = sigma;
            }
            if noise == Noise::TwoStep {
                for l in 0..n {
                    let (c, d) = coeff_at(co, l);
                    let p = input(l);
                    let rsq = dot(p.dr, p.dr);
                    let s2 = twostep_rate(friction, model, &geom_at(st, l), st.gs[1][l], &p, rsq);
                    st.gs[2][l] = friction_at(friction, &c, &d, s2).1;
                }
            }
        }
    }
    let (co, xi, st) = (&b.scratch.co, &b.scratch.xi, &b.scratch.st);
    for l in 0..n {
        let (c, d) = coeff_at(co, l);
        let p = input_at(b, xi, l);
        let rsq = dot(p.dr, p.dr);
        let ok = in_range(rsq, c.rc);
        // Constant friction: γ and σ are the type pair's (what `friction_at` returns).
        let (gamma, sigma, sigma2) = if friction == Friction::None {
            (c.gamma0, d.sigma0, d.sigma0)
        } else if noise == Noise::TwoStep {
            (st.gs[0][l], st.gs[1][l], st.gs[2][l])
        } else {
            (st.gs[0][l], st.gs[1][l], st.gs[1][l])
        };
        let pf = assemble(
            friction,
            noise,
            model,
            &c,
            &d,
            &p,
            &geom_at(st, l),
            gamma,
            sigma,
            sigma2,
        );
        b.fpair[l] = if ok { pf.total() * pf.inv_r } else { 0.0 };
        b.energy[l] = if ok { pf.energy } else { 0.0 };
    }
}
