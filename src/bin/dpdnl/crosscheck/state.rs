//! A crosscheck from LAMMPS's state (`--from lammps`): LAMMPS runs the script's set-up (its
//! text up to the first top-level `run`) and writes its exact state (`write_data … nocoeff`:
//! box, tilt, atoms with their style's columns and image flags, velocities, masses, topology,
//! the step in the title; each group's membership through `gmask()` in a `write_dump`), which
//! the standalone engine then installs in place of its own set-up
//! ([`dpdnl::input::FromState`]).

use super::CannotRun;
use dpdnl::input::{FromState, StateReport, first_run_line, setup_groups};
use std::fmt::Write as _;
use std::path::Path;

/// The file names, in the work directory, of LAMMPS's set-up script, its log and its state.
const SETUP_IN: &str = "lammps-setup.in";
const SETUP_LOG: &str = "lammps-setup.log";
const STATE_DATA: &str = "lammps-state.data";
const GROUPS_DUMP: &str = "lammps-groups.dump";

/// `s` as one LAMMPS word (quoted when it holds a space or a quote).
fn word(s: &str) -> String {
    if s.contains([' ', '"', '\'', '#', '$']) {
        format!("\"\"\"{s}\"\"\"")
    } else {
        s.to_string()
    }
}

/// LAMMPS's set-up script: the lines of `text` before `run_line`, then the commands that write
/// its state into `workdir`.
fn setup_script(text: &str, run_line: usize, groups: &[String], workdir: &Path) -> String {
    let mut s: String =
        text.lines()
            .take(run_line.saturating_sub(1))
            .fold(String::new(), |mut s, l| {
                s.push_str(l);
                s.push('\n');
                s
            });
    let path = |name: &str| word(&workdir.join(name).display().to_string());
    let _ = writeln!(
        s,
        "\n# dpdnl crosscheck --from lammps: the state at the start of the first run"
    );
    let _ = writeln!(s, "write_data {} nocoeff", path(STATE_DATA));
    if !groups.is_empty() {
        let mut cols = String::new();
        for (k, g) in groups.iter().enumerate() {
            let _ = writeln!(s, "variable dpdnl_group_{k} atom gmask({g})");
            let _ = write!(cols, " v_dpdnl_group_{k}");
        }
        let _ = writeln!(
            s,
            "write_dump all custom {} id{cols} modify sort id",
            path(GROUPS_DUMP)
        );
    }
    s
}

/// Runs the set-up of `script` in LAMMPS (`lmp`, in the current directory: the script's) and
/// returns where its state is, for the standalone engine.
pub(super) fn lammps_state(
    lmp: &Path,
    script: &Path,
    workdir: &Path,
    vars: &[(String, String)],
) -> Result<FromState, CannotRun> {
    let text = std::fs::read_to_string(script)
        .map_err(|e| CannotRun(format!("cannot read {}: {e}", script.display())))?;
    let run_line = first_run_line(&text).ok_or_else(|| {
        CannotRun(format!(
            "{}: no `run` command in the script itself, so there is no set-up to take from \
             LAMMPS (crosscheck --from lammps splits the script at its first top-level run; a \
             run inside an include file or a loop is not found)",
            script.display()
        ))
    })?;
    let (groups, unnamed) = setup_groups(&text, run_line);
    if let Some(g) = unnamed.first() {
        return Err(CannotRun(format!(
            "{}: `{g}`: a group named by a variable; crosscheck --from lammps needs the group \
             names written out",
            script.display()
        )));
    }
    let setup = workdir.join(SETUP_IN);
    std::fs::write(&setup, setup_script(&text, run_line, &groups, workdir))
        .map_err(|e| CannotRun(format!("cannot write {}: {e}", setup.display())))?;
    let log = workdir.join(SETUP_LOG);
    let data = workdir.join(STATE_DATA);
    let dump = workdir.join(GROUPS_DUMP);
    for f in [&data, &dump] {
        let _ = std::fs::remove_file(f);
    }
    let out = super::engines::run_lmp(lmp, &setup, &log, vars)?;
    if !out.status.success() || !data.is_file() {
        let tail = std::fs::read_to_string(&log).unwrap_or_default();
        let tail: Vec<&str> = tail.lines().rev().take(8).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(CannotRun(format!(
            "LAMMPS ({}) could not run the set-up ({}, lines 1-{} of the script, then \
             write_data); end of {}:\n{}\n{}",
            lmp.display(),
            out.status,
            run_line - 1,
            log.display(),
            tail.join("\n"),
            String::from_utf8_lossy(&out.stderr).trim_end()
        )));
    }
    Ok(FromState {
        data,
        group_dump: (!groups.is_empty()).then_some(dump),
        groups,
        run_line,
    })
}

