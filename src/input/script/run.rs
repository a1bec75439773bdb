//! `run`: the set-up, the time-step loop with its end-of-step fixes, thermo and dump output;
//! and dry runs, which set every run up and record it as a [`PlannedRun`].

use super::fix::FixKind;
use super::{CmdResult, Interpreter};
use crate::engine::lees_edwards::flip_jump_note;
use crate::engine::modify::InputValue;
use crate::engine::{Integrator, SetupNote, System};
use crate::forces::StylePlan;
use crate::grammar::{need, parse_int};
use crate::input::observe::Env;
use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

/// What a `run` command would run, as seen by its set-up (for `dpdnl theory SCRIPT`): the
/// state point and the pair style's plan.
#[derive(Clone, Debug)]
pub struct PlannedRun {
    /// Step at which the run starts.
    pub first_step: u64,
    /// Number of steps.
    pub steps: u64,
    /// Dimension (2 or 3).
    pub dim: u32,
    /// Number of atoms.
    pub natoms: usize,
    /// Volume (area in 2-D).
    pub volume: f64,
    /// Per-type masses (index 0 unused).
    pub masses: Vec<f64>,
    /// The pair style's name.
    pub style: &'static str,
    /// What the pair style would use: kT, its words, each pair's coefficients and kinetic
    /// theory, after (η, Sc) targets were resolved.
    pub plan: Arc<dyn StylePlan>,
    /// Time step.
    pub dt: f64,
    /// The integrator, if any.
    pub integrator: Option<Integrator>,
    /// The set-up's log lines (resolved designs, warnings), then the plan's own notes.
    pub notes: Vec<SetupNote>,
    /// The unit style of the run.
    pub units: crate::units::Units,
}

impl PlannedRun {
    fn of(sys: &mut System, steps: u64, mut notes: Vec<SetupNote>) -> Result<PlannedRun, String> {
        let style = sys.pair.as_deref().ok_or("no pair style")?;
        let plan = style.plan(&sys.units, sys.dt);
        notes.extend(plan.notes());
        Ok(PlannedRun {
            first_step: sys.step,
            steps,
            dim: sys.bx.dim as u32,
            natoms: sys.atoms.len(),
            volume: sys.bx.volume(),
            masses: sys.mass.iter().map(|m| m.unwrap_or(0.0)).collect(),
            style: style.name(),
            plan,
            dt: sys.dt,
            integrator: sys.integrator,
            notes,
            units: sys.units,
        })
    }
}

/// Commands a dry run ([`Interpreter::set_dry_run`]) skips: everything that writes a file or
/// only matters to the output of a real run.
pub(super) fn dry_run_skips(cmd: &str, args: &[String]) -> bool {
    matches!(
        cmd,
        "dump"
            | "write_dump"
            | "dump_modify"
            | "undump"
            | "write_data"
            | "write_restart"
            | "restart"
            | "log"
            | "print"
    ) || (cmd == "fix"
        && args
            .get(2)
            .is_some_and(|s| s.starts_with("ave/") || s == "print"))
}

struct RunArgs {
    n: u64,
    upto: bool,
    start: Option<u64>,
    stop: Option<u64>,
    /// `every M CMD…` (`every M NULL`: no commands): run in chunks of M steps and run the
    /// commands after each.
    every: Option<(u64, Vec<String>)>,
}

const RUN_USAGE: &str =
    "run N [upto] [start S] [stop E] [pre yes|no] [post yes|no] [every M CMD…|NULL]";

