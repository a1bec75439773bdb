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
