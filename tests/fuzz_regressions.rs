//! Regression tests of the fuzzer's findings (fuzz/README.md): each input that made a target
//! panic, abort or hang, inline, with the verdict the library now gives. The property is the
//! fuzzer's: a value or a clear error, never a panic.

mod common;

use dpdnl::input::lexer::strip_comment;
use dpdnl::input::{Collect, Interpreter, Options};

/// Runs `text` as the `script` fuzz target does (caps on steps and atoms), returning the error
/// message, if any.
fn script(text: &str) -> Result<(), String> {
    let opts = Options {
        max_steps: Some(200),
        max_atoms: Some(400),
        ..Options::default()
    };
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &opts).expect("no log file");
    interp.run_text(text, "fuzz.in").map_err(|e| e.to_string())
}

/// The fuzzing caps (Options::max_steps, Options::max_atoms) refuse with a message, and a
/// script within them runs.
#[test]
fn fuzzing_caps() {
    let setup = "region b block 0 5 0 5 0 5\ncreate_box 1 b\nmass 1 1.0\n\
                 pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nfix 1 all nve\n";
    let err = script(&format!("{setup}create_atoms 1 random 401 7 NULL\n")).unwrap_err();
    assert!(err.contains("cap of 400"), "{err}");
    let err = script(&format!(
        "{setup}create_atoms 1 random 300 7 NULL\ncreate_atoms 1 random 101 8 NULL\n"
    ))
    .unwrap_err();
    assert!(err.contains("cap of 400"), "{err}");
    let err = script(&format!(
        "{setup}create_atoms 1 random 10 7 NULL\nrun 201\n"
    ))
    .unwrap_err();
    assert!(err.contains("cap of 200"), "{err}");
    script(&format!("{setup}create_atoms 1 random 400 7 NULL\nrun 2\n")).unwrap();
    // Without caps (the default), the same script is only limited by memory.
    assert!(common::run(&format!("{setup}create_atoms 1 random 401 7 NULL\nrun 0\n")).is_ok());
}

/// Finding 1 (script): `strip_comment` sliced the line at a byte inside a multi-byte character
/// (`start byte index 18 is not a char boundary`) on any non-ASCII text.
#[test]
fn non_ascii_text_in_a_line() {
    let text =
        "units lj\natom_style atomic\u{9c412}m_modifplugmass * .0.0\nfix 1 all pex/push -0.1\n";
    let err = script(text).unwrap_err();
    assert!(err.starts_with("fuzz.in:2: atom_style"), "{err}");
    assert_eq!(strip_comment("print \"é\" # ü"), "print \"é\" ");
    assert_eq!(strip_comment("ü#"), "ü");
    assert_eq!(strip_comment("'ü # é'"), "'ü # é'");
}

/// Found reading the code the fuzzer exercises: `$` followed by a multi-byte character named
/// the variable after the character's first byte ('Ã' for `$é`).
#[test]
fn one_character_variable_name_is_a_character() {
    let err = script("print $é\n").unwrap_err();
    assert!(err.contains("variable 'é' is not defined"), "{err}");
    let err = script("variable a index 1\nprint \"$a$ü\"\n").unwrap_err();
    assert!(err.contains("variable 'ü' is not defined"), "{err}");
}

/// Finding 2 (script): a sparse box (side ~5000, cut-off 1.3: 6·10¹⁰ cells) made the neighbour
/// grid allocation abort the process (`memory allocation … failed`). The grid is now coarsened
/// to at most max(4·atoms, 4096) cells (finding 9: the floor was 2²¹, visited at every build of a
/// sparse sheared 3-D box, a timeout); the run goes on. The fuzzer's input reduced to its core,
/// and the same in a Lees–Edwards (sheared) box, which has its own grid.
#[test]
fn sparse_box_neighbour_grid() {
    let body = "region box block 0 5000 0 5000 1 5000\ncreate_box 1 box\n\
                create_atoms 1 random 150 8675 box\nmass 1 1.0\n\
                velocity all create 0.1 4928 mom yes dist gaussian\n\
                pair_style dpd/nonlinear 0.1 1.0 34387 friction dot noise twostep\n\
                pair_coeff 1 1 0.0 5.0 1.0\ntimestep 0.001\nfix 1 all nve\n";
    let (_, sys) = common::run(&format!("{body}run 20\n")).expect("runs");
    assert_eq!(sys.expect("system").atoms.len(), 150);
    script(&format!("{body}run 20\n")).unwrap();
    // 2-D, one huge axis.
    let body2d = "dimension 2\nregion box block 0 1e12 0 3 -0.5 0.5\ncreate_box 1 box\n\
                  create_atoms 1 random 50 1 box\nmass 1 1.0\n\
                  pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nfix 1 all nve\nrun 5\n";
    common::run(body2d).expect("runs");
    // Sheared (triclinic, Lees–Edwards) 2-D box of side 10⁶.
    let sheared = "dimension 2\nregion box prism 0 1e6 0 1e6 -0.5 0.5 0 0 0\ncreate_box 1 box\n\
                   create_atoms 1 random 50 1 box\nmass 1 1.0\n\
                   pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nfix 1 all nve\n\
                   fix d all deform 1 xy erate 0.1 remap v\nrun 5\n";
    common::run(sheared).expect("runs");
    // Finding 9: a sparse sheared 3-D box, rebuilt often (every step here); 2000 steps visited
    // 2²¹ cells per build before. The grid-size bound is the unit test in neighbor/mod.rs.
    let sheared3d = "region box prism 0 300 0 300 0 300 0 0 0\ncreate_box 1 box\n\
                     create_atoms 1 random 40 7 box\nmass 1 1.0\n\
                     velocity all create 1.0 4928 mom yes dist gaussian\n\
                     pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\n\
                     neighbor 0.0 bin\nneigh_modify every 1 delay 0 check no\n\
                     timestep 0.01\nfix 1 all nve\n\
                     fix d all deform 1 xy erate 0.1 remap v\nrun 2000\n";
    let (_, sys) = common::run(sheared3d).expect("runs");
    assert_eq!(sys.expect("system").atoms.len(), 40);
}

