//! The pure pair force of `pair_style test/spring`: a linear spring F = k (1 − r/r_c) along
//! e_ij (repulsive for k > 0), energy U = k r_c (1 − r/r_c)²/2, nothing beyond r_c; no
//! dissipation, no noise.

use crate::forces::PairBatch;

/// One type pair's coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpringCoeff {
    /// k, the force at contact.
    pub k: f64,
    /// The cut-off r_c (0: the pair does not interact).
    pub rc: f64,
}

/// F(r)/r and U of one pair at distance² `rsq` (0, 0 at or beyond r_c or at r = 0).
#[inline]
pub fn spring_pair(c: &SpringCoeff, rsq: f64) -> (f64, f64) {
    if rsq >= c.rc * c.rc || rsq <= 0.0 {
        return (0.0, 0.0);
    }
    let r = rsq.sqrt();
    let w = 1.0 - r / c.rc;
    (c.k * w / r, 0.5 * c.k * c.rc * w * w)
}

/// Every lane of `b`: [`spring_pair`] of its coefficients `coeff[b.coeff[l]]`.
pub fn spring_batch(coeff: &[SpringCoeff], b: &mut PairBatch) {
    for l in 0..b.len {
        let rsq = (0..3).map(|k| b.dr[k][l] * b.dr[k][l]).sum();
        let (f, e) = spring_pair(&coeff[b.coeff[l] as usize], rsq);
        b.fpair[l] = f;
        b.energy[l] = e;
    }
}
