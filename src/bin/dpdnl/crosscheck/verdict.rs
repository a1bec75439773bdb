//! What a crosscheck says beyond its tables: LAMMPS's neighbour-list settings, the notes on box
//! flips and shear, and the verdict on a difference (its growth, and its likely reason).

use crate::report::c;
use dpdnl::fmtnum::fmt_g;
use dpdnl::io::growth::{Growth, MAX_RATE, Point, table_rows};
use dpdnl::io::lammps_log::{NeighborSummary, flip_records};
use std::fmt::Write as _;

/// `lammps neighbor lists: neigh_modify every 1 delay 10 check yes; Dangerous builds = 2`, from
/// the LAMMPS log (None when it has neither line).
pub(super) fn neighbor_line(n: &NeighborSummary) -> Option<String> {
    if n.settings.is_empty() && n.dangerous.is_empty() {
        return None;
    }
    let settings = n
        .settings
        .last()
        .map_or("settings not logged".to_string(), |s| {
            format!("neigh_modify {}", s.keywords())
        });
    let builds = if n.dangerous.is_empty() {
        String::new()
    } else if n.unchecked_runs() == n.dangerous.len() {
        "; Dangerous builds not checked".to_string()
    } else {
        format!("; Dangerous builds = {}", dangerous_counts(n))
    };
    Some(format!("lammps neighbor lists: {settings}{builds}"))
}

/// `2`, or per run `0, 2, not checked`.
fn dangerous_counts(n: &NeighborSummary) -> String {
    if n.dangerous.len() == 1 {
        return n.dangerous_total().to_string();
    }
    let runs: Vec<String> = n
        .dangerous
        .iter()
        .map(|d| d.map_or("not checked".to_string(), |k| k.to_string()))
        .collect();
    format!("{} (per run: {})", n.dangerous_total(), runs.join(", "))
}

/// The momentum leak at box flips (issue 41), as the end-of-run warnings of the two logs report
/// it: plain `fix deform … remap v` puts atoms through y at flips without the velocity jump, so
/// the mean velocity relative to the shear profile, V, is not 0; both engines do the same and
/// agree, but neither is right. One note per engine that reports it, with the cure.
pub(super) fn flip_leak_notes(text_s: &str, text_l: &str) -> Vec<String> {
    let leak = |text: &str| -> Option<(u64, String)> {
        let no_jump: Vec<_> = flip_records(text).into_iter().filter(|r| !r.jump).collect();
        let atoms = no_jump.iter().map(|r| r.atoms).sum::<u64>();
        let v = no_jump.last().map(|r| fmt_g(r.v)).unwrap_or_default();
        (atoms > 0).then_some((atoms, v))
    };
    [("standalone engine", text_s), ("LAMMPS", text_l)]
        .iter()
        .filter_map(|(who, text)| {
            let (atoms, v) = leak(text)?;
            Some(format!(
                "{who}: box flips put {atoms} atom(s) through y without remap v's velocity jump \
                 (V = {v} in its last run): the momentum relative to the shear profile leaked, \
                 as LAMMPS's fix deform leaks it; add `fix ID all flip/momentum` \
                 (docs/manual/styles/fix_flip_momentum.md)"
            ))
        })
        .collect()
}

