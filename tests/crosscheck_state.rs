//! `dpdnl crosscheck --from lammps` (issue 56, item 1): both engines start the run from the
//! state LAMMPS reaches after the script's set-up.
//!
//! The interpreter's state mode is tested here without LAMMPS (a hand-written state file in
//! LAMMPS's write_data layout); the golden case runs a script written by others, LAMMPS's own
//! `dpdext` example (`validation/corpus/lammps-dpdext/in.dpdext`: lattice, create_atoms random,
//! velocity create, run_style verlet), with `build/lmp_dpdnl` (skipped without it, unless
//! DPDNL_REQUIRE_LAMMPS is set).

mod plugin_support;

use dpdnl::input::{Collect, FromState, Interpreter, Options};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// A state file as LAMMPS's `write_data … nocoeff` writes it: 3 atoms, step 40.
const STATE: &str = "LAMMPS data file via write_data, version 7 Jan 2022, timestep = 40\n\n\
3 atoms\n2 atom types\n\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\nMasses\n\n1 1\n2 2\n\n\
Atoms # atomic\n\n1 1 0.5 0.5 0.5 0 0 0\n2 2 1.25 0.5 0.5 1 0 0\n3 1 3.5 3.5 3.5 0 0 -1\n\n\
Velocities\n\n1 0.125 0 0\n2 -0.0625 0 0\n3 0 0 0.5\n";

/// Runs `script` (written to `dir/in.test`) from the state `STATE` with its set-up ending at
/// the line of its first `run`; the interpreter's result and console.
fn run_from_state(dir: &Path, script: &str) -> (Result<(), String>, Vec<String>, Interp) {
    let data = dir.join("state.data");
    std::fs::write(&data, STATE).expect("state file");
    let path = dir.join("in.test");
    std::fs::write(&path, script).expect("script");
    let run_line = dpdnl::input::first_run_line(script).unwrap_or(usize::MAX);
    let opts = Options {
        from_state: Some(FromState {
            data,
            run_line,
            ..FromState::default()
        }),
        threads: 1,
        ..Options::default()
    };
    let mut console = Collect::default();
    let (res, report, atoms) = {
        let mut it = Interpreter::new(&mut console, &opts).expect("interpreter");
        let res = it.run_file(&path).map_err(|e| e.to_string());
        let atoms = it.system().map(|s| {
            let mut a: Vec<AtomRow> = (0..s.atoms.len())
                .map(|i| {
                    (
                        s.atoms.tag[i],
                        s.atoms.x[i],
                        s.atoms.v[i],
                        s.atoms.image[i],
                        s.step,
                    )
                })
                .collect();
            a.sort_by_key(|r| r.0);
            a
        });
        (res, it.state_report().cloned(), atoms)
    };
    (res, console.0, Interp { report, atoms })
}

/// One atom after the run: id, position, velocity, image flags, the system's step.
type AtomRow = (u32, [f64; 3], [f64; 3], [i32; 3], u64);

struct Interp {
    report: Option<dpdnl::input::StateReport>,
    atoms: Option<Vec<AtomRow>>,
}

const PRELUDE: &str = "units lj\natom_style atomic\nboundary p p p\n";

