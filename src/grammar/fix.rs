//! The fixes this project defines (`fix nve/euler`, `fix pex/push`; docs/fixes.md), and
//! `fix nve`, whose words the standalone engine checks the same way.

use super::{INT_MAX, StyleSpec, keywords, need, parse_f64, parse_int_in, shown};

/// `fix ID group nve`.
pub(crate) const NVE: StyleSpec = StyleSpec {
    command: "fix",
    style: "nve",
    usage: "fix ID group-ID nve",
    keywords: &[],
};

/// `fix ID group nve/euler`.
pub(crate) const NVE_EULER: StyleSpec = StyleSpec {
    command: "fix",
    style: "nve/euler",
    usage: "fix ID group-ID nve/euler",
    keywords: &[],
};

/// `fix ID group pex/push dp [width W] [every N]`.
pub(crate) const PEX_PUSH: StyleSpec = StyleSpec {
    command: "fix",
    style: "pex/push",
    usage: "fix ID group-ID pex/push dp [width W] [every N]",
    keywords: &["width", "every"],
};

/// `fix ID group flip/momentum [mode jump|check]` (issue 41).
pub(crate) const FLIP_MOMENTUM: StyleSpec = StyleSpec {
    command: "fix",
    style: "flip/momentum",
    usage: "fix ID group-ID flip/momentum [mode jump|check]",
    keywords: &["mode"],
};

/// `fix ID all dpdnl/frames N FILE` (issue 56): the state a dpdnl pair style saw and its own
/// force, every N steps (`crate::io::frames`).
pub(crate) const FRAMES: StyleSpec = StyleSpec {
    command: "fix",
    style: "dpdnl/frames",
    usage: "fix ID all dpdnl/frames N FILE",
    keywords: &[],
};

/// Parse `fix ID group dpdnl/frames N FILE` (`args` after the style name; `group` its group
/// name): every N steps, 1..=2147483647, into FILE. The frames hold every atom, so the group
/// must be `all`.
pub fn frames<S: AsRef<str>>(group: &str, args: &[S]) -> Result<(u64, String), String> {
    let usage = FRAMES.usage;
    need(args, 2, usage)?;
    if group != "all" {
        return Err(format!(
            "group '{}': a frame holds every atom (the force of each depends on its \
             neighbours), so the group must be all",
            shown(group)
        ));
    }
    let every = parse_int_in(args[0].as_ref(), "N", 1, INT_MAX)?;
    if let Some(extra) = args.get(2) {
        return Err(format!(
            "unexpected argument '{}' (usage: {usage})",
            shown(extra.as_ref())
        ));
    }
    Ok((every, args[1].as_ref().to_string()))
}

/// Parse `fix ID group flip/momentum [mode jump|check]` (`args` after the style name): true
/// for `mode jump` (the default: atoms put through y at a box flip get `remap v`'s velocity
/// jump), false for `mode check` (nothing changes; the atoms and the momentum are counted and
/// reported at the end of the run, as both engines do by themselves without this fix).
pub fn flip_momentum<S: AsRef<str>>(args: &[S]) -> Result<bool, String> {
    let mut jump = true;
    keywords(args, &FLIP_MOMENTUM, |_, val| {
        jump = match val {
            "jump" => true,
            "check" => false,
            o => {
                return Err(format!(
                    "fix flip/momentum mode '{}' must be jump or check",
                    shown(o)
                ));
            }
        };
        Ok(())
    })?;
    Ok(jump)
}

/// What `fix flip/momentum` needs of the run it is in, checked at each run's set-up in both
/// engines: a `fix deform … remap v` of the same group that changes the xy tilt only (no other
/// tilt, no box length: the jump it applies is that of an atom through y, h_rate_xy).
/// `deform`: None without a `fix deform`, else (its ID, remap v, same group, only xy changes).
pub fn flip_momentum_setup(deform: Option<(&str, bool, bool, bool)>) -> Result<(), String> {
    let Some((id, remap_v, same_group, xy_only)) = deform else {
        return Err("fix flip/momentum needs a fix deform … xy … remap v".into());
    };
    if !remap_v {
        return Err(format!(
            "fix flip/momentum needs 'remap v' on fix deform '{id}' (the jump it completes)"
        ));
    }
    if !same_group {
        return Err(format!(
            "fix flip/momentum must have the group of fix deform '{id}'"
        ));
    }
    if !xy_only {
        return Err(format!(
            "fix flip/momentum supports a fix deform '{id}' that changes the xy tilt only \
             (Couette flow: no xz or yz tilt, no change of a box length)"
        ));
    }
    Ok(())
}

