//! `write_restart FILE`, `read_restart FILE` and `restart N FILE [FILE2]`: the interpreter's side
//! of the restart file ([`crate::io::restart`]; format and rules in `docs/restart.md`).
//!
//! `read_restart` restores the system (box and tilt, atoms in storage order, masses, step,
//! timestep, skin, last energy/virial) and the pair style, by re-issuing the stored
//! `pair_style`/`pair_coeff` words (so any pair style the interpreter can define is covered).
//! Fixes are re-issued by the script, as in LAMMPS; a fix with internal state gets it back when
//! it is defined again with the same ID and style ([`fix_state`] and [`restore_fix_state`]: a
//! fix with state is added to both). State no fix claimed is dropped with a warning at the next
//! run's set-up.

use super::fix::FixKind;
use super::{CmdResult, Interpreter};
use crate::engine::lees_edwards::Triclinic;
use crate::engine::topology::AtomStyle;
use crate::engine::{System, Topology};
use crate::grammar::{at_most, need, parse_int};
use crate::io::restart::{self, FixRecord, Restart, Tilt, TopoRecord};
use std::path::Path;

/// `restart N FILE [FILE2]`: write every N steps, to FILE (its `*` replaced by the step) or
/// alternately to FILE and FILE2.
#[derive(Clone, Debug)]
pub(super) struct RestartEvery {
    every: u64,
    files: Vec<String>,
    next: usize,
}

/// Fix state from a restart file that no fix has claimed yet: the file and the record.
pub(super) type PendingFix = (String, FixRecord);

