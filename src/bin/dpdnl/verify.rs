//! `dpdnl verify SCRIPT FRAMES…`: recompute, in the standalone engine, the force of this
//! project's pair style in every frame that `fix dpdnl/frames` wrote during a LAMMPS run, and
//! compare it per atom (docs/manual/verify.md).
//!
//! The style's settings come from the script: its `variable`, `units` and `dimension` lines,
//! the `pair_style` line of the frame's style (alone or as a sub-style of `hybrid`/
//! `hybrid/overlay`, whose other sub-styles are left to LAMMPS) and that style's `pair_coeff`
//! lines; when the script sets no coefficients of it (a data file's `Pair Coeffs`), those the
//! frame recorded. The box, atoms, masses, time step and step come from the frame. Exit status
//! as `crosscheck`: 0 agree, 1 differ, 2 cannot run.

use dpdnl::engine::{Integrator, System};
use dpdnl::input::lexer::{logical_lines, split_words, strip_comment};
use dpdnl::input::{Collect, Interpreter, Options};
use dpdnl::io::frames::{Frame, FrameReader, flags};
use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Check a LAMMPS run frame by frame: recompute the dpdnl pair style's force of every frame of
/// `fix dpdnl/frames` in the standalone engine and compare it per atom.
///
/// Exit status: 0 when every atom of every frame agrees, 1 when one differs, 2 when the check
/// cannot run.
#[derive(clap::Args)]
pub struct VerifyArgs {
    /// The LAMMPS input script of the run (for the style's settings).
    pub script: PathBuf,
    /// Frame files written by `fix ID all dpdnl/frames N FILE`.
    #[arg(required = true)]
    pub frames: Vec<PathBuf>,
    /// Relative tolerance per force component: |A−B| / max(|A|, |B|, rms), rms the frame's
    /// root-mean-square force component (a net force can be a near-cancellation of pair forces,
    /// which two summation orders leave apart by round-off of the pair forces' size).
    #[arg(long, default_value_t = 1e-8)]
    pub rtol: f64,
    /// Absolute tolerance: a component differs only if both tolerances are exceeded.
    #[arg(long, default_value_t = 0.0)]
    pub atol: f64,
    /// Define an index-style variable NAME with VALUE, as LAMMPS's `-var`; repeatable.
    #[arg(long = "var", short = 'v', num_args = 2, value_names = ["NAME", "VALUE"], action = clap::ArgAction::Append, allow_hyphen_values = true)]
    pub var: Vec<String>,
    /// Worker threads (the forces' bits do not depend on it). 0: one per CPU available.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64))]
    pub threads: u64,
}

/// "Cannot run" (exit 2).
#[derive(Debug)]
struct CannotRun(String);

impl From<String> for CannotRun {
    fn from(e: String) -> Self {
        CannotRun(e)
    }
}

pub fn main(a: VerifyArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    match run(&a) {
        Ok(true) => Ok(ExitCode::SUCCESS),
        Ok(false) => Ok(ExitCode::from(1)),
        Err(CannotRun(e)) => {
            eprintln!("ERROR: dpdnl verify: {e}");
            Ok(ExitCode::from(2))
        }
    }
}

/// The lines of the script that set the style: (line text, is a `pair_coeff` of the style).
struct Settings {
    lines: Vec<(String, bool)>,
    name: String,
    file: String,
    /// The style is a sub-style of `hybrid`/`hybrid/overlay` (its last `pair_style` line):
    /// type pairs without its coefficients belong to other styles.
    hybrid: bool,
}

/// The scan of a script (and the files it includes) for the lines that matter to one style.
struct Scan<'a> {
    style: &'a str,
    lines: Vec<(String, bool)>,
    /// The current `pair_style` is (or holds) the style.
    ours: bool,
    hybrid: bool,
    seen: bool,
    /// `include` lines not followed (a variable in the file name), for a note.
    skipped: Vec<String>,
}

