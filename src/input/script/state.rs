//! Crosscheck's "from LAMMPS's state" mode: the standalone engine runs a script whose set-up
//! (everything before its first top-level `run`) LAMMPS has already run and written out
//! (`write_data`, and the group memberships), so that both engines start the run from the same
//! state, whatever commands built it.
//!
//! In this mode, up to the line of the first top-level `run` ([`FromState::run_line`]):
//!
//! - the command that creates the box (`create_box`, `read_data`) installs LAMMPS's state
//!   instead: box and tilt, atoms (ids, types, molecules, positions, image flags, the atom
//!   style's columns), velocities, masses, bonds and angles, and the step of the data file's
//!   title; `read_data` also applies its own file's coefficient sections (LAMMPS's state is
//!   written with `nocoeff`);
//! - the commands whose effect that state carries are accepted without running and logged as
//!   such ([`CARRIED`]: `lattice`, `create_atoms`, `velocity`, `set`, `delete_atoms`,
//!   `displace_atoms`, `minimize`, `mass`, …), and so are `region` commands this engine cannot
//!   parse (only the atoms they placed matter once the state is installed) and `group`
//!   commands: each group takes LAMMPS's membership at the end of the set-up
//!   ([`FromState::group_dump`]); `group ID delete` runs as written;
//! - every other command runs as usual (units, styles, coefficients, fixes, computes, output).
//!
//! From the run line on, the script runs normally. A `run` met before it (in an `include`d
//! file) is an error: the split is textual, at the first `run` of the script itself.

use super::{CmdResult, Interpreter};
use crate::io::data::{DataFile, parse_data_columns};
use std::path::PathBuf;

/// Where LAMMPS's state is, for [`super::Options::from_state`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FromState {
    /// The data file LAMMPS's `write_data … nocoeff` wrote at the end of the set-up.
    pub data: PathBuf,
    /// The group memberships: a `write_dump … custom` file with the columns `id` and one 0/1
    /// column per group, in the order of `groups` (None: the set-up defines no group).
    pub group_dump: Option<PathBuf>,
    /// The groups of `group_dump`'s columns.
    pub groups: Vec<String>,
    /// The 1-based line of the script's first top-level `run` (see [`first_run_line`]).
    pub run_line: usize,
}

/// What a run from LAMMPS's state did with the set-up, for crosscheck's verdict.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateReport {
    /// The step of LAMMPS's state.
    pub step: u64,
    /// The number of atoms installed.
    pub atoms: usize,
    /// The set-up commands LAMMPS's state carries, not run here: (line, command words).
    pub carried: Vec<(usize, String)>,
    /// What LAMMPS's set-up made that the standalone engine could not take over, each with the
    /// reason.
    pub not_carried: Vec<String>,
}

/// The state mode's progress inside an [`Interpreter`].
#[derive(Debug)]
pub(super) struct StateMode {
    spec: FromState,
    /// True until the run line is reached.
    active: bool,
    installed: bool,
    report: StateReport,
    /// The group memberships of the group dump (name, member ids), once read.
    members: Option<Vec<(String, Vec<u32>)>>,
}

impl StateMode {
    pub(super) fn new(spec: FromState) -> StateMode {
        StateMode {
            spec,
            active: true,
            installed: false,
            report: StateReport::default(),
            members: None,
        }
    }

    /// The ids of the members of group `name` in LAMMPS's state (None: not in the group dump).
    fn members(&mut self, name: &str) -> Result<Option<Vec<u32>>, String> {
        if self.members.is_none() {
            self.members = Some(match &self.spec.group_dump {
                Some(p) => read_group_dump(p, &self.spec.groups)?,
                None => Vec::new(),
            });
        }
        Ok(self
            .members
            .as_ref()
            .and_then(|m| m.iter().find(|(g, _)| g == name))
            .map(|(_, t)| t.clone()))
    }
}

/// The memberships of `groups` in a `write_dump … custom … id v_…` file whose columns after
/// `id` are the groups' 0/1 masks, in order.
fn read_group_dump(
    path: &std::path::Path,
    groups: &[String],
) -> Result<Vec<(String, Vec<u32>)>, String> {
    let file = path.display();
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read LAMMPS's group memberships {file}: {e}"))?;
    let frames = crate::io::dump_read::parse_dump(&text).map_err(|e| format!("{file}: {e}"))?;
    let f = frames
        .first()
        .ok_or_else(|| format!("{file}: no frame of group memberships"))?;
    if f.columns.len() != groups.len() + 1 || f.columns.first().map(String::as_str) != Some("id") {
        return Err(format!(
            "{file}: columns {:?}, expected id and one per group {groups:?}",
            f.columns
        ));
    }
    Ok(groups
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let tags = f
                .rows
                .iter()
                .filter(|r| r.get(k + 1).is_some_and(|&m| m != 0.0))
                .filter_map(|r| r.first().map(|&id| id as u32))
                .collect();
            (g.clone(), tags)
        })
        .collect())
}

