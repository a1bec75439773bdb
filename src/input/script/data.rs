//! The data-file commands: `read_data` (also the box of a crosscheck from LAMMPS's state) and
//! `write_data`, in LAMMPS's layout ([`crate::io::data`]).

use super::{CmdResult, Interpreter};
use crate::engine::lees_edwards::Triclinic;
use crate::grammar::{need, parse_int};
use crate::io::data::{CoeffKind, DataFile, format_data_with, parse_data_columns, style_match};
use std::collections::BTreeMap;

impl Interpreter<'_> {
    pub(super) fn cmd_read_data(&mut self, args: &[String]) -> CmdResult {
        let (d, nocoeff, group) = self.read_data_file(args)?;
        let (n, ntypes, nb, nbt, na, nat) = (
            d.atoms.len(),
            d.ntypes,
            d.bonds.len(),
            d.nbondtypes,
            d.angles.len(),
            d.nangletypes,
        );
        self.fill_new_system(d, nocoeff, &args[0])?;
        if let Some(g) = group {
            // LAMMPS: the atoms read join group ID (here every atom: no `add`).
            let sys = self.sys_mut()?;
            let tags = sys.atoms.tag.clone();
            sys.set_group_members(&g, &tags)?;
        }
        self.out(&format!(
            "Read data file {}: {n} atoms, {ntypes} atom types",
            args[0]
        ));
        if self.atom_style.molecular() {
            self.out(&format!(
                "  {nb} bonds, {nbt} bond types, {na} angles, {nat} angle types"
            ));
        }
        Ok(())
    }

    /// The data file of a `read_data` command, read and checked, with its keywords' extra
    /// types added; whether `nocoeff` was given; the group of `group ID`.
    pub(super) fn read_data_file(
        &mut self,
        args: &[String],
    ) -> Result<(DataFile, bool, Option<String>), String> {
        let usage = "read_data FILE [nocoeff] [group ID] [extra/atom/types N] [extra/bond/types N] [extra/angle/types N] [extra/bond|angle|dihedral|improper|special/per/atom N]";
        need(args, 1, usage)?;
        // LAMMPS's keywords that make room for more (types added to the file's counts; the
        // per-atom ones only size LAMMPS's arrays and change nothing here), and `nocoeff`
        // (the file's coefficient sections are skipped).
        let mut extra_types = [0usize; 3];
        let mut nocoeff = false;
        let mut group = None;
        let mut k = 1;
        while k < args.len() {
            let slot = match args[k].as_str() {
                "nocoeff" => {
                    nocoeff = true;
                    k += 1;
                    continue;
                }
                "group" => {
                    let id = args.get(k + 1).ok_or_else(|| {
                        format!("read_data group needs a group ID; usage: {usage}")
                    })?;
                    group = Some(id.clone());
                    k += 2;
                    continue;
                }
                "extra/atom/types" => Some(0),
                "extra/bond/types" => Some(1),
                "extra/angle/types" => Some(2),
                "extra/bond/per/atom"
                | "extra/angle/per/atom"
                | "extra/dihedral/per/atom"
                | "extra/improper/per/atom"
                | "extra/special/per/atom" => None,
                other => {
                    return Err(format!(
                        "read_data keyword '{}' not supported; usage: {usage}",
                        crate::grammar::shown(other)
                    ));
                }
            };
            let v = args
                .get(k + 1)
                .ok_or_else(|| format!("read_data {} needs a count", args[k]))?;
            let n: usize = parse_int(v, &args[k])?;
            if let Some(s) = slot {
                if s > 0 && !self.atom_style.molecular() {
                    return Err(format!(
                        "read_data {}: atom_style {} has no bonds",
                        args[k],
                        self.atom_style.word()
                    ));
                }
                extra_types[s] = n;
            }
            k += 2;
        }
        let text = std::fs::read_to_string(&args[0])
            .map_err(|e| format!("cannot read data file {}: {e}", args[0]))?;
        let mut d = parse_data_columns(&text, &args[0], &self.atom_columns)?;
        d.ntypes = d.ntypes.saturating_add(extra_types[0]);
        d.nbondtypes = d.nbondtypes.saturating_add(extra_types[1]);
        d.nangletypes = d.nangletypes.saturating_add(extra_types[2]);
        Ok((d, nocoeff, group))
    }

    /// A new box made from the data file `d` (named `file` in messages): the topology (the
    /// styles given before take the type counts), the box with the pair style given before it,
    /// the atoms, velocities and masses, then the coefficient sections in file order. On an
    /// error no box is left (as if the command had not run: an embedding may go on).
    pub(super) fn fill_new_system(
        &mut self,
        mut d: DataFile,
        nocoeff: bool,
        file: &str,
    ) -> CmdResult {
        crate::engine::check_ntypes(d.ntypes)?;
        for n in [d.nbondtypes, d.nangletypes] {
            crate::engine::check_ntypes(n.max(1))?;
        }
        d.masses.resize(d.ntypes + 1, None);
        if self.dim == 2 && d.atoms.iter().any(|a| a.2[2] != 0.0) {
            return Err(format!("{file}: a 2-D system needs z = 0 for every atom"));
        }
        if let Some(h) = &d.atoms_hint
            && !style_match(h, self.atom_columns.word())
        {
            self.warn(&format!(
                "Atom style in data file {h} differs from currently defined atom style {}",
                self.atom_columns.word()
            ));
        }
        let topo = if self.atom_style.molecular() {
            let mut t = self
                .pre_topo
                .topology(self.atom_style, d.nbondtypes, d.nangletypes)?;
            t.bonds = d.bonds.clone();
            t.angles = d.angles.clone();
            Some(t)
        } else {
            None
        };
        self.new_system(d.ntypes, d.lo, d.hi)?;
        let filled = self.fill_from_data(&d, topo, nocoeff, file);
        if filled.is_err() {
            self.sys = None;
        }
        self.atom_extra = d
            .atoms
            .iter()
            .zip(&d.extra)
            .map(|(a, e)| (a.0, *e))
            .collect();
        filled
    }

    /// The new box of `read_data` filled from the file `d`: the topology `topo`, the tilt, the
    /// atoms, velocities and masses, and the coefficient sections ([`Self::apply_data_coeffs`]).
    fn fill_from_data(
        &mut self,
        d: &DataFile,
        topo: Option<crate::engine::Topology>,
        nocoeff: bool,
        file: &str,
    ) -> CmdResult {
        let sys = self.sys_mut()?;
        if let Some(t) = d.tilt {
            sys.tri = Some(Triclinic::new(t[0]));
        }
        sys.topo = topo;
        let mut index = BTreeMap::new();
        for (k, &(tag, t, x, im)) in d.atoms.iter().enumerate() {
            match d.mol.get(k) {
                Some(&m) => sys.atoms.push_mol(tag, t, m, x, [0.0; 3], im),
                None => sys.atoms.push(tag, t, x, [0.0; 3], im),
            }
            index.insert(tag, k);
        }
        // A tilted box: every atom into the box as LAMMPS's `read_data` remaps it (through y
        // with the tilt, no velocity change), x + ix L_x + iy xy kept.
        sys.remap_into_box();
        for (tag, v) in &d.velocities {
            let k = index
                .get(tag)
                .ok_or_else(|| format!("{file}: Velocities for unknown atom id {tag}"))?;
            sys.atoms.v[*k] = *v;
        }
        for (t, m) in d.masses.iter().enumerate() {
            if m.is_some() {
                sys.mass[t] = *m;
            }
        }
        self.apply_data_coeffs(d, nocoeff, file)
    }

    /// The coefficient sections of a data file, in file order, as LAMMPS's `read_data` applies
    /// them: each needs its style defined before `read_data` ("Must define pair_style before
    /// Pair Coeffs", an error naming the file and line); a `# style` after the title that does
    /// not match the style defined (LAMMPS's `style_match`) is LAMMPS's warning, and the lines
    /// go to the style defined all the same, each as its coefficient command (`Pair Coeffs`
    /// line `I c…` as `pair_coeff I I c…`), whose errors name the file and line. A later
    /// `pair_coeff`, `bond_coeff` or `angle_coeff` overrides them, as any second coefficient
    /// command does. With `nocoeff` LAMMPS reads the sections into `zero` styles and drops them:
    /// no style is needed, and the warning compares the `# style` with `zero`.
    fn apply_data_coeffs(&mut self, d: &DataFile, nocoeff: bool, file: &str) -> CmdResult {
        for c in &d.coeffs {
            let title = c.kind.title();
            let sys = self.sys_mut()?;
            let defined: Option<&'static str> = if nocoeff {
                Some("zero")
            } else {
                match c.kind {
                    CoeffKind::Pair | CoeffKind::PairIJ => sys.pair.as_deref().map(|p| p.name()),
                    CoeffKind::Bond => sys
                        .topo
                        .as_ref()
                        .and_then(|t| t.bond_style.as_ref())
                        .map(|b| b.form.word()),
                    CoeffKind::Angle => sys
                        .topo
                        .as_ref()
                        .and_then(|t| t.angle_style.as_ref())
                        .map(|a| a.form.word()),
                }
            };
            let Some(defined) = defined else {
                return Err(format!(
                    "{file}:{}: Must define {} before {title}",
                    c.line,
                    c.kind.style_command()
                ));
            };
            if let Some(h) = &c.style
                && !style_match(h, defined)
            {
                let (big, small) = match c.kind {
                    CoeffKind::Pair | CoeffKind::PairIJ => ("Pair", "pair"),
                    CoeffKind::Bond => ("Bond", "bond"),
                    CoeffKind::Angle => ("Angle", "angle"),
                };
                self.warn(&format!(
                    "{big} style {h} in data file differs from currently defined {small} style \
                     {defined}"
                ));
            }
            if nocoeff {
                continue;
            }
            let sys = self.sys_mut()?;
            for (k, (line, _)) in c.lines.iter().enumerate() {
                let words = c.command_words(k);
                let res = match c.kind {
                    CoeffKind::Pair | CoeffKind::PairIJ => {
                        sys.pair.as_deref_mut().map(|p| p.coeff(&words))
                    }
                    CoeffKind::Bond => sys
                        .topo
                        .as_mut()
                        .and_then(|t| t.bond_style.as_mut())
                        .map(|b| b.set_coeff(&words)),
                    CoeffKind::Angle => sys
                        .topo
                        .as_mut()
                        .and_then(|t| t.angle_style.as_mut())
                        .map(|a| a.set_coeff(&words)),
                };
                if let Some(Err(e)) = res {
                    return Err(format!("{file}:{line}: {title}: {e}"));
                }
            }
        }
        Ok(())
    }

    pub(super) fn cmd_write_data(&mut self, args: &[String]) -> CmdResult {
        let usage = "write_data FILE [nocoeff] [nofix] [pair ii|ij]";
        need(args, 1, usage)?;
        let mut nocoeff = false;
        let mut pair: Option<CoeffKind> = None;
        let mut k = 1;
        while k < args.len() {
            match args[k].as_str() {
                "nocoeff" => nocoeff = true,
                // No fix here writes a data section of its own.
                "nofix" => {}
                "pair" => {
                    pair = Some(match args.get(k + 1).map(String::as_str) {
                        Some("ii") => CoeffKind::Pair,
                        Some("ij") => CoeffKind::PairIJ,
                        o => {
                            return Err(format!(
                                "write_data pair needs ii or ij, found '{}'; usage: {usage}",
                                crate::grammar::shown(o.unwrap_or(""))
                            ));
                        }
                    });
                    k += 1;
                }
                a => {
                    return Err(format!(
                        "write_data keyword '{}' not supported; usage: {usage}",
                        crate::grammar::shown(a)
                    ));
                }
            }
            k += 1;
        }
        let sys = self.sys.as_mut().ok_or("needs a simulation box first")?;
        // A tilted box: LAMMPS's `write_data` wraps the atoms first (`Domain::pbc`, with the
        // velocity jump of `remap v` for an atom through y), then writes them in its tilted
        // cell with its image flags.
        let tilt = sys.tri.is_some().then(|| sys.pbc());
        let sys = self.sys.as_ref().ok_or("needs a simulation box first")?;
        let mut order: Vec<usize> = (0..sys.atoms.len()).collect();
        order.sort_by_key(|&i| sys.atoms.tag[i]);
        let mut atoms = Vec::with_capacity(order.len());
        let mut vels = Vec::with_capacity(order.len());
        let mut mol = Vec::new();
        for &i in &order {
            let mut x = sys.atoms.x[i];
            let mut im = sys.atoms.image[i];
            match tilt {
                Some(xy) => sys.to_tilted_cell(&mut x, &mut im, xy),
                None => sys.bx.wrap(&mut x, &mut im),
            }
            atoms.push((sys.atoms.tag[i], sys.atoms.typ[i], x, im));
            vels.push((sys.atoms.tag[i], sys.atoms.v[i]));
            if sys.topo.is_some() {
                mol.push(sys.atoms.mol_of(i));
            }
        }
        let mut d = DataFile {
            ntypes: sys.ntypes,
            lo: sys.bx.lo,
            hi: sys.bx.hi,
            tilt: tilt.map(|xy| [xy, 0.0, 0.0]),
            masses: sys.mass.clone(),
            atoms,
            velocities: vels,
            mol,
            ..DataFile::default()
        };
        let mut coeffs = [None, None];
        if let Some(t) = &sys.topo {
            d.style = t.style;
            d.nbondtypes = t.nbondtypes;
            d.nangletypes = t.nangletypes;
            d.bonds = t.bonds.clone();
            d.angles = t.angles.clone();
            if !nocoeff {
                let rows = |c: &[Option<Vec<f64>>]| -> Option<Vec<Vec<f64>>> {
                    c.iter()
                        .skip(1)
                        .cloned()
                        .collect::<Option<Vec<_>>>()
                        .map(|mut v| {
                            v.insert(0, Vec::new());
                            v
                        })
                };
                if let Some(b) = &t.bond_style
                    && t.nbondtypes > 0
                {
                    coeffs[0] = rows(&b.coeff).map(|r| (b.form.word().to_string(), r));
                }
                if let Some(a) = &t.angle_style
                    && t.nangletypes > 0
                {
                    coeffs[1] = rows(&a.coeff).map(|r| (a.form.word().to_string(), r));
                }
            }
        }
        if !self.atom_columns.is_plain() {
            d.style = self.atom_columns.base;
            d.columns = self.atom_columns.clone();
            d.extra = d
                .atoms
                .iter()
                .map(|a| self.atom_extra.get(&a.0).copied().unwrap_or_default())
                .collect();
        }
        if let Some(kind) = pair.filter(|_| !nocoeff)
            && let Some(p) = sys.pair.as_deref().filter(|p| p.writes_data())
        {
            d.coeffs.push(pair_coeff_section(p, kind, sys.ntypes)?);
        }
        let title = format!(
            "LAMMPS data file via write_data (dpdnl), timestep = {}",
            sys.step
        );
        std::fs::write(&args[0], format_data_with(&d, &title, &coeffs))
            .map_err(|e| format!("cannot write {}: {e}", args[0]))
    }
}

/// The `Pair Coeffs` (`kind` Pair: a line `I c…` per type) or `PairIJ Coeffs` (a line `I J c…`
/// per type pair I ≤ J) section of `write_data … pair ii|ij`, numbers as LAMMPS's styles
/// write them (`%.17g`), for a style that writes data coefficients.
fn pair_coeff_section(
    p: &dyn crate::forces::PairStyle,
    kind: CoeffKind,
    ntypes: usize,
) -> Result<crate::io::data::CoeffSection, String> {
    let mut lines = Vec::new();
    for i in 1..=ntypes {
        let js: Vec<usize> = match kind {
            CoeffKind::PairIJ => (i..=ntypes).collect(),
            _ => vec![i],
        };
        for j in js {
            let mut words = vec![i.to_string()];
            if kind == CoeffKind::PairIJ {
                words.push(j.to_string());
            }
            for v in p.data_coeffs(i, j).unwrap_or_default() {
                words.push(crate::input::format::sprintf(
                    "%.17g",
                    &[crate::input::format::FmtArg::Float(v)],
                )?);
            }
            lines.push((0, words));
        }
    }
    Ok(crate::io::data::CoeffSection {
        kind,
        line: 0,
        style: Some(p.name().to_string()),
        lines,
    })
}