/// The lines a crosscheck from LAMMPS's state prints before its tables: where the state came
/// from, the commands it carried and what it did not carry.
pub(super) fn report_lines(r: &StateReport, state: &FromState) -> Vec<String> {
    let mut out = vec![format!(
        "from LAMMPS's state: {} atoms at step {} ({}, the set-up before line {})",
        r.atoms,
        r.step,
        state.data.display(),
        state.run_line
    )];
    for (line, cmd) in &r.carried {
        out.push(format!("carried by LAMMPS's state: line {line}: {cmd}"));
    }
    for n in &r.not_carried {
        out.push(format!("not carried: {n}"));
    }
    out
}

/// The verdict's part on the state: `from LAMMPS's state at step N (carried: …; not carried:
/// …)`.
pub(super) fn verdict_part(r: &StateReport) -> String {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for (_, cmd) in &r.carried {
        let w = cmd.split_whitespace().next().unwrap_or("").to_string();
        match counts.iter_mut().find(|(c, _)| *c == w) {
            Some(c) => c.1 += 1,
            None => counts.push((w, 1)),
        }
    }
    let carried: Vec<String> = counts
        .iter()
        .map(|(c, n)| {
            if *n > 1 {
                format!("{c} x{n}")
            } else {
                c.clone()
            }
        })
        .collect();
    let not = if r.not_carried.is_empty() {
        "nothing".to_string()
    } else {
        r.not_carried.join("; ")
    };
    format!(
        "from LAMMPS's state at step {} (carried: {}; not carried: {not})",
        r.step,
        if carried.is_empty() {
            "the box and atoms".to_string()
        } else {
            format!("the box and atoms, {}", carried.join(", "))
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setup_script_ends_with_the_state_commands() {
        let text = "units lj\ncreate_box 1 b\nrun 10\nrun 5\n";
        let s = setup_script(text, 3, &["mobile".into()], Path::new("/w d"));
        assert!(s.starts_with("units lj\ncreate_box 1 b\n\n#"), "{s}");
        assert!(!s.contains("run 10"), "{s}");
        assert!(
            s.contains("write_data \"\"\"/w d/lammps-state.data\"\"\" nocoeff\n"),
            "{s}"
        );
        assert!(
            s.contains("variable dpdnl_group_0 atom gmask(mobile)\n"),
            "{s}"
        );
        assert!(s.contains(" id v_dpdnl_group_0 modify sort id\n"), "{s}");
    }

    #[test]
    fn the_verdict_part_counts_carried_commands() {
        let r = StateReport {
            step: 7,
            atoms: 3,
            carried: vec![
                (1, "lattice fcc 3".into()),
                (4, "create_atoms 1 random 5 1 NULL".into()),
                (5, "create_atoms 2 random 5 1 NULL".into()),
            ],
            not_carried: vec![],
        };
        assert_eq!(
            verdict_part(&r),
            "from LAMMPS's state at step 7 (carried: the box and atoms, lattice, create_atoms \
             x2; not carried: nothing)"
        );
    }
}
