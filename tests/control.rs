//! Script control in the standalone engine, with LAMMPS's semantics (its `Input::ifthenelse`,
//! `jump`, `label`, `next` and `loop` variables): what each script prints is what LAMMPS's
//! documentation of these commands says it prints.

mod common;

fn printed(text: &str) -> Vec<String> {
    let (lines, _) = common::run(text).unwrap_or_else(|e| panic!("{e}"));
    lines
}

fn refused(text: &str) -> String {
    common::run(text).expect_err("refused").to_string()
}

#[test]
fn if_then_elif_else_runs_the_first_true_branch_only() {
    let out = printed(
        "variable a equal 2\n\
         if \"${a} > 5\" then \"print big\" elif \"${a} > 1\" \"print middle\" \"print again\" else \"print small\"\n\
         if \"${a} < 0\" then \"print negative\"\n\
         if \"${a} == 0\" then \"print zero\" else \"print nonzero\"\n\
         variable s string abc\n\
         if \"${s} == abc\" then 'print \"string equal\"'\n\
         if \"(${a} >= 2) && !(${s} != abc)\" then \"print both\"\n",
    );
    assert_eq!(
        out,
        ["middle", "again", "nonzero", "string equal", "both"],
        "{out:?}"
    );
}

#[test]
fn if_commands_are_substituted_when_they_run() {
    // The second command sees the value the first one set (each runs as an input line).
    let out = printed(
        "variable a equal 1\n\
         if \"1\" then \"variable a equal 7\" \"print 'a = $a'\"\n",
    );
    assert_eq!(out, ["a = 7"]);
}

#[test]
fn branches_are_read_as_they_are_reached() {
    // As LAMMPS: the true branch runs and what follows it is not looked at.
    assert_eq!(printed("if \"1 > 0\" then \"print yes\" elif\n"), ["yes"]);
    assert!(refused("if \"1 < 0\" then \"print yes\" else\n").contains("'else' needs commands"));
    assert!(refused("if \"1 < 0\" then \"print yes\" elif \"1\"\n").contains("no command"));
}

#[test]
fn loop_with_next_and_jump_self() {
    let text = "variable i loop 3\n\
                label top\n\
                print \"pass $i\"\n\
                next i\n\
                jump SELF top\n\
                print done\n";
    let dir = std::env::temp_dir().join(format!("dpdnl-control-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("in.loop");
    std::fs::write(&path, text).unwrap();
    let mut console = dpdnl::Collect::default();
    let opts = dpdnl::input::Options::default();
    let mut interp = dpdnl::Interpreter::new(&mut console, &opts).unwrap();
    interp.run_file(&path).unwrap();
    drop(interp);
    assert_eq!(console.0, ["pass 1", "pass 2", "pass 3", "done"]);
    // The same loop in the text itself (SELF: the text being read), with index values and an
    // if that leaves it.
    let out = printed(
        "variable n index 10 20 30\n\
         label again\n\
         print \"n = $n\"\n\
         if \"$n == 20\" then \"jump SELF out\"\n\
         next n\n\
         jump SELF again\n\
         label out\n\
         print left\n",
    );
    assert_eq!(out, ["n = 10", "n = 20", "left"]);
}

#[test]
fn loop_variable_pad_and_range() {
    let out = printed(
        "variable k loop 8 10 pad\n\
         label l\n\
         print $k\n\
         next k\n\
         jump SELF l\n",
    );
    assert_eq!(out, ["08", "09", "10"]);
}

#[test]
fn refusals_name_what_is_wrong() {
    assert!(refused("if \"1 < a\" then \"print x\"\n").contains("operate on numbers only"));
    assert!(refused("if \"a == 1\" then \"print x\"\n").contains("with a number"));
    assert!(refused("if \"1 =< 2\" then \"print x\"\n").contains("invalid Boolean syntax"));
    assert!(refused("if \"1\" than \"print x\"\n").contains("expected 'then'"));
    assert!(refused("if \"1\" then\n").contains("missing arguments"));
    assert!(refused("jump SELF nowhere\n").contains("label 'nowhere' not found"));
    assert!(refused("variable e equal 1\nnext e\n").contains("not an index or loop variable"));
    assert!(refused("run_style respa 2 2\n").contains("run_style respa is not supported"));
}

mod plugin_support;

/// The lines of a LAMMPS log or screen text that a script's `print`, `fix print`, `if` and
/// `run every` commands wrote: those starting with "out:".
fn out_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.starts_with("out:"))
        .map(str::to_string)
        .collect()
}