/// The differences by design of a sheared run (a `fix … deform` in LAMMPS's echo of the
/// script), each with the agreement to expect: LAMMPS wraps atoms back into a tilted box, and
/// `remap v` changes their v_x by the box's velocity jump, only when it re-neighbours (and, with
/// no jump, in `write_restart`, whose `init` sets the jump to 0 outside a run); the standalone
/// engine re-neighbours by LAMMPS's rule for `neigh_modify delay 0 every 1 check yes` (and on
/// the steps `restart N` writes, as LAMMPS), so another `neigh_modify` schedule or a
/// `write_restart` between runs wraps atoms on other steps in LAMMPS.
pub(super) fn shear_notes(text_l: &str, n: &NeighborSummary) -> Vec<String> {
    let words = |l: &str| l.split_whitespace().map(str::to_string).collect::<Vec<_>>();
    let lines: Vec<Vec<String>> = text_l.lines().map(words).collect();
    let sheared = lines
        .iter()
        .any(|w| w.len() > 3 && w[0] == "fix" && w[3] == "deform");
    if !sheared {
        return Vec::new();
    }
    let mut why = Vec::new();
    if let Some(st) = n
        .settings
        .last()
        .filter(|s| !(s.every == 1 && s.delay == 0 && s.check))
    {
        why.push(format!(
            "LAMMPS re-neighbours by `neigh_modify {}`, the standalone engine by LAMMPS's \
             rule for `neigh_modify delay 0 every 1 check yes` only",
            st.keywords()
        ));
    }
    if lines
        .iter()
        .any(|w| w.first().is_some_and(|c| c == "write_restart"))
    {
        why.push(
            "LAMMPS's `write_restart` wraps the atoms outside the box without the velocity \
             jump (its `fix deform` has h_rate 0 outside a run), the standalone engine's \
             leaves them"
                .to_string(),
        );
    }
    why.into_iter()
        .map(|w| {
            format!(
                "sheared box (fix deform): {w}, and LAMMPS wraps atoms into the tilted box \
                 (with the `remap v` velocity jump) only when it re-neighbours, so an atom can \
                 wait outside the box in one engine and not in the other: expect `temp`, `ke`, \
                 `etotal`, the thermo pressure and dumped x, vx to differ (by about \
                 m (R L_y)^2 / (d N) in temp per such atom); pe, forces, `temp/deform` and its \
                 pressure, and xu agree to round-off only until the first box flip (LAMMPS puts \
                 the atoms outside the box at a flip back without their velocity jump, and \
                 which atoms those are depends on its schedule), after it they differ too; for \
                 the same numbers use `neigh_modify delay 0 every 1 check yes` and no \
                 `write_restart` between runs"
            )
        })
        .collect()
}

/// The DIFFER verdict line, with the reason LAMMPS's own log gives when it gives one: dangerous
/// builds (its neighbour lists missed pairs, unless they were checked every step), or lists it
/// rebuilt every N > 1 steps unchecked.
pub(super) fn differ_verdict(
    what: &str,
    rtol: f64,
    n: &NeighborSummary,
    growth: &Growth,
    random_setup: Option<&(usize, String)>,
) -> String {
    let reason = match (growth, random_setup) {
        (Growth::AtStart { start, .. }, Some((line, cmd))) => format!(
            " (the engines start from different states: already {} at step {} ({}), because \
             line {line}, `{cmd}`, draws LAMMPS's random numbers in LAMMPS and keyed ones in \
             the standalone engine; this is not a model difference: run `dpdnl crosscheck \
             --from lammps`, which starts both engines from LAMMPS's state after the set-up)",
            c("%.1e", start.diff),
            start.step,
            start.what,
        ),
        _ => growth_reason(growth),
    };
    let mut v = format!(
        "CROSSCHECK DIFFER{reason}: {what} not within rtol {} (see the table(s) above)",
        c("%g", rtol)
    );
    if let Growth::Chaotic {
        reaches_rtol: Some(t),
        start,
        ..
    } = growth
    {
        let _ = write!(
            v,
            "; the fitted growth reaches rtol {} about {} steps after step {}: compare \
             shorter runs, or loosen --rtol",
            c("%g", rtol),
            (t - start.elapsed as f64).max(0.0).round(),
            start.step
        );
    }
    let settings = n.settings.last().map_or(String::new(), |s| {
        format!(" (neigh_modify {})", s.keywords())
    });
    let fix = "add `neigh_modify delay 0 every 1 check yes` to the script and run again to see \
               what difference remains (the standalone engine checks its lists every step)";
    let every_step = n.settings.last().is_some_and(|s| s.checks_every_step());
    if n.dangerous_total() > 0 && every_step {
        // LAMMPS counts a build as dangerous when it comes at the first step it could
        // (ago == max(every, delay)): with every 1 delay 0 that is any build one step after the
        // previous, e.g. every build under fast shear. The lists were checked before every
        // force evaluation, so no pair was missed: the count explains nothing here.
        let _ = write!(
            v,
            "; LAMMPS logged Dangerous builds = {}{settings}: with lists checked every step \
             that only counts rebuilds on consecutive steps (fast shear or fast atoms), not \
             missed pairs, so the difference has another cause",
            dangerous_counts(n)
        );
    } else if n.dangerous_total() > 0 {
        let _ = write!(
            v,
            "; LAMMPS logged Dangerous builds = {}{settings}: some atom had moved more than half \
             the skin before LAMMPS rebuilt its neighbor lists, so it missed pairs, enough by \
             itself to make the engines differ; {fix}",
            dangerous_counts(n)
        );
    } else if n.unchecked_runs() > 0 && n.settings.last().is_none_or(|s| s.every > 1) {
        let _ = write!(
            v,
            "; LAMMPS did not check its neighbor lists (Dangerous builds not checked{settings}), \
             so missed pairs cannot be ruled out; {fix}"
        );
    }
    v
}