impl Scan<'_> {
    /// Scan `text`; `dir` resolves relative `include` names (LAMMPS's current directory, the
    /// script's own when run from there).
    fn text(&mut self, text: &str, dir: &std::path::Path, depth: usize) -> Result<(), CannotRun> {
        let style = self.style;
        for raw in logical_lines(text) {
            let body = strip_comment(&raw.text);
            let Ok(w) = split_words(body) else { continue };
            let Some(cmd) = w.first() else { continue };
            match cmd.as_str() {
                "variable" | "units" | "dimension" => self.lines.push((body.to_string(), false)),
                "include" if w.len() == 2 && !w[1].contains('$') && depth < 16 => {
                    let path = dir.join(&w[1]);
                    let t = std::fs::read_to_string(&path).map_err(|e| {
                        CannotRun(format!(
                            "include {}: cannot read {}: {e}",
                            w[1],
                            path.display()
                        ))
                    })?;
                    self.text(&t, path.parent().unwrap_or(dir), depth + 1)?;
                }
                "include" => self.skipped.push(body.to_string()),
                "pair_style" => {
                    self.hybrid = w.get(1).is_some_and(|s| s.starts_with("hybrid"));
                    self.ours = w.get(1).is_some_and(|s| s == style)
                        || (self.hybrid && w.iter().skip(2).any(|s| s == style));
                    if self.ours {
                        self.seen = true;
                        self.lines.push((body.to_string(), false));
                    }
                }
                "pair_coeff" if self.ours && !self.hybrid => {
                    self.lines.push((body.to_string(), true))
                }
                "pair_coeff" if self.ours && w.get(3).is_some_and(|s| s == style) => {
                    let mut kept: Vec<String> = w.clone();
                    kept.remove(3);
                    self.lines.push((kept.join(" "), true));
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The script's lines that matter to `style` (see the module's documentation), following its
/// `include` files.
fn read_settings(script: &str, path: &std::path::Path, style: &str) -> Result<Settings, CannotRun> {
    let file = path.display().to_string();
    let mut scan = Scan {
        style,
        lines: Vec::new(),
        ours: false,
        hybrid: false,
        seen: false,
        skipped: Vec::new(),
    };
    let dir = path.parent().unwrap_or(std::path::Path::new("."));
    scan.text(script, dir, 0)?;
    for line in &scan.skipped {
        eprintln!("note: dpdnl verify: '{line}' not followed (a variable in the file name)");
    }
    if !scan.seen {
        return Err(CannotRun(format!(
            "{file} has no pair_style {style} (the frames' style), alone or under hybrid"
        )));
    }
    Ok(Settings {
        lines: scan.lines,
        name: style.to_string(),
        file,
        hybrid: scan.hybrid,
    })
}

/// Masses per type from the frame's per-atom masses (a type whose atoms differ cannot be run:
/// the standalone engine has per-type masses).
fn type_masses(fr: &Frame, ntypes: usize) -> Result<Vec<f64>, CannotRun> {
    let mut m: Vec<Option<f64>> = vec![None; ntypes + 1];
    for (&t, &mass) in fr.typ.iter().zip(&fr.mass) {
        let slot = m
            .get_mut(t as usize)
            .ok_or_else(|| CannotRun(format!("atom type {t} above the frame's {ntypes} types")))?;
        match *slot {
            Some(old) if old != mass => {
                return Err(CannotRun(format!(
                    "atoms of type {t} have different masses ({old} and {mass}): the standalone \
                     engine has one mass per type"
                )));
            }
            _ => *slot = Some(mass),
        }
    }
    Ok(m.iter().skip(1).map(|x| x.unwrap_or(1.0)).collect())
}

/// The script text the standalone engine runs for frame `fr`: the settings with the frame's
/// box, masses and time step (the coefficients of the frame when the script sets none).
fn frame_script(s: &Settings, fr: &Frame) -> Result<String, CannotRun> {
    let h = &fr.head;
    let ntypes = (h.ntypes as usize).max(fr.typ.iter().copied().max().unwrap_or(1) as usize);
    let masses = type_masses(fr, ntypes)?;
    // A non-periodic axis becomes a periodic one with room beyond the atoms, so that no pair
    // meets across it.
    let mut lo = h.boxlo;
    let mut hi = h.boxhi;
    let pad = (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max);
    for d in 0..h.dimension as usize {
        if !h.periodic(d) {
            let (mn, mx) =
                fr.x.iter()
                    .fold((lo[d], hi[d]), |(a, b), x| (a.min(x[d]), b.max(x[d])));
            lo[d] = mn - pad;
            hi[d] = mx + pad;
        }
    }
    let mut box_lines = format!(
        "dimension {}\nregion verify_box block {} {} {} {} {} {}\ncreate_box {ntypes} verify_box\n",
        h.dimension, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
    );
    for (t, m) in masses.iter().enumerate() {
        box_lines.push_str(&format!("mass {} {m}\n", t + 1));
    }
    box_lines.push_str(&format!("timestep {}\n", h.dt));
    let has_coeff = s.lines.iter().any(|(_, c)| *c);
    let mut text = String::new();
    let mut placed = false;
    for (line, coeff) in &s.lines {
        if *coeff && !placed {
            text.push_str(&box_lines);
            placed = true;
        }
        text.push_str(line);
        text.push('\n');
    }
    if !placed {
        text.push_str(&box_lines);
    }
    if !has_coeff {
        // The frame's own record of the style's coefficients (read_data's Pair Coeffs).
        for l in h.settings.lines().filter(|l| l.starts_with("pair_coeff")) {
            text.push_str(l);
            text.push('\n');
        }
    }
    Ok(text)
}

/// The standalone engine's force of the style on every atom of `fr`, by atom id.
fn recompute(s: &Settings, fr: &Frame, vars: &[(String, String)]) -> Result<System, CannotRun> {
    let h = &fr.head;
    if h.flags & flags::TRICLINIC != 0 && h.tilt.iter().any(|&t| t != 0.0) {
        return Err(CannotRun(
            "a tilted (triclinic) box: not supported by verify yet".into(),
        ));
    }
    if h.flags & flags::MOLECULAR != 0 && h.special_lj.iter().any(|&f| f != 1.0) {
        return Err(CannotRun(format!(
            "special_bonds lj {:?} on a molecular system: the frames do not carry the topology \
             yet",
            h.special_lj
        )));
    }
    let text = frame_script(s, fr)?;
    let mut console = Collect::default();
    let opts = Options {
        vars: vars.to_vec(),
        substyle: Some(s.name.clone()),
        ..Default::default()
    };
    let mut it = Interpreter::new(&mut console, &opts)?;
    it.run_text(&text, &s.file)
        .map_err(|e| CannotRun(format!("the script's settings of {}: {e}", s.name)))?;
    let mut sys = it.into_system().ok_or_else(|| CannotRun("no box".into()))?;
    // The style may cover some type pairs only (`pair_coeff I J none` or another style's).
    sys.pair_substyle = s.hybrid;
    for k in 0..fr.tag.len() {
        sys.atoms
            .push(fr.tag[k], fr.typ[k], fr.x[k], fr.v[k], [0, 0, 0]);
    }
    sys.step = h.step;
    sys.integrator = Some(if h.flags & flags::EULER != 0 {
        Integrator::Euler
    } else {
        Integrator::VelocityVerlet
    });
    let end = h.endstep.max(h.step);
    sys.setup_run_window(end, Some(h.beginstep.min(h.step)), Some(end))
        .map_err(|e| CannotRun(format!("frame at step {}: {e}", h.step)))?;
    Ok(sys)
}

/// The comparison of one frame.
#[derive(Default)]
struct Compared {
    max_abs: f64,
    max_rel: f64,
    /// (atom id, |ΔF| component, relative) of the worst atom.
    worst: Option<(u32, f64, f64)>,
    differing: usize,
    missing: Vec<u32>,
}

fn compare(fr: &Frame, sys: &System, rtol: f64, atol: f64) -> Compared {
    let n = fr.f.len().max(1) as f64;
    let rms = (fr.f.iter().flatten().map(|c| c * c).sum::<f64>() / (3.0 * n)).sqrt();
    let mut at: HashMap<u32, usize> = HashMap::with_capacity(sys.atoms.len());
    for (k, &t) in sys.atoms.tag.iter().enumerate() {
        at.insert(t, k);
    }
    let mut c = Compared::default();
    for (k, &tag) in fr.tag.iter().enumerate() {
        let Some(&j) = at.get(&tag) else {
            c.missing.push(tag);
            continue;
        };
        let (a, b) = (fr.f[k], sys.atoms.f[j]);
        let mut bad = false;
        let mut atom_rel = 0.0f64;
        let mut atom_abs = 0.0f64;
        for d in 0..3 {
            let diff = (a[d] - b[d]).abs();
            let scale = a[d].abs().max(b[d].abs()).max(rms);
            let rel = if scale > 0.0 { diff / scale } else { 0.0 };
            bad |= !(diff <= atol || rel <= rtol);
            atom_rel = atom_rel.max(rel);
            atom_abs = atom_abs.max(diff);
        }
        c.max_abs = c.max_abs.max(atom_abs);
        if atom_rel > c.max_rel || c.worst.is_none() {
            c.max_rel = c.max_rel.max(atom_rel);
            c.worst = Some((tag, atom_abs, atom_rel));
        }
        c.differing += usize::from(bad);
    }
    c
}

fn run(a: &VerifyArgs) -> Result<bool, CannotRun> {
    if !(a.rtol >= 0.0 && a.atol >= 0.0) {
        return Err(CannotRun("--rtol and --atol must be numbers >= 0".into()));
    }
    let threads = crate::thread_count(a.threads);
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global();
    let file = a.script.display().to_string();
    let script = std::fs::read_to_string(&a.script)
        .map_err(|e| CannotRun(format!("cannot read {file}: {e}")))?;
    let vars = crate::var_pairs(&a.var);
    let mut settings: Option<Settings> = None;
    let (mut frames, mut atoms, mut bad_frames) = (0usize, 0usize, 0usize);
    let (mut max_abs, mut max_rel) = (0.0f64, 0.0f64);
    for path in &a.frames {
        let mut reader = FrameReader::open(path)?;
        loop {
            let t0 = Instant::now();
            let Some(fr) = reader.next_frame()? else {
                break;
            };
            let t_read = t0.elapsed().as_secs_f64();
            let style = fr.head.style.clone();
            let s = match &settings {
                Some(s) if s.name == style => s,
                Some(s) => {
                    return Err(CannotRun(format!(
                        "{}: a frame of pair_style {style} after frames of {}",
                        path.display(),
                        s.name
                    )));
                }
                None => settings.insert(read_settings(&script, &a.script, &style)?),
            };
            let t1 = Instant::now();
            let sys = recompute(s, &fr, &vars)?;
            let t_force = t1.elapsed().as_secs_f64();
            let c = compare(&fr, &sys, a.rtol, a.atol);
            frames += 1;
            atoms += fr.tag.len();
            max_abs = max_abs.max(c.max_abs);
            max_rel = max_rel.max(c.max_rel);
            report_frame(path, frames, &fr, &c, &sys, t_read, t_force);
            if c.differing > 0 || !c.missing.is_empty() {
                bad_frames += 1;
            }
        }
    }
    if frames == 0 {
        return Err(CannotRun("the frame files hold no frame".into()));
    }
    let style = settings.map(|s| s.name).unwrap_or_default();
    let tol = match a.atol > 0.0 {
        true => format!("rtol {:e} or atol {:e}", a.rtol, a.atol),
        false => format!("rtol {:e}", a.rtol),
    };
    if bad_frames == 0 {
        println!(
            "VERIFY AGREE: pair_style {style}, {frames} frame(s), {atoms} atom forces within \
             {tol} (max |dF| {max_abs:.3e}, max rel {max_rel:.3e})"
        );
        Ok(true)
    } else {
        println!(
            "VERIFY DIFFER: pair_style {style}, {bad_frames} of {frames} frame(s) not within \
             {tol} (max |dF| {max_abs:.3e}, max rel {max_rel:.3e}; see the frames above)"
        );
        Ok(false)
    }
}

fn report_frame(
    path: &std::path::Path,
    k: usize,
    fr: &Frame,
    c: &Compared,
    sys: &System,
    t_read: f64,
    t_force: f64,
) {
    let step = fr.head.step;
    let n = fr.tag.len();
    let verdict = if c.differing == 0 && c.missing.is_empty() {
        "agree"
    } else {
        "DIFFER"
    };
    println!(
        "frame {k} ({}, step {step}, {n} atoms): max |dF| {:.3e}, max rel {:.3e}: {verdict} \
         (read {t_read:.3} s, recompute and compare {t_force:.3} s)",
        path.display(),
        c.max_abs,
        c.max_rel
    );
    if !c.missing.is_empty() {
        println!(
            "  {} atom(s) of the frame missing from the recomputation, first id {}",
            c.missing.len(),
            c.missing[0]
        );
    }
    if c.differing > 0 {
        if let Some((tag, abs, rel)) = c.worst {
            let k = fr.tag.iter().position(|&t| t == tag).unwrap_or(0);
            let j = sys.atoms.tag.iter().position(|&t| t == tag).unwrap_or(0);
            println!(
                "  {} atom(s) differ; worst atom {tag} (type {}): LAMMPS {:?}, standalone {:?}, \
                 |dF| {abs:.3e}, rel {rel:.3e}",
                c.differing, fr.typ[k], fr.f[k], sys.atoms.f[j]
            );
        }
        if let Some(style) = sys.pair.as_deref() {
            let mine: Vec<String> = style.restart_lines().iter().map(|l| l.join(" ")).collect();
            let mine = mine.join("\n");
            if mine != fr.head.settings {
                println!(
                    "  note: the style's settings in LAMMPS at this frame differ from the \
                     script's:\n    LAMMPS:     {}\n    standalone: {}",
                    fr.head.settings.replace('\n', "\n                "),
                    mine.replace('\n', "\n                ")
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lines kept: the style's own under hybrid/overlay (its name dropped from
    /// `pair_coeff`), none of another pair_style's, and those of an included file.
    #[test]
    fn settings_follow_hybrid_and_include() {
        let dir = std::env::temp_dir().join(format!("dpdnl-verify-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("coeffs.in"),
            "pair_coeff 2 2 dpd/nonlinear 4 3 0\n",
        )
        .unwrap();
        let script = "units lj\nvariable T equal 1.0\npair_style soft 1.0\npair_coeff * * 1.0\n\
                      pair_style hybrid/overlay lj/cut 1.0 dpd/nonlinear ${T} 1.0 5\n\
                      pair_coeff * * lj/cut 0.1 0.5\npair_coeff 1 1 dpd/nonlinear 5 4.5 0\n\
                      include coeffs.in\nfix 1 all nve\n";
        let path = dir.join("in.test");
        let s = read_settings(script, &path, "dpd/nonlinear").unwrap();
        let lines: Vec<(&str, bool)> = s.lines.iter().map(|(l, c)| (l.as_str(), *c)).collect();
        assert_eq!(
            lines,
            [
                ("units lj", false),
                ("variable T equal 1.0", false),
                (
                    "pair_style hybrid/overlay lj/cut 1.0 dpd/nonlinear ${T} 1.0 5",
                    false
                ),
                ("pair_coeff 1 1 5 4.5 0", true),
                ("pair_coeff 2 2 4 3 0", true),
            ]
        );
        let e = read_settings(script, &path, "sdpd").err().unwrap();
        assert!(e.0.contains("no pair_style sdpd"), "{}", e.0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