/// The set-up commands whose effect LAMMPS's state carries: accepted and not run before the
/// first `run` in the state mode.
pub const CARRIED: &[&str] = &[
    "lattice",
    "create_atoms",
    "velocity",
    "set",
    "delete_atoms",
    "displace_atoms",
    "minimize",
    "min_style",
    "min_modify",
    "mass",
    "reset_atoms",
    "reset_atom_ids",
    "replicate",
];

/// The 1-based line of the first `run` command of the script text itself (a logical line whose
/// first word is `run`, after comments; `include`d files and loops are not looked into), or
/// None.
pub fn first_run_line(text: &str) -> Option<usize> {
    crate::input::lexer::logical_lines(text)
        .into_iter()
        .find(|l| {
            crate::input::lexer::strip_comment(&l.text)
                .split_whitespace()
                .next()
                == Some("run")
        })
        .map(|l| l.line)
}

/// The groups the set-up (the lines before `run_line`) defines, in order of first definition,
/// without `all` and those deleted again (`group ID delete`); a name holding a `$` is left out
/// (its value is the interpreter's), and returned in the second list.
pub fn setup_groups(text: &str, run_line: usize) -> (Vec<String>, Vec<String>) {
    let mut groups: Vec<String> = Vec::new();
    let mut unnamed = Vec::new();
    for l in crate::input::lexer::logical_lines(text) {
        if l.line >= run_line {
            break;
        }
        let w: Vec<&str> = crate::input::lexer::strip_comment(&l.text)
            .split_whitespace()
            .collect();
        if w.len() < 3 || w[0] != "group" || w[1] == "all" {
            continue;
        }
        if w[1].contains('$') {
            unnamed.push(w.join(" "));
            continue;
        }
        if w[2] == "delete" {
            groups.retain(|g| g != w[1]);
        } else if !groups.iter().any(|g| g == w[1]) {
            groups.push(w[1].to_string());
        }
    }
    (groups, unnamed)
}

/// The step in the title of a data file LAMMPS's `write_data` wrote (`… timestep = N`, its
/// first line), or None.
fn title_step(text: &str) -> Option<u64> {
    let first = text.lines().next()?;
    let (_, rest) = first.split_once("timestep = ")?;
    rest.split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()
}