/// The first set-up command of `script` whose random numbers are the engine's own (LAMMPS's
/// generators in LAMMPS, keyed ones in the standalone engine), so that the two engines start
/// from different states: `velocity … create` and `create_atoms … random`. Its line (1-based)
/// and text.
pub(super) fn engine_random_setup(script: &str) -> Option<(usize, String)> {
    script.lines().enumerate().find_map(|(k, line)| {
        let code = line.split('#').next().unwrap_or("");
        let w: Vec<&str> = code.split_whitespace().collect();
        let random = matches!(
            w.as_slice(),
            ["velocity", _, "create", ..] | ["create_atoms", _, "random", ..]
        );
        random.then(|| (k + 1, w.join(" ")))
    })
}

/// `3.1e-13`, or `0 (identical to the printed digits)`.
fn small(x: f64) -> String {
    if x == 0.0 {
        "0 (identical to the printed digits)".to_string()
    } else {
        c("%.1e", x)
    }
}

/// ` (chaotic growth of round-off: …)`, the parenthesis of the DIFFER verdict that says which
/// case the user is in ([`Growth`]).
fn growth_reason(g: &Growth) -> String {
    match g {
        Growth::Agree => String::new(),
        Growth::AtStart { start, floor } => format!(
            " (model difference: already {} at step {} ({}), where round-off leaves at most {})",
            c("%.1e", start.diff),
            start.step,
            start.what,
            c("%.0e", *floor)
        ),
        Growth::Chaotic { start, rate, .. } => format!(
            " (chaotic growth of round-off: step-{} agreement {}, growth rate {} per step, x10 \
             every {} steps; this is not a model difference)",
            start.step,
            small(start.diff),
            c("%.3g", *rate),
            c("%.0f", std::f64::consts::LN_10 / rate)
        ),
        Growth::NotRoundoff {
            start,
            at,
            needed_rate,
            line_start,
            ..
        } => {
            let why = if *needed_rate > MAX_RATE {
                format!(
                    "growing from round-off that needs a rate of at least {} per step, x10 every \
                     {} steps, too fast for chaos at a time step that resolves the dynamics",
                    c("%.3g", *needed_rate),
                    c("%.2g", std::f64::consts::LN_10 / needed_rate)
                )
            } else {
                format!(
                    "not a constant exponential growth from round-off{}",
                    line_start.map_or(String::new(), |l| format!(
                        " (the growth taken back to step {} gives {})",
                        start.step,
                        c("%.1e", l)
                    ))
                )
            };
            format!(
                " (model difference after step {s}: step-{s} agreement {}, then {} at step {} \
                 ({}); {why})",
                small(start.diff),
                c("%.1e", at.diff),
                at.step,
                at.what,
                s = start.step,
            )
        }
        Growth::Unresolved {
            start,
            at,
            needed_rate,
            ..
        } => format!(
            " (round-off growth or model difference, cannot tell: step-{} agreement {}, then {} \
             at step {} ({}), too few output steps in between to measure the growth; from \
             round-off that needs a rate of at least {} per step, x10 every {} steps; print \
             thermo more often)",
            start.step,
            small(start.diff),
            c("%.1e", at.diff),
            at.step,
            at.what,
            c("%.3g", *needed_rate),
            c("%.2g", std::f64::consts::LN_10 / needed_rate)
        ),
        Growth::RoundoffOnly { largest, floor } => format!(
            " (round-off only: every difference is at most {} (round-off, or the printed \
             digits), the largest {} at step {}; --rtol is tighter than that)",
            c("%.0e", *floor),
            c("%.1e", largest.diff),
            largest.step
        ),
    }
}