/// Findings 3 (script) and 4 (readers): `create_box 23333333333333 box`, and a data file with
/// `26666666666666666 atom types`, allocated per-type tables of that size
/// (`memory allocation of 373333333333344 bytes failed`, an abort). Atom type counts are now
/// 1..=1000 in `create_box`, `read_data` (the data file reader itself) and `read_restart`.
#[test]
fn atom_type_count_is_bounded() {
    let err = script("region box block 0 5 0 5 0 5\ncreate_box 23333333333333 box\n").unwrap_err();
    assert!(
        err.starts_with("fuzz.in:2: create_box: 23333333333333 atom types: at most 1000"),
        "{err}"
    );
    script("region box block 0 5 0 5 0 5\ncreate_box 1000 box\n").unwrap();
    let data = "title\n\n1 atoms\n18446744073709551615 atom types\n\n0 1 xlo xhi\n0 1 ylo yhi\n\
                0 1 zlo zhi\n\nAtoms\n\n1 1 0.5 0.5 0.5\n";
    let err = dpdnl::io::data::parse_data(data, "big.data").unwrap_err();
    assert!(
        err.starts_with("big.data: 18446744073709551615 atom types: at most 1000"),
        "{err}"
    );
}

/// Finding 5 (script): with a friction of ~1e12 an atom flew ~2^31 box lengths between two
/// rebuilds and the image count overflowed (`attempt to add with overflow` in
/// `SimBox::wrap_le`; the periodic `SimBox::wrap` had the same `+=`). The counts saturate; the
/// run then stops at the blow-up check with the atom named.
#[test]
fn huge_displacement_image_count() {
    for (region, deform) in [
        (
            "prism 0 10 0 10 -0.5 0.5 0 0 0",
            "fix 3 all deform 1 xy erate 0.5 remap v\n",
        ),
        ("block 0 10 0 10 -0.5 0.5", ""),
    ] {
        let text = format!(
            "dimension 2\nregion box {region}\ncreate_box 1 box\n\
             create_atoms 1 random 150 8675 box\nmass 1 1.0\n\
             velocity all create 2.0 4928 mom yes dist gaussian\n\
             pair_style dpd/nonlinear 1.0 1.0 34387 weight 0.5\n\
             pair_coeff 1 1 0.0 1e12 0.0\nfix 1 all nve\n{deform}thermo 1000\nrun 42\n"
        );
        let err = script(&text).unwrap_err();
        assert!(err.contains("run: blow-up at step"), "{err}");
    }
}

/// Found by hand while the fuzzer ran, in code it exercises: `reset_timestep` near 2^64 and a
/// `run` past it overflowed the last step (`attempt to add with overflow` in `cmd_run`).
#[test]
fn run_past_the_last_step_number() {
    let setup = "region b block 0 5 0 5 0 5\ncreate_box 1 b\nmass 1 1.0\n\
                 create_atoms 1 random 10 7 NULL\npair_style dpd/nonlinear 1.0 1.0 5\n\
                 pair_coeff * * 25 4.5 0\nfix 1 all nve\nreset_timestep 18446744073709551610\n";
    let err = script(&format!("{setup}run 10\n")).unwrap_err();
    assert!(
        err.starts_with("fuzz.in:9: run: run 10 from step 18446744073709551610 would pass"),
        "{err}"
    );
    script(&format!("{setup}run 5\n")).unwrap();
}

/// Found by hand while the fuzzer ran, in code it exercises: `fix ave/histo` with 10^11 bins and
/// `ave window 100000000000000` allocated that many slots up front (aborts in the allocator).
/// Histogram bins are now 1..10^8 (as compute chunk/atom's), and a window's slots are allocated
/// as samples arrive.
#[test]
fn averaging_sizes_are_bounded() {
    let setup = "region b block 0 5 0 5 0 5\ncreate_box 1 b\nmass 1 1.0\n\
                 create_atoms 1 random 10 7 NULL\npair_style dpd/nonlinear 1.0 1.0 5\n\
                 pair_coeff * * 25 4.5 0\nfix 1 all nve\nvariable v atom vx\n";
    let err = script(&format!(
        "{setup}fix h all ave/histo 1 1 1 0 1 100000000000 v_v mode vector\nrun 2\n"
    ))
    .unwrap_err();
    assert!(err.contains("100000000000 bins (need 1 to 10^8)"), "{err}");
    script(&format!(
        "{setup}fix a all ave/time 1 1 1 c_thermo_temp ave window 100000000000000\nrun 5\n"
    ))
    .unwrap();
    script(&format!(
        "{setup}fix h all ave/histo 1 1 1 0 1 10 v_v mode vector ave window 100000000000000\n\
         run 5\n"
    ))
    .unwrap();
}