impl Interpreter<'_> {
    /// The report of the state mode, when the interpreter runs from LAMMPS's state.
    pub fn state_report(&self) -> Option<&StateReport> {
        self.state.as_ref().map(|s| &s.report)
    }

    /// In the state mode, before the run line: the command at `line` (of the script itself when
    /// `depth` is 0) handled here (Some) or left to the dispatch (None).
    pub(super) fn state_command(
        &mut self,
        line: usize,
        cmd: &str,
        args: &[String],
    ) -> Option<CmdResult> {
        let depth = self.depth;
        let st = self.state.as_mut().filter(|s| s.active)?;
        if depth == 0 && line >= st.spec.run_line {
            st.active = false;
            if !st.installed {
                return Some(Err(
                    "the set-up before the first run made no box (create_box or read_data), \
                     so there was no LAMMPS state to install"
                        .into(),
                ));
            }
            return None;
        }
        let words = || std::iter::once(cmd.to_string()).chain(args.iter().cloned());
        let shown = words().collect::<Vec<_>>().join(" ");
        match cmd {
            "run" => Some(Err(format!(
                "a run before the script's first top-level run (line {}): crosscheck from \
                 LAMMPS's state splits the script at that line, so the set-up may not run \
                 steps itself (in an include file or a loop)",
                st.spec.run_line
            ))),
            "create_box" | "read_data" if !st.installed => Some(self.install_state(cmd, args)),
            "create_box" | "read_data" => Some(self.carried(line, shown)),
            c if CARRIED.contains(&c) => Some(self.carried(line, shown)),
            "group" if args.get(1).map(String::as_str) == Some("delete") => None,
            "group" => Some(self.carried_group(line, shown, args)),
            "region" => match self.cmd_region(args) {
                Ok(()) => Some(Ok(())),
                Err(e) => {
                    let carried = self.carried(line, shown);
                    let st = self.state.as_mut()?;
                    st.report.not_carried.push(format!(
                        "region {} (this engine cannot define it: {e}); only the atoms LAMMPS \
                         placed with it are carried",
                        args.first().map_or("", String::as_str)
                    ));
                    Some(carried)
                }
            },
            _ => None,
        }
    }

    /// Logs a carried command and records it for the report.
    fn carried(&mut self, line: usize, shown: String) -> CmdResult {
        self.out(&format!("carried by LAMMPS's state (not run): {shown}"));
        if let Some(st) = self.state.as_mut() {
            st.report.carried.push((line, shown));
        }
        Ok(())
    }

    /// A `group` of the set-up: its membership is LAMMPS's at the end of the set-up (the
    /// group dump's column of it); a group the dump lacks is named as not carried.
    fn carried_group(&mut self, line: usize, shown: String, args: &[String]) -> CmdResult {
        self.carried(line, shown)?;
        let name = args.first().cloned().unwrap_or_default();
        let members = self
            .state
            .as_mut()
            .map(|st| st.members(&name))
            .transpose()?
            .flatten();
        match members {
            Some(tags) => {
                self.sys_mut()?.set_group_members(&name, &tags)?;
            }
            None => {
                if let Some(st) = self.state.as_mut()
                    && !st
                        .report
                        .not_carried
                        .iter()
                        .any(|n| n.starts_with(&format!("group {name} ")))
                {
                    st.report.not_carried.push(format!(
                        "group {name} (LAMMPS's state has no membership of it: a group deleted \
                         or named by a variable in the set-up)"
                    ));
                }
            }
        }
        Ok(())
    }

    /// `create_box` or `read_data` in the state mode: the box and atoms of LAMMPS's state,
    /// with, for `read_data`, its own file's coefficient sections.
    fn install_state(&mut self, cmd: &str, args: &[String]) -> CmdResult {
        let Some(spec) = self.state.as_ref().map(|s| s.spec.clone()) else {
            return Ok(());
        };
        let file = spec.data.display().to_string();
        let text = std::fs::read_to_string(&spec.data)
            .map_err(|e| format!("cannot read LAMMPS's state {file}: {e}"))?;
        let mut d: DataFile = parse_data_columns(&text, &file, &self.atom_columns)
            .map_err(|e| format!("LAMMPS's state: {e}"))?;
        let step = title_step(&text)
            .ok_or_else(|| format!("LAMMPS's state {file}: no 'timestep = N' in its title line"))?;
        let mut nocoeff = false;
        if cmd == "read_data" {
            let own = self.read_data_file(args)?;
            d.coeffs = own.0.coeffs;
            nocoeff = own.1;
        }
        let n = d.atoms.len();
        self.fill_new_system(d, nocoeff, &file)?;
        self.sys_mut()?.step = step;
        self.out(&format!(
            "{cmd}: LAMMPS's state installed from {file}: {n} atoms at step {step}"
        ));
        if let Some(st) = self.state.as_mut() {
            st.installed = true;
            st.report.step = step;
            st.report.atoms = n;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_run_line_skips_comments_and_continuations() {
        let text =
            "units lj\n# run 5\nvariable a &\n  equal 1\nfix 1 all nve # run\nrun 10\nrun 5\n";
        assert_eq!(first_run_line(text), Some(6));
        assert_eq!(first_run_line("units lj\n"), None);
        assert_eq!(first_run_line("  run\t100 every 5 NULL\n"), Some(1));
    }

    #[test]
    fn setup_groups_in_order_without_deleted_ones() {
        let text = "group a type 1\ngroup b id 1 2\ngroup a type 2\ngroup c type 1\n\
                    group c delete\ngroup ${g} type 1\ngroup all type 1\nrun 5\ngroup d type 1\n";
        let (g, unnamed) = setup_groups(text, 8);
        assert_eq!(g, ["a", "b"]);
        assert_eq!(unnamed, ["group ${g} type 1"]);
    }

    #[test]
    fn the_step_of_write_data_titles() {
        let t = "LAMMPS data file via write_data, version 7 Jan 2022, timestep = 1234\n\n";
        assert_eq!(title_step(t), Some(1234));
        let t = "LAMMPS data file via write_data, version 22 Jul 2025, timestep = 0, units = lj\n";
        assert_eq!(title_step(t), Some(0));
        assert_eq!(title_step("a title\n"), None);
    }
}