/// The same script in both engines: the lines its `if`, loop, `run every` and `fix print`
/// commands print, and the `fix print` file, are the same text (values printed to 10
/// significant digits: the engines' thermo values agree to ~1e-14 relative, see the golden
/// case in.control_if_loop_every_3d).
#[test]
fn printed_lines_and_fix_print_file_match_lammps() {
    let Some(lmp) = plugin_support::lmp_dpdnl("script control against LAMMPS") else {
        return;
    };
    let dir = plugin_support::work_dir("control", "print");
    std::fs::create_dir_all(&dir).unwrap();
    let data = plugin_support::root().join("tests/data/crosscheck/dpd3d.data");
    let script = format!(
        "units lj\natom_style atomic\natom_modify map yes\ncomm_modify vel yes\nread_data {}\nmass * 1.0\n\
         pair_style dpd/nonlinear 1.0 1.0 5 friction dot\npair_coeff * * 25.0 4.5 0.5\n\
         run_style verlet\nfix 1 all nve\nthermo 100\n\
         variable t string yes\n\
         if \"$t == yes\" then \"print 'out: if t = $t'\" else \"print 'out: no'\"\n\
         fix p all print 3 \"out: step $(step) T $(temp:%.10g) pe $(pe:%.10g)\" file fp.txt title \"# fix p\"\n\
         variable i loop 2\nlabel again\nrun 4\n\
         if \"$i == 1\" then \"print 'out: first loop'\" elif \"$i == 2\" \"print 'out: second loop'\"\n\
         next i\njump SELF again\n\
         run 6 every 4 \"print 'out: chunk to $(step) Pxx $(pxx:%.10g)'\"\n\
         unfix p\nprint \"out: done at $(step)\"\n\
         variable xr equal x[3]+2*vy[7]\n\
         print \"out: atoms $(x[3]:%.10g) $(vy[7]:%.10g) $(fz[7]:%.10g) $(mass[7]) $(type[7]) $(id[7]) $(v_xr:%.10g)\"\n",
        data.display()
    );
    let input = dir.join("in.control");
    std::fs::write(&input, &script).unwrap();
    // LAMMPS: -echo none, so only what the commands print is in its log.
    let out = std::process::Command::new(&lmp)
        .args(["-in", "in.control", "-log", "lammps.log", "-echo", "none"])
        .current_dir(&dir)
        .output()
        .expect("run lmp_dpdnl");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lammps = out_lines(&std::fs::read_to_string(dir.join("lammps.log")).unwrap());
    let lammps_file = std::fs::read_to_string(dir.join("fp.txt")).unwrap();
    std::fs::remove_file(dir.join("fp.txt")).unwrap();
    // The standalone engine, in the same folder (the fix print file is relative).
    let mut console = dpdnl::Collect::default();
    let opts = dpdnl::input::Options::default();
    let here = std::env::current_dir().unwrap();
    std::env::set_current_dir(&dir).unwrap();
    let r = dpdnl::Interpreter::new(&mut console, &opts)
        .unwrap()
        .run_file(&input);
    std::env::set_current_dir(here).unwrap();
    r.unwrap();
    let standalone = out_lines(&console.0.join("\n"));
    let standalone_file = std::fs::read_to_string(dir.join("fp.txt")).unwrap();
    assert!(lammps.len() >= 10, "{lammps:?}");
    assert_eq!(standalone, lammps);
    assert_eq!(standalone_file, lammps_file);
    assert!(lammps_file.starts_with("# fix p\n"), "{lammps_file}");
}
