//! Property-based tier (issue 16): the readers and the formula evaluator on generated inputs.
//! Round trips are exact; arbitrary text gives an error or a value, never a panic. Case counts
//! are proptest's default (256 per property) unless stated.

use dpdnl::input::expr::{ExprContext, eval_equal};
use dpdnl::io::data::{DataFile, format_data, parse_data};
use dpdnl::io::dump_read::parse_dump;
use dpdnl::io::lammps_log::parse_log;
use proptest::prelude::*;

struct Ctx;

impl ExprContext for Ctx {
    fn variable(&self, name: &str) -> Result<f64, String> {
        match name {
            "a" => Ok(2.0),
            _ => Err(format!("no variable {name}")),
        }
    }
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>> {
        (keyword == "step").then_some(Ok(10.0))
    }
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![-1e6..1e6f64, -1e-6..1e-6f64, Just(0.0), Just(-0.0)]
}

prop_compose! {
    fn data_file()(ntypes in 1usize..4, n in 0usize..40)
        (atoms in proptest::collection::vec(
            (1u32..4, [finite(), finite(), finite()], [-3i32..3, -3i32..3, -3i32..3]), n),
         vels in proptest::collection::vec([finite(), finite(), finite()], n),
         masses in proptest::collection::vec(0.1f64..10.0, ntypes),
         ntypes in Just(ntypes))
        -> DataFile
    {
        let mut d = DataFile {
            ntypes,
            lo: [-1e7; 3],
            hi: [1e7; 3],
            masses: std::iter::once(None).chain(masses.into_iter().map(Some)).collect(),
            ..DataFile::default()
        };
        for (k, ((t, x, im), v)) in atoms.into_iter().zip(vels).enumerate() {
            let tag = k as u32 + 1;
            d.atoms.push((tag, (t as usize).min(ntypes) as u32, x, im));
            d.velocities.push((tag, v));
        }
        d
    }
}

proptest! {
    /// write_data → read_data gives back every number bit for bit.
    #[test]
    fn data_files_round_trip(d in data_file()) {
        let text = format_data(&d, "prop");
        let back = parse_data(&text, "prop.data").map_err(TestCaseError::fail)?;
        prop_assert_eq!(back.ntypes, d.ntypes);
        prop_assert_eq!(back.atoms.len(), d.atoms.len());
        for (a, b) in d.atoms.iter().zip(&back.atoms) {
            prop_assert_eq!(a.0, b.0);
            prop_assert_eq!(a.1, b.1);
            prop_assert_eq!(a.2.map(f64::to_bits), b.2.map(f64::to_bits));
            prop_assert_eq!(a.3, b.3);
        }
        for (a, b) in d.velocities.iter().zip(&back.velocities) {
            prop_assert_eq!(a.1.map(f64::to_bits), b.1.map(f64::to_bits));
        }
    }

    /// Arbitrary text (and arbitrary damage to a valid file) never panics a reader.
    #[test]
    fn readers_never_panic(text in ".{0,400}", cut in 0usize..2000, d in data_file()) {
        let _ = parse_data(&text, "x.data");
        let _ = parse_dump(&text);
        let _ = parse_log(&text);
        let valid = format_data(&d, "prop");
        let cut = cut.min(valid.len());
        if valid.is_char_boundary(cut) {
            let _ = parse_data(&valid[..cut], "cut.data");
        }
    }

    /// Formulas from the grammar's alphabet: a value or an error, never a panic; a finite
    /// value for well-formed sums and products of numbers.
    #[test]
    fn formulas_never_panic(s in "[0-9a-z_.()+*/^<>=!&|, -]{0,60}") {
        let _ = eval_equal(&s, &Ctx);
        let _ = eval_equal(&format!("v_{s}"), &Ctx);
    }

    #[test]
    fn sums_and_products_evaluate_as_f64(a in -1e3..1e3f64, b in -1e3..1e3f64, c in 0.5..1e3f64) {
        let e = format!("({a:e})+({b:e})*({c:e})");
        let v = eval_equal(&e, &Ctx).map_err(TestCaseError::fail)?;
        prop_assert_eq!(v.to_bits(), (a + b * c).to_bits());
        let q = eval_equal(&format!("({a:e})/({c:e})"), &Ctx).map_err(TestCaseError::fail)?;
        prop_assert_eq!(q.to_bits(), (a / c).to_bits());
    }
}
