//! The machine-readable line of a run's box flips (`crate::engine::lees_edwards::FLIP_RECORD`),
//! which both engines print after their end-of-run flip note or warning.

use crate::engine::lees_edwards::FLIP_RECORD;

/// One run's [`FLIP_RECORD`] line: what its box flips did to the atoms they put through y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlipRecord {
    /// Atoms put through y at flips.
    pub atoms: u64,
    /// Whether they got remap v's velocity jump (`fix flip/momentum`, mode jump).
    pub jump: bool,
    /// Without the jump: the x momentum relative to the shear profile that they changed, as
    /// the warning prints it (six significant digits); 0 with the jump.
    pub momentum: f64,
    /// Without the jump: the mean velocity V relative to the profile, as printed; 0 with it.
    pub v: f64,
}

/// Every [`FLIP_RECORD`] line of a log, in order (one per run whose flips put atoms through
/// y). Words after the `key=value` pairs (LAMMPS's ` (file:line)`) are ignored; a line whose
/// atom count is missing or unreadable is not a record.
pub fn flip_records(text: &str) -> Vec<FlipRecord> {
    text.lines()
        .filter_map(|line| line.trim_start().strip_prefix(FLIP_RECORD))
        .filter_map(|rest| {
            let mut r = FlipRecord {
                atoms: 0,
                jump: false,
                momentum: 0.0,
                v: 0.0,
            };
            let mut atoms = None;
            for (key, value) in rest.split_whitespace().map_while(|w| w.split_once('=')) {
                match key {
                    "atoms" => atoms = value.parse().ok(),
                    "jump" => r.jump = value == "1",
                    "momentum" => r.momentum = value.parse().unwrap_or(f64::NAN),
                    "V" => r.v = value.parse().unwrap_or(f64::NAN),
                    _ => {}
                }
            }
            r.atoms = atoms?;
            Some(r)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::lees_edwards::{FlipLeak, flip_jump_note, flip_leak_warning};

    #[test]
    fn the_records_of_both_texts_read_back() {
        let leak = FlipLeak {
            atoms: 7,
            momentum: -1.234567e-3,
            conserved: false,
        };
        // LAMMPS's warning appends the file and line to the text's last line.
        let log = format!(
            "WARNING: {} (src/fix_flip_momentum.cpp:118)\n{}\n",
            flip_leak_warning(&leak, 10.0).unwrap(),
            flip_jump_note(&FlipLeak {
                conserved: true,
                ..leak
            })
            .unwrap()
        );
        let r = flip_records(&log);
        assert_eq!(r.len(), 2, "{log}");
        assert_eq!(
            r[0],
            FlipRecord {
                atoms: 7,
                jump: false,
                momentum: -0.00123457,
                v: -0.000123457,
            }
        );
        assert_eq!(
            r[1],
            FlipRecord {
                atoms: 7,
                jump: true,
                momentum: 0.0,
                v: 0.0,
            }
        );
        assert!(flip_records("flip_leak: jump=0\nflip_leak: atoms=x\n").is_empty());
    }
}