/// The state is installed at `create_box`: LAMMPS's atoms, velocities, image flags and step;
/// the commands it carries are logged and not run (a `create_atoms` on a region shape this
/// engine cannot define, a `velocity create` whose numbers would be this engine's, `mass`), a
/// region it cannot parse is named as not carried, and after the run line the script runs as
/// usual.
#[test]
fn the_state_replaces_the_set_up() {
    let dir = scratch("state_mode_install");
    let script = format!(
        "{PRELUDE}lattice fcc 3.0\nregion b block 0 4 0 4 0 4 units box\n\
         region c cylinder z 2 2 1 INF INF\ncreate_box 2 b\n\
         create_atoms 1 region c\nmass * 1.0\nvelocity all create 1.0 4928459\n\
         group heavy type 2\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nfix 1 all nve\n\
         run 0\nvelocity all set 0 0 0\nrun 0\n"
    );
    let (res, out, it) = run_from_state(&dir, &script);
    res.unwrap_or_else(|e| panic!("{e}\n{}", out.join("\n")));
    let r = it.report.expect("a state report");
    assert_eq!((r.step, r.atoms), (40, 3));
    let carried: Vec<&str> = r
        .carried
        .iter()
        .map(|(_, c)| c.split_whitespace().next().unwrap_or(""))
        .collect();
    assert_eq!(
        carried,
        [
            "lattice",
            "region",
            "create_atoms",
            "mass",
            "velocity",
            "group"
        ]
    );
    assert_eq!(r.carried[0].0, 4, "{:?}", r.carried);
    assert!(
        r.not_carried.iter().any(|n| n.starts_with("region c ")),
        "{:?}",
        r.not_carried
    );
    // No group dump here: the group is named as not carried.
    assert!(
        r.not_carried.iter().any(|n| n.starts_with("group heavy ")),
        "{:?}",
        r.not_carried
    );
    assert!(
        out.iter()
            .any(|l| l == "carried by LAMMPS's state (not run): velocity all create 1.0 4928459"),
        "{out:?}"
    );
    // After the run line the script runs: the second velocity command zeroed the velocities.
    let atoms = it.atoms.expect("a system");
    assert_eq!(atoms.len(), 3);
    assert_eq!(atoms[2].1, [3.5, 3.5, 3.5]);
    assert_eq!(atoms[2].3, [0, 0, -1]);
    assert_eq!(atoms[1].3, [1, 0, 0]);
    assert!(atoms.iter().all(|a| a.2 == [0.0; 3] && a.4 == 40));
}

/// Without `velocity all set` after the run line, the velocities are LAMMPS's exactly.
#[test]
fn the_state_carries_velocities_and_masses_exactly() {
    let dir = scratch("state_mode_velocities");
    let script = format!(
        "{PRELUDE}region b block 0 4 0 4 0 4\ncreate_box 2 b\nmass 1 7.0\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nrun 0\n"
    );
    let (res, out, it) = run_from_state(&dir, &script);
    res.unwrap_or_else(|e| panic!("{e}\n{}", out.join("\n")));
    let atoms = it.atoms.expect("a system");
    let v: Vec<[f64; 3]> = atoms.iter().map(|a| a.2).collect();
    assert_eq!(v, [[0.125, 0.0, 0.0], [-0.0625, 0.0, 0.0], [0.0, 0.0, 0.5]]);
}

/// The refusals of the state mode: a set-up that runs steps itself (a run in an include file
/// before the script's first run), and one that makes no box before the run line.
#[test]
fn state_mode_refusals_name_the_line() {
    let dir = scratch("state_mode_refusals");
    std::fs::write(dir.join("inc.in"), "run 5\n").expect("include");
    let script = format!(
        "{PRELUDE}region b block 0 4 0 4 0 4\ncreate_box 2 b\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\n\
         include {}\nrun 0\n",
        dir.join("inc.in").display()
    );
    let (res, _, _) = run_from_state(&dir, &script);
    let e = res.expect_err("a run in the set-up");
    assert!(
        e.contains("inc.in:1: run: a run before the script's first top-level run (line 9)"),
        "{e}"
    );
    let (res, _, _) = run_from_state(&dir, &format!("{PRELUDE}run 0\n"));
    let e = res.expect_err("no box");
    assert!(
        e.contains(":4: run: the set-up before the first run made no box"),
        "{e}"
    );
}

/// `run_style verlet` is the standalone engine's own loop; other run styles are refused.
#[test]
fn run_style_verlet_only() {
    let mut c = Collect::default();
    let mut it = Interpreter::new(&mut c, &Options::default()).expect("interpreter");
    it.run_text("run_style verlet\n", "t").expect("verlet");
    let e = it.run_text("run_style respa 2 2\n", "t").unwrap_err();
    assert_eq!(e.line, 1);
    assert!(
        e.message
            .starts_with("run_style respa is not supported: the standalone engine has one force"),
        "{e}"
    );
}

