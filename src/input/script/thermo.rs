//! Thermo output: `thermo_style`, `thermo_modify`, the keywords' values (with `thermo_modify
//! temp|press` computes and `norm`), the header line and the formatted rows.

use super::{CmdResult, Interpreter};
use crate::grammar::{need, parse_int};
use crate::input::format::{FmtArg, sprintf};
use crate::input::observe;
use std::collections::BTreeMap;

#[derive(Clone, Debug)]
pub(super) struct ThermoSettings {
    pub(super) every: u64,
    columns: Vec<String>,
    fmt_line: Option<Vec<String>>,
    fmt_int: Option<String>,
    fmt_float: Option<String>,
    fmt_col: BTreeMap<usize, String>,
    /// `thermo_modify norm yes|no` (None: LAMMPS's default of the unit style at the run, yes in
    /// `lj`, no otherwise).
    norm: Option<bool>,
    /// `thermo_modify temp ID` / `press ID` (None: thermo_temp / thermo_press).
    temp: Option<String>,
    press: Option<String>,
}

impl Default for ThermoSettings {
    fn default() -> Self {
        ThermoSettings {
            every: 0,
            columns: ["step", "temp", "epair", "emol", "etotal", "press"]
                .map(String::from)
                .to_vec(),
            fmt_line: None,
            fmt_int: None,
            fmt_float: None,
            fmt_col: BTreeMap::new(),
            norm: None,
            temp: None,
            press: None,
        }
    }
}

/// LAMMPS's header name of a thermo keyword.
fn thermo_header(kw: &str) -> String {
    match kw {
        "step" => "Step".into(),
        "elapsed" => "Elapsed".into(),
        "dt" => "Dt".into(),
        "time" => "Time".into(),
        "atoms" => "Atoms".into(),
        "temp" => "Temp".into(),
        "press" => "Press".into(),
        "ke" => "KinEng".into(),
        "pe" => "PotEng".into(),
        "epair" => "E_pair".into(),
        "evdwl" => "E_vdwl".into(),
        "emol" => "E_mol".into(),
        "ebond" => "E_bond".into(),
        "eangle" => "E_angle".into(),
        "etotal" => "TotEng".into(),
        "vol" => "Volume".into(),
        "density" => "Density".into(),
        "pxx" | "pyy" | "pzz" | "pxy" | "pxz" | "pyz" | "lx" | "ly" | "lz" | "xlo" | "xhi"
        | "ylo" | "yhi" | "zlo" | "zhi" | "xy" | "xz" | "yz" => {
            let mut c = kw.chars();
            match c.next() {
                Some(f) => f.to_uppercase().chain(c).collect(),
                None => String::new(),
            }
        }
        other => other.to_string(),
    }
}

fn is_int_keyword(kw: &str) -> bool {
    matches!(kw, "step" | "elapsed" | "atoms")
}