impl Interpreter<'_> {
    /// `write_restart FILE`.
    pub(super) fn cmd_write_restart(&mut self, args: &[String]) -> CmdResult {
        let usage = "write_restart FILE";
        need(args, 1, usage)?;
        at_most(args, 1, usage)?;
        let step = self
            .sys
            .as_ref()
            .ok_or("needs a simulation box first")?
            .step;
        self.write_restart_file(&restart::file_for_step(&args[0], step))
    }

    /// `restart 0` or `restart N FILE [FILE2]`.
    pub(super) fn cmd_restart(&mut self, args: &[String]) -> CmdResult {
        let usage = "restart 0 | restart N FILE [FILE2]";
        need(args, 1, usage)?;
        let every: u64 = parse_int(&args[0], "restart interval N")?;
        if every == 0 {
            at_most(args, 1, "restart 0 (it takes no file name)")?;
            self.restart = None;
            return Ok(());
        }
        need(args, 2, usage)?;
        at_most(args, 3, usage)?;
        if let Some(k) = args[1..].iter().find(|a| *a == "fileper" || *a == "nfile") {
            return Err(format!(
                "restart keyword '{k}' not supported: the standalone engine writes one file"
            ));
        }
        self.restart = Some(RestartEvery {
            every,
            files: args[1..].to_vec(),
            next: 0,
        });
        Ok(())
    }

    /// `read_restart FILE`.
    pub(super) fn cmd_read_restart(&mut self, args: &[String]) -> CmdResult {
        let usage = "read_restart FILE";
        need(args, 1, usage)?;
        at_most(args, 1, usage)?;
        if self.sys.is_some() {
            return Err(
                "cannot read_restart after the simulation box is defined (read_restart creates it)"
                    .into(),
            );
        }
        let file = &args[0];
        let r = restart::read(Path::new(file)).map_err(|e| format!("restart file {file}: {e}"))?;
        let result = self.restore(r, file);
        if result.is_err() {
            self.sys = None;
        }
        result
    }

    /// Build the system from `r` and re-issue its pair style lines.
    fn restore(&mut self, r: Restart, file: &str) -> CmdResult {
        let bad = |what: String| format!("restart file {file}: {what}");
        self.dim = r.dim as usize;
        self.units = crate::units::Units::standalone(r.units.name()).map_err(bad)?;
        self.dt = r.dt;
        self.skin = r.skin;
        self.atom_style = r.topo.as_ref().map_or(AtomStyle::Atomic, |t| t.style);
        self.atom_columns = crate::io::data::AtomColumns::of(self.atom_style);
        self.atom_extra.clear();
        self.new_system(r.ntypes as usize, r.lo, r.hi)
            .map_err(bad)?;
        let natoms = r.atoms.len();
        let sys = self.sys_mut()?;
        sys.step = r.step;
        sys.mass = r.masses;
        sys.atoms = r.atoms;
        sys.groups = crate::engine::groups::Groups::from_names(r.groups).map_err(bad)?;
        sys.tally = r.tally;
        let topo_lines = match r.topo {
            Some(t) => {
                sys.atoms.mol = t.mol;
                sys.energies = t.energies;
                sys.topo = Some(Topology {
                    style: t.style,
                    nbondtypes: t.nbondtypes as usize,
                    nangletypes: t.nangletypes as usize,
                    bonds: t.bonds,
                    angles: t.angles,
                    special: t.special,
                    ..Topology::default()
                });
                t.lines
            }
            None => Vec::new(),
        };
        for line in &topo_lines {
            let Some((cmd, args)) = line.split_first() else {
                return Err(bad("an empty bond or angle style line".into()));
            };
            if !["bond_style", "bond_coeff", "angle_style", "angle_coeff"].contains(&cmd.as_str()) {
                return Err(bad(format!("'{cmd}' among the bond and angle style lines")));
            }
            self.command(cmd, args)
                .map_err(|e| bad(format!("its line '{}' is refused: {e}", line.join(" "))))?;
        }
        let sys = self.sys_mut()?;
        sys.tri = r.tilt.map(|t| {
            let mut tri = Triclinic::new(t.xy);
            tri.le.rate = t.rate;
            tri.le.offset = t.offset;
            tri
        });
        let kind = if sys.tri.is_some() {
            "triclinic"
        } else {
            "orthogonal"
        };
        for line in &r.pair {
            let Some((cmd, args)) = line.split_first() else {
                return Err(bad("an empty pair style line".into()));
            };
            if cmd != "pair_style" && cmd != "pair_coeff" {
                return Err(bad(format!("'{cmd}' among the pair style lines")));
            }
            self.command(cmd, args)
                .map_err(|e| bad(format!("its line '{}' is refused: {e}", line.join(" "))))?;
        }
        self.out(&format!(
            "Read restart file {file}: {natoms} atoms, {} atom types, {kind} box, step {}",
            r.ntypes, r.step
        ));
        if !r.fixes.is_empty() {
            self.out("  fixes when it was written (re-issue them; state comes back with the same ID and style):");
            for f in &r.fixes {
                self.out(&format!("    fix {}", f.words.join(" ")));
            }
        }
        self.restart_fixes = r
            .fixes
            .into_iter()
            .filter(|f| !f.state.is_empty())
            .map(|f| (file.to_string(), f))
            .collect();
        Ok(())
    }

    /// Write the restart file `path` (no `*` expansion) atomically.
    pub(super) fn write_restart_file(&mut self, path: &str) -> CmdResult {
        let fixes = self.fix_records();
        let sys = self.sys.as_mut().ok_or("needs a simulation box first")?;
        let pair = sys
            .pair
            .as_deref()
            .map(|p| p.restart_lines())
            .unwrap_or_default();
        // The atoms move into the record for the encoding and straight back (no copy).
        let r = Restart {
            dim: sys.dim() as u32,
            ntypes: sys.ntypes as u32,
            lo: sys.bx.lo,
            hi: sys.bx.hi,
            tilt: sys.tri.as_ref().map(|t| Tilt {
                xy: t.xy,
                rate: t.le.rate,
                offset: t.le.offset,
            }),
            step: sys.step,
            dt: sys.dt,
            skin: sys.neighbor.skin,
            masses: sys.mass.clone(),
            pair,
            fixes,
            topo: sys.topo.as_ref().map(|t| TopoRecord {
                style: t.style,
                nbondtypes: t.nbondtypes as u32,
                nangletypes: t.nangletypes as u32,
                bonds: t.bonds.clone(),
                angles: t.angles.clone(),
                mol: if sys.atoms.mol.is_empty() {
                    vec![0; sys.atoms.len()]
                } else {
                    sys.atoms.mol.clone()
                },
                special: t.special,
                lines: t
                    .bond_style
                    .iter()
                    .flat_map(|b| b.lines())
                    .chain(t.angle_style.iter().flat_map(|a| a.lines()))
                    .collect(),
                energies: sys.energies,
            }),
            atoms: std::mem::take(&mut sys.atoms),
            tally: sys.tally,
            units: sys.units.style,
            groups: sys.groups.names().to_vec(),
        };
        let bytes = restart::encode(&r);
        sys.atoms = r.atoms;
        restart::write_atomic(Path::new(path), &bytes)
    }

    /// The periodic restart of `restart N FILE` at the current step, if one is configured:
    /// the file written.
    pub(super) fn write_scheduled_restart(&mut self) -> Result<Option<String>, String> {
        let (Some(sched), Some(sys)) = (self.restart.as_mut(), self.sys.as_ref()) else {
            return Ok(None);
        };
        let path = restart::file_for_step(&sched.files[sched.next], sys.step);
        sched.next = (sched.next + 1) % sched.files.len();
        self.write_restart_file(&path)?;
        Ok(Some(path))
    }

    /// True when `restart N FILE` asks for a file at `step`.
    pub(super) fn restart_due(&self, step: u64) -> bool {
        self.restart
            .as_ref()
            .is_some_and(|s| step.is_multiple_of(s.every))
    }

    /// The fixes as the restart file records them, in definition order.
    fn fix_records(&self) -> Vec<FixRecord> {
        self.fixes
            .iter()
            .map(|(id, kind)| FixRecord {
                words: self.fix_lines.get(id).cloned().unwrap_or_default(),
                state: self
                    .sys
                    .as_ref()
                    .map_or_else(Vec::new, |s| fix_state(s, id, kind)),
            })
            .collect()
    }

    /// After `fix ID … STYLE …` is defined: give it the state of the restart file's fix with the
    /// same ID and style, if there is one.
    pub(super) fn claim_fix_state(&mut self, id: &str, style: &str) -> CmdResult {
        let Some(k) = self
            .restart_fixes
            .iter()
            .position(|(_, f)| f.id() == id && f.style() == style)
        else {
            return Ok(());
        };
        let (file, rec) = self.restart_fixes.remove(k);
        let sys = self.sys_mut()?;
        restore_fix_state(sys, id, style, &rec.state)
            .map_err(|e| format!("restart file {file}: fix {id} {style}: {e}"))?;
        self.out(&format!(
            "fix {id} {style}: state restored from restart file {file}"
        ));
        Ok(())
    }

    /// At a run's set-up: warn about restart-file fix state that no fix claimed, and drop it
    /// (LAMMPS's "Unused restart file global fix info").
    pub(super) fn drop_unclaimed_fix_state(&mut self) {
        for (file, f) in std::mem::take(&mut self.restart_fixes) {
            self.warn(&format!(
                "restart file {file}: the state of fix {} {} is not used (no fix with that ID \
                 and style was defined after read_restart)",
                f.id(),
                f.style()
            ));
        }
    }
}

/// The internal state of fix `id` of kind `kind` (empty for fixes without one). A fix style
/// with state appears here and in [`restore_fix_state`].
fn fix_state(sys: &System, id: &str, kind: &FixKind) -> Vec<f64> {
    match kind {
        FixKind::Pex => sys
            .pex
            .iter()
            .find(|p| p.id == id)
            .map_or_else(Vec::new, |p| vec![p.total]),
        _ => Vec::new(),
    }
}

/// Put `state` (from [`fix_state`] of a restart file) back into the fix `id` of `style`.
fn restore_fix_state(sys: &mut System, id: &str, style: &str, state: &[f64]) -> CmdResult {
    match style {
        "pex/push" => {
            let &[total] = state else {
                return Err(format!("{} state values, expected 1", state.len()));
            };
            let p = sys
                .pex
                .iter_mut()
                .find(|p| p.id == id)
                .ok_or("the fix is not a pex/push")?;
            p.total = total;
            Ok(())
        }
        _ => Err(format!(
            "{} state values for a fix without state",
            state.len()
        )),
    }
}
