//! Property-based tier (issue 16): the readers (restart files too) and the formula evaluator on
//! generated inputs.
//! Round trips are exact; arbitrary text gives an error or a value, never a panic. Case counts
//! are proptest's default (256 per property) unless stated.

use dpdnl::input::expr::{ExprContext, eval_equal};
use dpdnl::io::data::{DataFile, format_data, parse_data};
use dpdnl::io::dump_read::parse_dump;
use dpdnl::io::lammps_log::parse_log;
use dpdnl::io::restart;
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

/// `payload` in a restart file's header with a matching checksum (so the payload reader, not
/// the checksum, decides).
fn restart_file(payload: &[u8]) -> Vec<u8> {
    let mut b = restart::MAGIC.to_vec();
    b.extend_from_slice(&restart::FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    b.extend_from_slice(payload);
    let sum = restart::fnv1a64(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// A small valid restart file's payload (two atoms, a pair style line, a fix with state),
/// written once.
fn restart_payload() -> Vec<u8> {
    static PAYLOAD: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    PAYLOAD.get_or_init(write_restart_payload).clone()
}

fn write_restart_payload() -> Vec<u8> {
    let text = "units lj\natom_style atomic\nregion b block 0 3 0 3 0 3\ncreate_box 2 b\n\
                create_atoms 1 single 1 1 1\ncreate_atoms 2 single 2 2 2\nmass * 1.0\n\
                pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\n\
                fix 1 all nve\nfix p all pex/push 0.1\n";
    let mut console = dpdnl::input::Collect::default();
    let opts = dpdnl::input::Options::default();
    let mut interp = dpdnl::input::Interpreter::new(&mut console, &opts).expect("interpreter");
    interp.run_text(text, "prop.in").expect("set-up");
    let file = std::env::temp_dir().join(format!("dpdnl-prop-{}.restart", std::process::id()));
    interp
        .run_text(&format!("write_restart {}\n", file.display()), "prop.in")
        .expect("written");
    let bytes = std::fs::read(&file).expect("read back");
    let _ = std::fs::remove_file(&file);
    bytes[20..bytes.len() - 8].to_vec()
}

proptest! {
    /// Any bytes, and any damage to a valid payload under a matching checksum, give a restart
    /// or an error from `restart::decode`, never a panic or a huge allocation.
    #[test]
    fn restart_reader_never_panics(
        junk in proptest::collection::vec(any::<u8>(), 0..300),
        at in 0usize..10_000,
        byte in any::<u8>(),
        cut in 0usize..10_000,
    ) {
        let _ = restart::decode(&junk);
        let _ = restart::decode(&restart_file(&junk));
        let mut p = restart_payload();
        let k = at % p.len();
        p[k] = byte;
        let _ = restart::decode(&restart_file(&p));
        p.truncate(cut % (p.len() + 1));
        let _ = restart::decode(&restart_file(&p));
    }

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