impl Interpreter<'_> {
    /// Whether thermo normalises extensive values by the number of atoms: `thermo_modify norm`,
    /// else LAMMPS's default of the unit style (yes in `lj` only).
    fn thermo_norm(&self) -> bool {
        self.thermo.norm.unwrap_or(self.units.is_lj())
    }

    pub(super) fn thermo_value(&self, kw: &str) -> Option<Result<f64, String>> {
        if let Some(name) = kw.strip_prefix("v_") {
            return Some(self.eval(&format!("v_{name}")));
        }
        if let Some(r) = observe::split_reference(kw) {
            return Some(r.and_then(|(kind, id, index)| {
                let v = self.obs.reference(kind, id, index, self)?;
                let n = self.sys.as_ref().map_or(0, |s| s.atoms.len());
                Ok(
                    if self.thermo_norm() && n > 0 && self.obs.extensive(kind, id, index) {
                        v / n as f64
                    } else {
                        v
                    },
                )
            }));
        }
        let no_box = || Some(Err(format!("thermo keyword '{kw}' needs a simulation box")));
        let Some(sys) = self.sys.as_ref() else {
            return match kw {
                "step" | "elapsed" | "dt" | "time" | "atoms" | "temp" | "press" | "pxx" | "pyy"
                | "pzz" | "pxy" | "pxz" | "pyz" | "ke" | "pe" | "epair" | "evdwl" | "emol"
                | "ebond" | "eangle" | "etotal" | "vol" | "lx" | "ly" | "lz" | "density" => {
                    no_box()
                }
                _ => None,
            };
        };
        let n = sys.atoms.len() as f64;
        let norm = if self.thermo_norm() && n > 0.0 {
            1.0 / n
        } else {
            1.0
        };
        // The temperature and pressure computes of thermo (LAMMPS: thermo_temp and
        // thermo_press unless thermo_modify temp/press; thermo_press uses thermo_modify's temp).
        let t = match &self.thermo.temp {
            None => sys.thermo(),
            Some(id) => match self.obs.thermo_of_temp(id, sys) {
                Ok(t) => t,
                Err(e) => return Some(Err(e)),
            },
        };
        let p = match self
            .obs
            .thermo_of_press(self.thermo.press.as_deref().unwrap_or("thermo_press"), sys)
        {
            Ok(p) => p,
            Err(e) => return Some(Err(e)),
        };
        let len = sys.bx.len();
        let v = match kw {
            "step" => sys.step as f64,
            "elapsed" => (sys.step - self.run_first) as f64,
            "dt" => self.dt,
            "time" => sys.step as f64 * self.dt,
            "atoms" => n,
            "temp" => t.temp,
            "press" => p.press,
            "pxx" => p.p_tensor[0],
            "pyy" => p.p_tensor[1],
            "pzz" => p.p_tensor[2],
            "pxy" => p.p_tensor[3],
            "pxz" => p.p_tensor[4],
            "pyz" => p.p_tensor[5],
            "xy" => sys.tri.as_ref().map_or(0.0, |tr| tr.reported_xy(&sys.bx)),
            "xz" | "yz" => 0.0,
            "ke" => t.ke * norm,
            "pe" => t.pe * norm,
            "epair" | "evdwl" => t.energies.epair * norm,
            "emol" => (t.energies.ebond + t.energies.eangle) * norm,
            "ebond" => t.energies.ebond * norm,
            "eangle" => t.energies.eangle * norm,
            "etotal" => (t.ke + t.pe) * norm,
            "vol" => t.vol,
            "lx" => len[0],
            "ly" => len[1],
            "lz" => len[2],
            "xlo" => sys.bx.lo[0],
            "xhi" => sys.bx.hi[0],
            "ylo" => sys.bx.lo[1],
            "yhi" => sys.bx.hi[1],
            "zlo" => sys.bx.lo[2],
            "zhi" => sys.bx.hi[2],
            "density" => {
                let m: f64 = sys
                    .atoms
                    .typ
                    .iter()
                    .map(|&ty| sys.mass[ty as usize].unwrap_or(0.0))
                    .sum();
                m * sys.units.mv2d / t.vol
            }
            _ => return None,
        };
        Some(Ok(v))
    }

    pub(super) fn thermo_header_line(&self) -> String {
        self.thermo
            .columns
            .iter()
            .map(|c| thermo_header(c))
            .collect::<Vec<_>>()
            .join(" ")
    }

    pub(super) fn thermo_row(&self) -> Result<String, String> {
        let mut fields = Vec::with_capacity(self.thermo.columns.len());
        for (k, kw) in self.thermo.columns.iter().enumerate() {
            let v = self
                .thermo_value(kw)
                .ok_or_else(|| format!("unknown thermo keyword '{kw}'"))??;
            let int = is_int_keyword(kw);
            let fmtstr = self
                .thermo
                .fmt_col
                .get(&(k + 1))
                .cloned()
                .or_else(|| {
                    self.thermo
                        .fmt_line
                        .as_ref()
                        .and_then(|l| l.get(k).cloned())
                })
                .or_else(|| {
                    if int {
                        self.thermo.fmt_int.clone()
                    } else {
                        self.thermo.fmt_float.clone()
                    }
                })
                .unwrap_or_else(|| if int { "%10d".into() } else { "%14.8g".into() });
            let arg = if int {
                FmtArg::Int(v as i64)
            } else {
                FmtArg::Float(v)
            };
            fields.push(sprintf(&fmtstr, &[arg])?);
        }
        Ok(fields.join(" "))
    }

    pub(super) fn cmd_thermo_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "thermo_style custom KEYWORDS… | thermo_style one")?;
        match args[0].as_str() {
            "one" => self.thermo.columns = ThermoSettings::default().columns,
            "custom" => {
                need(args, 2, "thermo_style custom KEYWORDS…")?;
                for kw in &args[1..] {
                    let known = kw.starts_with("v_")
                        || kw.starts_with("f_")
                        || kw.starts_with("c_")
                        || matches!(
                            kw.as_str(),
                            "step"
                                | "elapsed"
                                | "dt"
                                | "time"
                                | "atoms"
                                | "temp"
                                | "press"
                                | "pxx"
                                | "pyy"
                                | "pzz"
                                | "pxy"
                                | "pxz"
                                | "pyz"
                                | "ke"
                                | "pe"
                                | "epair"
                                | "evdwl"
                                | "emol"
                                | "ebond"
                                | "eangle"
                                | "etotal"
                                | "vol"
                                | "lx"
                                | "ly"
                                | "lz"
                                | "xlo"
                                | "xhi"
                                | "ylo"
                                | "yhi"
                                | "zlo"
                                | "zhi"
                                | "xy"
                                | "xz"
                                | "yz"
                                | "density"
                        );
                    if !known {
                        return Err(format!("unknown thermo keyword '{kw}'"));
                    }
                }
                self.thermo.columns = args[1..].to_vec();
            }
            o => return Err(format!("thermo_style '{o}' not supported (one, custom)")),
        }
        self.thermo.fmt_line = None;
        self.thermo.fmt_col.clear();
        // As LAMMPS: a new thermo_style drops thermo_modify's temp and press (thermo_press
        // keeps the temperature thermo_modify gave it).
        if self.thermo.temp.is_some() || self.thermo.press.is_some() {
            self.thermo.temp = None;
            self.thermo.press = None;
            self.warn("New thermo_style command, previous thermo_modify settings will be lost");
        }
        Ok(())
    }

    pub(super) fn cmd_thermo_modify(&mut self, args: &[String]) -> CmdResult {
        let usage = "thermo_modify norm yes|no | format line|int|float|N FORMAT | flush yes|no | temp ID | press ID";
        need(args, 2, usage)?;
        let mut k = 0;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match args[k].as_str() {
                "norm" => self.thermo.norm = Some(args[k + 1] == "yes"),
                "flush" | "lost" | "lost/bond" | "warn" => {}
                "temp" => {
                    let id = &args[k + 1];
                    self.obs.set_thermo_temp(id)?;
                    self.thermo.temp = Some(id.clone());
                }
                "press" => {
                    let id = &args[k + 1];
                    if !self.obs.is_pressure(id) {
                        return Err(format!(
                            "thermo_modify press: '{id}' is not a pressure compute"
                        ));
                    }
                    self.thermo.press = Some(id.clone());
                }
                "format" => {
                    need(&args[k..], 3, usage)?;
                    let what = args[k + 1].as_str();
                    let f = args[k + 2].clone();
                    match what {
                        "line" => {
                            self.thermo.fmt_line =
                                Some(f.split_whitespace().map(String::from).collect())
                        }
                        "int" => self.thermo.fmt_int = Some(f),
                        "float" => self.thermo.fmt_float = Some(f),
                        "none" => {
                            self.thermo.fmt_line = None;
                            self.thermo.fmt_int = None;
                            self.thermo.fmt_float = None;
                            self.thermo.fmt_col.clear();
                            k += 2;
                            continue;
                        }
                        n => {
                            let col: usize = parse_int(n, "thermo column")?;
                            if col == 0 || col > self.thermo.columns.len() {
                                return Err(format!("thermo column {col} out of range"));
                            }
                            self.thermo.fmt_col.insert(col, f);
                        }
                    }
                    k += 3;
                    continue;
                }
                o => return Err(format!("unknown thermo_modify keyword '{o}'")),
            }
            k += 2;
        }
        Ok(())
    }
}
