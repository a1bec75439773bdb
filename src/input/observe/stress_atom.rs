//! `compute ID all stress/atom TEMP-ID|NULL [ke] [pair] [bond] [angle] [virial]` (LAMMPS's
//! `ComputeStressAtom`): its words, and the parts and kinetic bias it asks of
//! [`System::stress_atom`](crate::engine::System::stress_atom) at each evaluation.

use super::{Env, arg};
use crate::engine::{KineticBias, StressParts};

/// A `compute stress/atom`: the temperature compute whose bias the kinetic part removes
/// (None: `NULL`) and the parts summed (`parts.ke`'s bias is resolved at each evaluation).
#[derive(Debug)]
pub(super) struct StressAtom {
    temp: Option<String>,
    parts: StressParts,
}

impl StressAtom {
    /// `compute ID all stress/atom TEMP-ID|NULL [ke] [pair] [bond] [angle] [virial]`: LAMMPS's
    /// keywords (none: every part; `dihedral`, `improper`, `kspace` and `fix` add nothing
    /// here).
    pub(super) fn parse(args: &[String], env: &dyn Env) -> Result<StressAtom, String> {
        let usage = "compute ID all stress/atom TEMP-ID|NULL [ke] [pair] [bond] [angle] [virial]";
        let t = arg(args, 3, usage)?;
        let temp = if t == "NULL" {
            None
        } else {
            match env.observe().compute(t) {
                Some(c) if c.kind.is_temperature() => {}
                Some(c) => {
                    return Err(format!(
                        "compute stress/atom: compute '{t}' is a {} compute, not a temperature                          (give a temperature compute's ID or NULL)",
                        c.kind.style()
                    ));
                }
                None => {
                    return Err(format!(
                        "compute stress/atom: temperature compute '{t}' does not exist (define                          it first, or give NULL)"
                    ));
                }
            }
            Some(t.to_string())
        };
        let mut parts = StressParts {
            ke: Some(KineticBias::None),
            pair: true,
            bond: true,
            angle: true,
        };
        if args.len() > 4 {
            parts = StressParts {
                ke: None,
                pair: false,
                bond: false,
                angle: false,
            };
        }
        for w in &args[4..] {
            match w.as_str() {
                "ke" => parts.ke = Some(KineticBias::None),
                "pair" => parts.pair = true,
                "bond" => parts.bond = true,
                "angle" => parts.angle = true,
                "virial" => {
                    parts.pair = true;
                    parts.bond = true;
                    parts.angle = true;
                }
                // LAMMPS's terms the standalone engine does not have (no dihedrals,
                // impropers, kspace, or fixes with a virial): nothing to add, as in LAMMPS
                // without them.
                "dihedral" | "improper" | "kspace" | "fix" => {}
                o => {
                    return Err(format!(
                        "unknown compute stress/atom keyword '{o}'; usage: {usage}"
                    ));
                }
            }
        }
        Ok(StressAtom { temp, parts })
    }

    /// Whether its temperature compute is `id`.
    pub(super) fn uses_compute(&self, id: &str) -> bool {
        self.temp.as_deref() == Some(id)
    }

    /// Its temperature compute's ID (`TEMP-ID`; None for `NULL`).
    pub(super) fn temp_id(&self) -> Option<&str> {
        self.temp.as_deref()
    }

    /// Its parts, the kinetic part (when asked for) with `bias` removed: the bias of its
    /// temperature compute now, which the caller looks up in the compute list.
    pub(super) fn parts_with(&self, bias: KineticBias) -> StressParts {
        let mut parts = self.parts;
        if parts.ke.is_some() {
            parts.ke = Some(bias);
        }
        parts
    }
}