/// The short table of the largest difference per output step, from the first.
pub(super) fn growth_table(points: &[Point], rtol: f64) -> String {
    let mut out = String::from(
        "\ngrowth of the largest difference from the first step (|A - B| / the largest |value| \
         of its column: thermo over the run, dump in the frame):\n",
    );
    let _ = writeln!(out, "{:>10}  {:>10}  where", "step", "difference");
    for i in table_rows(points, rtol, 12) {
        let p = &points[i];
        let _ = writeln!(
            out,
            "{:>10}  {:>10}  {}",
            p.step,
            c("%.2e", p.diff),
            if p.diff > 0.0 { p.what.as_str() } else { "" }
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use dpdnl::io::lammps_log::NeighborSettings;

    fn summary(every: u64, delay: u64, dangerous: u64) -> NeighborSummary {
        NeighborSummary {
            settings: vec![NeighborSettings {
                every,
                delay,
                check: true,
            }],
            dangerous: vec![Some(dangerous)],
        }
    }

    /// Late builds (delay 10) may miss pairs and the verdict says so; with lists checked every
    /// step LAMMPS's count only means consecutive rebuilds, and the verdict must not blame it.
    #[test]
    fn dangerous_builds_blamed_only_when_lists_were_not_checked_every_step() {
        let late = differ_verdict("thermo", 1e-9, &summary(1, 10, 2), &Growth::Agree, None);
        assert!(late.contains("so it missed pairs"), "{late}");
        let checked = differ_verdict("thermo", 1e-9, &summary(1, 0, 290), &Growth::Agree, None);
        assert!(checked.contains("not missed pairs"), "{checked}");
        assert!(!checked.contains("so it missed pairs"), "{checked}");
    }

    /// A script whose set-up draws the engine's own random numbers (`velocity create`) and
    /// differs at the start is told so, not called a model difference; without such a
    /// command, a difference at the start still is one.
    #[test]
    fn a_random_setup_is_named_not_called_a_model_difference() {
        let script = "units lj\n# velocity all create 9.0 1\nvelocity   all create 1.0 4928 \
                      loop geom # LAMMPS's\nrun 10\n";
        let found = engine_random_setup(script);
        assert_eq!(
            found,
            Some((3, "velocity all create 1.0 4928 loop geom".to_string()))
        );
        assert_eq!(
            engine_random_setup("create_atoms 1 random 100 5 NULL\n").map(|f| f.0),
            Some(1)
        );
        assert_eq!(engine_random_setup("velocity all set 0 0 0\n"), None);
        let start = Point {
            elapsed: 0,
            step: 0,
            block: 0,
            diff: 0.3,
            what: "Temp".into(),
            source: 0,
        };
        let g = Growth::AtStart {
            start,
            floor: 1e-12,
        };
        let v = differ_verdict("thermo", 1e-9, &summary(1, 0, 0), &g, found.as_ref());
        assert!(v.contains("start from different states"), "{v}");
        assert!(
            v.contains("line 3, `velocity all create 1.0 4928 loop geom`"),
            "{v}"
        );
        assert!(!v.contains("(model difference"), "{v}");
        let plain = differ_verdict("thermo", 1e-9, &summary(1, 0, 0), &g, None);
        assert!(
            plain.contains("(model difference: already 3.0e-01 at step 0"),
            "{plain}"
        );
    }

    /// The leak notes come from the engines' own end-of-run warnings (the words of
    /// `dpdnl::engine::lees_edwards::flip_leak_warning`), summed over runs, with the last V;
    /// nothing without a warning, and nothing for `fix flip/momentum`'s own line.
    #[test]
    fn flip_leak_notes_read_the_warnings() {
        use dpdnl::engine::lees_edwards::{FlipLeak, flip_jump_note, flip_leak_warning};
        let w = |atoms, momentum| {
            let leak = FlipLeak {
                atoms,
                momentum,
                conserved: false,
            };
            format!("WARNING: {}", flip_leak_warning(&leak, 400.0).unwrap())
        };
        let jumped = flip_jump_note(&FlipLeak {
            atoms: 3,
            momentum: 0.0,
            conserved: true,
        })
        .unwrap();
        let lmp = format!(
            "Step Temp\n{}\nLoop time\n{} (src/fix.cpp:12)\n",
            w(2, -60.0),
            w(1, 30.0)
        );
        let notes = flip_leak_notes(&jumped, &lmp);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].starts_with("LAMMPS: box flips put 3 atom(s)"),
            "{notes:?}"
        );
        assert!(
            notes[0].contains("(V = 0.075 in its last run)"),
            "{notes:?}"
        );
        assert!(flip_leak_notes("", &jumped).is_empty());
    }
}