/// `run N [upto] [start S] [stop E] [pre yes|no] [post yes|no] [every M CMD…|NULL]`.
fn parse_run_args(args: &[String]) -> Result<RunArgs, String> {
    need(args, 1, RUN_USAGE)?;
    let mut r = RunArgs {
        n: parse_int(&args[0], "number of steps")?,
        upto: false,
        start: None,
        stop: None,
        every: None,
    };
    let mut k = 1;
    while k < args.len() {
        match args[k].as_str() {
            "upto" => {
                r.upto = true;
                k += 1;
            }
            "pre" | "post" => k += 2,
            w @ ("start" | "stop") => {
                let v = args
                    .get(k + 1)
                    .ok_or_else(|| format!("run {w} needs a step; usage: {RUN_USAGE}"))?;
                let v = Some(parse_int(v, &format!("run {w}"))?);
                if w == "start" {
                    r.start = v;
                } else {
                    r.stop = v;
                }
                k += 2;
            }
            "every" => {
                // As LAMMPS: every takes the rest of the line.
                let m = args
                    .get(k + 1)
                    .ok_or_else(|| format!("run every needs M; usage: {RUN_USAGE}"))?;
                let m: u64 = parse_int(m, "run every")?;
                if m == 0 {
                    return Err(format!("run every M = 0 must be > 0; usage: {RUN_USAGE}"));
                }
                let mut cmds = args[k + 2..].to_vec();
                if cmds.len() == 1 && cmds[0] == "NULL" {
                    cmds.clear();
                }
                r.every = Some((m, cmds));
                k = args.len();
            }
            o => {
                return Err(format!(
                    "run keyword '{o}' not supported (upto, start, stop, pre, post, every)"
                ));
            }
        }
    }
    Ok(r)
}

/// `run_style verlet`: the standalone engine's only run style (velocity Verlet, or the Euler
/// update of `fix nve/euler`, both driven as LAMMPS's `Verlet` drives them), so the command is
/// accepted and changes nothing; every other style (`respa`, `verlet/split`, …) is refused.
pub(super) fn cmd_run_style(args: &[String]) -> CmdResult {
    need(args, 1, "run_style verlet")?;
    match args[0].as_str() {
        "verlet" => {
            crate::grammar::at_most(args, 1, "run_style verlet")?;
            Ok(())
        }
        s @ ("respa" | "respa/omp") => Err(format!(
            "run_style {s} is not supported: the standalone engine has one force evaluation \
             per step (run_style verlet); use run_style verlet, or drop the line (verlet is \
             the default)"
        )),
        s => Err(format!(
            "run_style {s} is not supported: the standalone engine runs run_style verlet \
             only; use run_style verlet, or drop the line (verlet is the default)"
        )),
    }
}

/// Steps between blow-up checks ([`crate::engine::System::check_health`]) when no thermo
/// output falls in between.
const HEALTH_EVERY: u64 = 100;

