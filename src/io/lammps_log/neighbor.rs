//! LAMMPS's neighbour-list settings lines and "Dangerous builds" counts in a log.

/// One `Neighbor list info` settings line of a LAMMPS log: `update every 1 steps, delay 10
/// steps, check yes` (LAMMPS up to 2022) or `update: every = 1 steps, delay = 0 steps, check =
/// yes` (later), the values of `neigh_modify every/delay/check`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NeighborSettings {
    pub every: u64,
    pub delay: u64,
    pub check: bool,
}

impl NeighborSettings {
    /// `every 1 delay 10 check yes`, as `neigh_modify` spells it.
    pub fn keywords(&self) -> String {
        format!(
            "every {} delay {} check {}",
            self.every,
            self.delay,
            if self.check { "yes" } else { "no" }
        )
    }

    /// `every 1 delay 0 check yes`: the lists are checked every step, so no build is late.
    pub fn checks_every_step(&self) -> bool {
        self.every == 1 && self.delay == 0 && self.check
    }

    fn parse(line: &str) -> Option<NeighborSettings> {
        let rest = line.trim().strip_prefix("update")?;
        let toks: Vec<&str> = rest
            .split(|c: char| c.is_whitespace() || matches!(c, ':' | '=' | ','))
            .filter(|t| !t.is_empty())
            .collect();
        let after = |key: &str| {
            toks.iter()
                .position(|t| *t == key)
                .and_then(|i| toks.get(i + 1))
        };
        Some(NeighborSettings {
            every: after("every")?.parse().ok()?,
            delay: after("delay")?.parse().ok()?,
            check: match *after("check")? {
                "yes" => true,
                "no" => false,
                _ => return None,
            },
        })
    }
}

/// What a LAMMPS log says about its neighbour lists: the settings printed under `Neighbor list
/// info ...` at a run's set-up, and the `Dangerous builds = N` line of each run's summary (a
/// build is dangerous when some atom had moved more than half the skin since the previous one:
/// pairs may have been missed in between).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NeighborSummary {
    /// Each settings line, in log order.
    pub settings: Vec<NeighborSettings>,
    /// Each run's dangerous-build count, in log order; `None` where LAMMPS printed `Dangerous
    /// builds not checked` (`check no`).
    pub dangerous: Vec<Option<u64>>,
}

impl NeighborSummary {
    /// Dangerous builds over all runs.
    pub fn dangerous_total(&self) -> u64 {
        self.dangerous.iter().flatten().sum()
    }

    /// Runs whose dangerous builds LAMMPS did not count.
    pub fn unchecked_runs(&self) -> usize {
        self.dangerous.iter().filter(|d| d.is_none()).count()
    }
}

/// Reads the neighbour-list settings and dangerous-build counts from a LAMMPS log's text
/// (empty when there are none, e.g. a log of this project's engine).
pub fn neighbor_summary(text: &str) -> NeighborSummary {
    let mut out = NeighborSummary::default();
    for line in text.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("Dangerous builds") {
            let rest = rest.trim();
            if let Some(n) = rest.strip_prefix('=').and_then(|n| n.trim().parse().ok()) {
                out.dangerous.push(Some(n));
            } else if rest == "not checked" {
                out.dangerous.push(None);
            }
        } else if t.starts_with("update")
            && let Some(s) = NeighborSettings::parse(t)
        {
            out.settings.push(s);
        }
    }
    out
}