/// Check `fix ID group nve` or `nve/euler` (`args` after the style name): no arguments.
pub fn integrator<S: AsRef<str>>(style: &str, args: &[S]) -> Result<(), String> {
    let spec = if style == "nve" { NVE } else { NVE_EULER };
    match args.first() {
        Some(extra) => Err(format!(
            "fix {style} takes no arguments, found '{}'; usage: {}",
            shown(extra.as_ref()),
            spec.usage
        )),
        None => Ok(()),
    }
}

/// The arguments of `fix pex/push`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PexArgs {
    /// Momentum Δp_z moved per push (finite, > 0).
    pub dp: f64,
    /// Slab width (None: Lx/20, docs/fixes.md).
    pub width: Option<f64>,
    /// Push every N steps, 1..=2147483647.
    pub every: u64,
}

/// Parse `fix ID group pex/push dp [width W] [every N]` (`args` after the style name) in a
/// box of dimension `dim`.
pub fn pex_push<S: AsRef<str>>(args: &[S], dim: usize) -> Result<PexArgs, String> {
    let usage = PEX_PUSH.usage;
    need(args, 1, usage)?;
    if dim != 3 {
        return Err("fix pex/push moves z momentum: it needs dimension 3".into());
    }
    let dp = parse_f64(args[0].as_ref(), "dp")?;
    if dp <= 0.0 {
        return Err(format!("dp = {dp} must be a finite number > 0"));
    }
    let mut p = PexArgs {
        dp,
        width: None,
        every: 1,
    };
    keywords(&args[1..], &PEX_PUSH, |key, val| {
        match key {
            "width" => {
                let w = parse_f64(val, "width")?;
                if w <= 0.0 {
                    return Err(format!("width = {w} must be a finite number > 0"));
                }
                p.width = Some(w);
            }
            _ => p.every = parse_int_in(val, "every", 1, INT_MAX)?,
        }
        Ok(())
    })?;
    Ok(p)
}

/// What a run's set-up checks of a `fix pex/push` against the box (both engines, at every
/// run): a periodic, orthogonal x axis and slabs of width W ≤ Lx/2 (the two slabs, centred at
/// Lx/4 and 3Lx/4, then do not overlap). Returns the width in use.
pub fn pex_box_check(
    width: Option<f64>,
    lx: f64,
    triclinic: bool,
    x_periodic: bool,
) -> Result<f64, String> {
    if triclinic {
        return Err("needs an orthogonal box".into());
    }
    if !x_periodic {
        return Err("needs a periodic x boundary".into());
    }
    let w = width.unwrap_or(lx / 20.0);
    if w > 0.5 * lx {
        return Err(format!("width {w} must be at most Lx/2 = {}", 0.5 * lx));
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pex_rules() {
        assert_eq!(
            pex_push(&["0.05", "width", "0.8", "every", "4"], 3),
            Ok(PexArgs {
                dp: 0.05,
                width: Some(0.8),
                every: 4
            })
        );
        assert!(pex_push(&["0.05"], 2).is_err());
        assert!(pex_push(&["-0.05"], 3).is_err());
        assert!(pex_push(&["0.05", "every", "4294967297"], 3).is_err());
        assert!(pex_push(&["0.05", "every"], 3).is_err());
        assert!(pex_push(&["0.05", "depth", "1"], 3).is_err());
        assert_eq!(pex_box_check(Some(2.0), 4.0, false, true), Ok(2.0));
        assert!(pex_box_check(Some(2.0001), 4.0, false, true).is_err());
        assert_eq!(pex_box_check(None, 4.0, false, true), Ok(0.2));
    }
}