impl Interpreter<'_> {
    /// Dry run (for `dpdnl theory SCRIPT`): every `run` does its set-up (checks, (η, Sc)
    /// resolution, warnings) and is recorded in [`Interpreter::planned_runs`] instead of being
    /// run; commands that write files (`dump`, `write_data`, `log`, `print`, `fix ave/*`) are
    /// skipped.
    pub fn set_dry_run(&mut self, on: bool) {
        self.dry_run = on;
    }

    /// The runs a dry run recorded, in script order.
    pub fn planned_runs(&self) -> &[PlannedRun] {
        &self.planned
    }

    /// LAMMPS `end_of_step` (and, at `setup`, the fixes' set-up call): PeX pushes and
    /// measurements in the order the fixes were defined.
    fn end_of_step(&mut self, setup: bool) -> CmdResult {
        for k in 0..self.fixes.len() {
            let (id, kind) = &self.fixes[k];
            match kind {
                FixKind::Pex if !setup => {
                    let id = id.clone();
                    let sys = self.sys_mut()?;
                    if let Some(p) = sys.pex.iter().position(|p| p.id == id) {
                        sys.apply_pex_push(p);
                    }
                }
                FixKind::Engine if !setup => {
                    let id = id.clone();
                    self.sys_mut()?.fix_end_of_step(&id);
                }
                FixKind::Print => {
                    let id = id.clone();
                    self.fix_print_step(&id, setup)?;
                }
                FixKind::Observe => {
                    if let Some(sample) = self.obs.sample(id, &*self)? {
                        let (id, step) = (id.clone(), self.sys_mut()?.step);
                        self.obs.accumulate(&id, sample, step)?;
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Hand the engine's fixes the variables they read at the coming `post_force` (or set-up),
    /// evaluated now, after the forces of the step (as LAMMPS evaluates them in `post_force`).
    fn feed_fix_inputs(&mut self) -> CmdResult {
        let wanted = self.sys_mut()?.fix_inputs();
        if wanted.is_empty() {
            return Ok(());
        }
        let mut values = Vec::new();
        for (fix, inputs) in wanted {
            for (k, input) in inputs.iter().enumerate() {
                let v = if input.atom {
                    InputValue::Atom(self.atom_variable(&input.name)?)
                } else {
                    InputValue::Equal(self.equal_variable(&input.name)?)
                };
                values.push((fix, k, v));
            }
        }
        let sys = self.sys_mut()?;
        for (fix, k, v) in values {
            sys.set_fix_input(fix, k, v);
        }
        Ok(())
    }

    pub(super) fn cmd_run(&mut self, args: &[String]) -> CmdResult {
        let RunArgs {
            mut n,
            upto,
            start,
            stop,
            every,
        } = parse_run_args(args)?;
        let step = self.sys_mut()?.step;
        if upto {
            n = n
                .checked_sub(step)
                .ok_or("run upto: target step is in the past")?;
        }
        let Some((m, cmds)) = every else {
            return self.run_chunk(n, start, stop);
        };
        if let Some(cap) = self.max_steps.filter(|&cap| n > cap) {
            return Err(format!(
                "run of {n} steps exceeds the cap of {cap} (Options::max_steps)"
            ));
        }
        // LAMMPS's `Run::command` with `every`: chunks of at most M steps (one of 0 steps
        // for `run 0`), each a run of its own with its set-up, then the commands.
        let mut left = n;
        let mut first = true;
        while left > 0 || first {
            let chunk = left.min(m);
            self.run_chunk(chunk, start, stop)?;
            for c in &cmds {
                self.one(c).map_err(|e| format!("every: {e}"))?;
            }
            left -= chunk;
            first = false;
        }
        Ok(())
    }

    /// One run of `n` steps (a whole `run`, or one chunk of `run N every M`).
    fn run_chunk(&mut self, n: u64, start: Option<u64>, stop: Option<u64>) -> CmdResult {
        let threads = self.threads;
        let step = self.sys_mut()?.step;
        if self.console.get().interrupted() {
            return Err(self.interrupted_at(step, None));
        }
        self.drop_unclaimed_fix_state();
        if let Some(cap) = self.max_steps.filter(|&cap| n > cap) {
            return Err(format!(
                "run of {n} steps exceeds the cap of {cap} (Options::max_steps)"
            ));
        }
        let sys = self.sys_mut()?;
        if sys.step.checked_add(n).is_none() {
            // `first + n` below overflowed (a fuzzed `reset_timestep 18446744073709551610`).
            return Err(format!(
                "run {n} from step {} would pass the last step number, 2^64 - 1",
                sys.step
            ));
        }
        sys.defer_fix_setup = true;
        sys.setup_run_window(sys.step + n, start, stop)?;
        self.feed_fix_inputs()?;
        let sys = self.sys_mut()?;
        sys.setup_fixes();
        let notes = std::mem::take(&mut sys.setup_notes);
        let integ = sys.integrator;
        let first = sys.step;
        let last = first + n;
        let natoms = sys.atoms.len();
        let dt = sys.dt;
        self.run_first = first;
        if self.dry_run {
            let plan = PlannedRun::of(self.sys_mut()?, n, notes)?;
            self.planned.push(plan);
            return Ok(());
        }
        self.run_setup(notes, integ, first, dt)?;
        let secs = self.run_steps(n, first, last)?;
        // LAMMPS's place: `fix flip/momentum`'s `post_run`, before the loop time.
        if let Some(w) = self.sys_mut()?.flip_leak_warning() {
            self.warn(&w);
        }
        let jumped = self
            .sys_mut()?
            .tri
            .as_ref()
            .and_then(|t| flip_jump_note(&t.leak));
        if let Some(note) = jumped {
            self.out(&note);
        }
        self.out(&format!(
            "Loop time of {secs:.6} on {threads} procs for {n} steps with {natoms} atoms\n"
        ));
        if secs > 0.0 && n > 0 {
            let steps_per_s = n as f64 / secs;
            self.out(&format!(
                "Performance: {:.3} tau/day, {:.3} timesteps/s, {:.3} katom-step/s",
                86400.0 * steps_per_s * dt,
                steps_per_s,
                steps_per_s * natoms as f64 / 1000.0
            ));
        }
        self.flush_outputs();
        Ok(())
    }

    /// The start of a real run, after the system's set-up: its notes and warnings, the
    /// "Setting up" block, the health check, the fixes' set-up, and the output of step `first`
    /// (thermo header and row, dumps).
    fn run_setup(
        &mut self,
        notes: Vec<SetupNote>,
        integ: Option<Integrator>,
        first: u64,
        dt: f64,
    ) -> CmdResult {
        for note in notes {
            match note {
                SetupNote::Info(text) => self.out(&text),
                SetupNote::Warning(text) => self.warn(&text),
            }
        }
        if integ.is_none() {
            self.warn("No fixes with time integration, atoms won't move");
        }
        let scheme = match integ {
            Some(Integrator::Euler) => "Euler (nve/euler)",
            _ => "velocity-Verlet (nve)",
        };
        self.out(&format!("Setting up {scheme} run ...\n  Unit style    : lj\n  Current step  : {first}\n  Time step     : {dt}"));
        for w in std::mem::take(&mut self.sys_mut()?.warnings) {
            self.warn(&w);
        }
        self.sys_mut()?.check_health()?;
        self.obs.init(first);
        self.end_of_step(true)?;
        let header = self.thermo_header_line();
        self.out(&header);
        let row = self.thermo_row()?;
        self.out(&row);
        self.write_dumps(true)
    }

    /// The time-step loop of a run of `n` steps from `first` to `last`, with its end-of-step
    /// fixes, thermo, dump and restart output, progress and interrupt checks; returns the
    /// seconds the loop took.
    fn run_steps(&mut self, n: u64, first: u64, last: u64) -> Result<f64, String> {
        let every = self.thermo.every;
        let start = Instant::now();
        let mut last_progress = Instant::now();
        let measuring = self.obs.has_fixes()
            || !self.prints.is_empty()
            || self.fixes.iter().any(|(_, k)| *k == FixKind::Engine);
        for _ in 0..n {
            // LAMMPS re-neighbours on the steps it writes a restart file.
            let next = self.sys_mut()?.step + 1;
            let rebuild = self.restart_due(next);
            let sys = self.sys_mut()?;
            if rebuild {
                sys.rebuild_at_next_step();
            }
            sys.advance_to_forces();
            self.feed_fix_inputs()?;
            let sys = self.sys_mut()?;
            sys.advance_finish();
            if !measuring {
                for k in 0..sys.pex.len() {
                    sys.apply_pex_push(k);
                }
            }
            let step = sys.step;
            let thermo_due = (every > 0 && step % every == 0) || step == last;
            if !sys.warnings.is_empty() {
                for w in std::mem::take(&mut sys.warnings) {
                    self.warn(&w);
                }
            }
            let sys = self.sys_mut()?;
            if (thermo_due || step % HEALTH_EVERY == 0 || sys.fault().is_some())
                && let Err(e) = sys.check_health()
            {
                self.flush_outputs();
                return Err(e);
            }
            if measuring {
                self.end_of_step(false)?;
            }
            if thermo_due {
                let row = self.thermo_row()?;
                self.out(&row);
            }
            if !self.dumps.is_empty() {
                self.write_dumps(false)?;
            }
            let mut restart_file = None;
            if self.restart_due(step) {
                restart_file = self.write_scheduled_restart().inspect_err(|_| {
                    self.flush_outputs();
                })?;
            }
            if last_progress.elapsed().as_secs_f64() > 1.0 {
                last_progress = Instant::now();
                self.console.get().progress(step, first, last);
                self.flush_outputs();
            }
            if self.console.get().interrupted() {
                return Err(self.interrupted_at(step, restart_file));
            }
        }
        Ok(start.elapsed().as_secs_f64())
    }

    /// Stop a run that [`super::Console::interrupted`] interrupted at `step`: flush the log as
    /// at the end of a run and, with `restart N FILE` set, write the restart file of this step
    /// (unless `written`, the one this step already wrote); the message of the error the script
    /// stops with.
    fn interrupted_at(&mut self, step: u64, written: Option<String>) -> String {
        self.flush_outputs();
        let mut message = format!("interrupted at step {step}");
        let file = match written {
            Some(f) => Ok(Some(f)),
            None => self.write_scheduled_restart(),
        };
        match file {
            Ok(Some(f)) => message.push_str(&format!("; restart file {f} written")),
            Ok(None) => {}
            Err(e) => message.push_str(&format!("; {e}")),
        }
        message
    }

    /// Flush the log (dumps and averaging files are flushed as each record is written).
    pub(super) fn flush_outputs(&mut self) {
        if let Some(l) = self.log.as_mut() {
            let _ = l.flush();
        }
    }
}