/// LAMMPS's `dpdext` example, migrated and shortened (see the test below), with `fix_line`
/// in place of its `fix 1 all nve` (when not empty) and `after` after its run.
fn dpdext_copy(fix_line: &str, after: &str) -> String {
    let original = plugin_support::read(
        &plugin_support::root().join("validation/corpus/lammps-dpdext/in.dpdext"),
    );
    let mut script = String::new();
    for line in original.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first().copied() {
            Some("pair_style") => {
                assert_eq!(w[1], "dpd/ext", "{line}");
                script.push_str(&line.replacen("dpd/ext", "dpd/nonlinear/ext", 1));
            }
            Some("run") => {
                script.push_str("run 100");
                script.push_str(after);
            }
            Some("thermo") => script.push_str(
                "thermo 20\nthermo_modify format float %20.15g\n\
                 dump d all custom 50 dump.${engine} id x y z vx vy vz fx fy fz\n\
                 dump_modify d format float %20.15g",
            ),
            Some("fix") if !fix_line.is_empty() => script.push_str(fix_line),
            _ => script.push_str(line),
        }
        script.push('\n');
    }
    script
}

/// LAMMPS's own `dpdext` example, migrated (`dpd/ext` → `dpd/nonlinear/ext`, the same words:
/// docs/manual/migration.md) and shortened to 100 steps, thermo every 20 steps and a dump at
/// steps 0, 50 and 100 at full precision (the corpus file is not edited: the copy is made here).
/// The standalone engine cannot build it (`lattice`, `create_atoms … random` on LAMMPS's
/// generator, `velocity create`), so crosscheck runs from LAMMPS's state: it must AGREE within
/// the golden cases' rtol 1e-9, atol 1e-9, and name what the state carried.
#[test]
fn corpus_dpdext_from_lammps_state_agrees() {
    let Some(lmp) = plugin_support::lmp_dpdnl("crosscheck from LAMMPS's state") else {
        return;
    };
    let script = dpdext_copy("", "");
    for needed in [
        "lattice",
        "create_atoms 1 random",
        "velocity all create",
        "run_style",
    ] {
        assert!(script.contains(needed), "{needed}: {script}");
    }
    let dir = scratch("crosscheck_state_dpdext");
    let path = dir.join("in.dpdext");
    std::fs::write(&path, &script).expect("script");
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("crosscheck")
        .arg(&path)
        .arg("--lmp")
        .arg(&lmp)
        .arg("--workdir")
        .arg(dir.join("work"))
        .args(["--threads", "2", "--atol", "1e-9"])
        .output()
        .expect("run dpdnl crosscheck");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("note: the standalone engine cannot build this system (/")
            && stdout.contains("in.dpdext:16: lattice: unknown command 'lattice'")
            && stdout.contains("); crosschecking from LAMMPS's state (--from lammps)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("from LAMMPS's state: 200 atoms at step 0"),
        "{stdout}"
    );
    let verdict = stdout.lines().last().unwrap_or("");
    assert!(
        verdict.starts_with("CROSSCHECK AGREE: thermo log and 1 dump(s), 600 atom rows"),
        "{verdict}"
    );
    assert!(
        verdict.ends_with(
            "from LAMMPS's state at step 0 (carried: the box and atoms, lattice, create_atoms \
             x2, mass x2, velocity; not carried: nothing)"
        ),
        "{verdict}"
    );
    // `--from script` refuses at the set-up, naming the command.
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("crosscheck")
        .arg(&path)
        .arg("--lmp")
        .arg(&lmp)
        .arg("--workdir")
        .arg(dir.join("work2"))
        .args(["--from", "script"])
        .output()
        .expect("run dpdnl crosscheck");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("in.dpdext:16: lattice: unknown command"),
        "{stderr}"
    );
}

/// Groups from LAMMPS's state: the dpdext example with three groups made in its set-up (a
/// region, a type, their intersection), a `velocity … set` on one of them in the set-up, a dump
/// of another, and `velocity left set 0 0 0` between two runs: the standalone engine takes each
/// group's membership from LAMMPS (`gmask()`), and the engines AGREE.
#[test]
fn corpus_dpdext_groups_from_lammps_state_agree() {
    let Some(lmp) = plugin_support::lmp_dpdnl("crosscheck from LAMMPS's state") else {
        return;
    };
    let script = dpdext_copy(
        "region half block 0 2.5 INF INF INF INF units box\ngroup left region half\n\
         group heavy type 2\ngroup lh intersect left heavy\nvelocity lh set 0 0 0\n\
         fix 1 all nve\ndump h lh custom 50 dump.lh.${engine} id vx vy vz\n\
         dump_modify h format float %20.15g",
        "\nvelocity left set 0 0 0\nrun 50",
    );
    let dir = scratch("crosscheck_state_groups");
    let path = dir.join("in.groups");
    std::fs::write(&path, &script).expect("script");
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("crosscheck")
        .arg(&path)
        .arg("--lmp")
        .arg(&lmp)
        .arg("--workdir")
        .arg(dir.join("work"))
        .args(["--threads", "2", "--atol", "1e-9", "--from", "lammps"])
        .output()
        .expect("run dpdnl crosscheck");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stdout}\n{stderr}");
    let verdict = stdout.lines().last().unwrap_or("");
    assert!(
        verdict.starts_with("CROSSCHECK AGREE: thermo log and 2 dump(s)"),
        "{verdict}"
    );
    assert!(
        verdict.contains("velocity x2, group x3; not carried: nothing)"),
        "{verdict}"
    );
    // The intersection holds some atoms but not all: the dump of it is not trivially empty.
    let text = plugin_support::read(&dir.join("work/dump.lh.standalone"));
    let rows = dpdnl::io::dump_read::parse_dump(&text).expect("dump")[0]
        .rows
        .len();
    assert!(rows > 10 && rows < 100, "{rows} atoms in lh");
}

/// A group of the set-up takes LAMMPS's membership from the group dump, whatever its own
/// command says (here `type 1`, while LAMMPS's dump puts atoms 2 and 3 in it).
#[test]
fn groups_take_lammps_membership() {
    let dir = scratch("state_mode_groups");
    let dump = dir.join("groups.dump");
    std::fs::write(
        &dump,
        "ITEM: TIMESTEP\n40\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n\
         ITEM: ATOMS id v_dpdnl_group_0\n1 0\n2 1\n3 1\n",
    )
    .expect("dump");
    let data = dir.join("state.data");
    std::fs::write(&data, STATE).expect("state file");
    let script = format!(
        "{PRELUDE}region b block 0 4 0 4 0 4\ncreate_box 2 b\ngroup g type 1\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25 4.5 0\nrun 0\n"
    );
    let path = dir.join("in.test");
    std::fs::write(&path, &script).expect("script");
    let opts = Options {
        from_state: Some(FromState {
            data,
            group_dump: Some(dump),
            groups: vec!["g".into()],
            run_line: 9,
        }),
        threads: 1,
        ..Options::default()
    };
    let mut console = Collect::default();
    let mut it = Interpreter::new(&mut console, &opts).expect("interpreter");
    it.run_file(&path).expect("runs");
    let sys = it.system().expect("a system");
    let bit = sys.groups.bit("g").expect("group g");
    let mut members: Vec<u32> = (0..sys.atoms.len())
        .filter(|&i| sys.atoms.mask_of(i) & bit != 0)
        .map(|i| sys.atoms.tag[i])
        .collect();
    members.sort_unstable();
    assert_eq!(members, [2, 3]);
    assert!(it.state_report().expect("report").not_carried.is_empty());
}

/// The atom styles of item 2 from LAMMPS's state: the dpdext example under `atom_style charge`
/// and `hybrid bond charge` (LAMMPS's write_data writes their columns, the standalone engine
/// reads them) agrees as under `atomic`.
#[test]
fn corpus_dpdext_charge_styles_from_lammps_state_agree() {
    let Some(lmp) = plugin_support::lmp_dpdnl("crosscheck from LAMMPS's state") else {
        return;
    };
    for (k, style) in ["charge", "hybrid bond charge"].iter().enumerate() {
        let script: String = dpdext_copy("", "")
            .lines()
            .map(|l| {
                if l.starts_with("atom_style") {
                    format!("atom_style {style}\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        let dir = scratch(&format!("crosscheck_state_style{k}"));
        let path = dir.join("in.style");
        std::fs::write(&path, &script).expect("script");
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(&path)
            .arg("--lmp")
            .arg(&lmp)
            .arg("--workdir")
            .arg(dir.join("work"))
            .args(["--threads", "2", "--atol", "1e-9"])
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{style}: {stdout}\n{stderr}");
        let state = plugin_support::read(&dir.join("work/lammps-state.data"));
        let hint = style.split_whitespace().next().unwrap_or("");
        assert!(state.contains(&format!("Atoms # {hint}")), "{state}");
        let verdict = stdout.lines().last().unwrap_or("");
        assert!(
            verdict.starts_with("CROSSCHECK AGREE: thermo log and 1 dump(s), 600 atom rows"),
            "{style}: {verdict}"
        );
    }
}
