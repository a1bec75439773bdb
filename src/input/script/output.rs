//! Files and screen output other than thermo: `dump` (custom style, sorted by atom ID),
//! `dump_modify`, `undump`, `write_dump` and the dump files, `print`, `log`.

use super::{CmdResult, Interpreter};
use crate::grammar::{at_most, need, parse_int};
use crate::input::format::{FmtArg, sprintf};
use std::fs::File;
use std::io::{BufWriter, Write};

pub(super) struct Dump {
    pub(super) id: String,
    /// The group whose atoms are written (at each write, as LAMMPS).
    pub(super) group: String,
    every: u64,
    pub(super) path: String,
    columns: Vec<String>,
    fmt_line: Option<Vec<String>>,
    fmt_int: Option<String>,
    fmt_float: Option<String>,
    writer: BufWriter<File>,
    last: Option<u64>,
}

impl Interpreter<'_> {
    pub(super) fn cmd_dump(&mut self, args: &[String]) -> CmdResult {
        let usage = "dump ID GROUP custom N FILE COLUMNS… | dump ID GROUP atom N FILE";
        // The style word first, so that a style this engine lacks is named as such, whatever
        // its arguments.
        need(args, 3, usage)?;
        if args[1] != "all" {
            self.group_bit(&args[1])?;
        }
        // `atom` is LAMMPS's default atom dump: id, type and scaled positions.
        let atom_style = match args[2].as_str() {
            "custom" => false,
            "atom" => true,
            other => {
                return Err(format!(
                    "dump style '{other}' not supported: only custom and atom (for a movie, \
                     dump custom with the columns you need: id type x y z, or xs ys zs)"
                ));
            }
        };
        if atom_style {
            need(args, 5, "dump ID all atom N FILE")?;
            at_most(args, 5, "dump ID all atom N FILE")?;
        } else {
            need(args, 6, usage)?;
        }
        if self.dumps.iter().any(|d| d.id == args[0]) {
            return Err(format!("dump ID '{}' already exists", args[0]));
        }
        let every: u64 = parse_int(&args[3], "dump interval")?;
        if every == 0 {
            return Err("dump interval must be >= 1".into());
        }
        let columns = if atom_style {
            ["id", "type", "xs", "ys", "zs"].map(String::from).to_vec()
        } else {
            args[5..].to_vec()
        };
        for c in &columns {
            if let Some(body) = c.strip_prefix("c_") {
                let id = body.split_once('[').map_or(body, |(id, _)| id);
                if !self.obs.has_per_atom(id) {
                    return Err(format!(
                        "dump column '{c}': compute '{id}' does not exist or has no per-atom \
                         values"
                    ));
                }
                self.obs.per_atom_ref(body, &format!("dump column '{c}'"))?;
                continue;
            }
            if c == "mol" && self.sys.as_ref().is_none_or(|s| s.topo.is_none()) {
                return Err(
                    "dump column 'mol': the atom style has no molecule ids (atom_style bond, \
                     angle, molecular or full)"
                        .into(),
                );
            }
            if !matches!(
                c.as_str(),
                "id" | "mol"
                    | "type"
                    | "mass"
                    | "x"
                    | "y"
                    | "z"
                    | "xu"
                    | "yu"
                    | "zu"
                    | "xs"
                    | "ys"
                    | "zs"
                    | "ix"
                    | "iy"
                    | "iz"
                    | "vx"
                    | "vy"
                    | "vz"
                    | "fx"
                    | "fy"
                    | "fz"
            ) {
                return Err(format!(
                    "unknown dump column '{c}': this engine writes id, mol, type, mass, x y z, \
                     xs ys zs, xu yu zu, ix iy iz, vx vy vz, fx fy fz and c_ID of a per-atom \
                     compute"
                ));
            }
        }
        let f = File::create(&args[4])
            .map_err(|e| format!("cannot open dump file {}: {e}", args[4]))?;
        self.dumps.push(Dump {
            id: args[0].clone(),
            group: args[1].clone(),
            every,
            path: args[4].clone(),
            columns,
            fmt_line: None,
            fmt_int: None,
            fmt_float: None,
            writer: BufWriter::new(f),
            last: None,
        });
        Ok(())
    }

    pub(super) fn cmd_dump_modify(&mut self, args: &[String]) -> CmdResult {
        let usage = "dump_modify ID sort id|off | format line|int|float FORMAT";
        need(args, 3, usage)?;
        let d = self
            .dumps
            .iter_mut()
            .find(|d| d.id == args[0])
            .ok_or_else(|| format!("no dump with ID '{}'", args[0]))?;
        let mut k = 1;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match args[k].as_str() {
                // Output is always sorted by id (the engine reorders atoms for locality).
                "sort" => k += 2,
                "flush" => k += 2,
                "format" => {
                    need(&args[k..], 3, usage)?;
                    let f = args[k + 2].clone();
                    match args[k + 1].as_str() {
                        "line" => {
                            d.fmt_line = Some(f.split_whitespace().map(String::from).collect())
                        }
                        "int" => d.fmt_int = Some(f),
                        "float" => d.fmt_float = Some(f),
                        o => {
                            return Err(format!(
                                "dump_modify format '{o}' not supported (line, int, float)"
                            ));
                        }
                    }
                    k += 3;
                }
                o => return Err(format!("unknown dump_modify keyword '{o}'")),
            }
        }
        Ok(())
    }

    pub(super) fn write_dumps(&mut self, setup: bool) -> CmdResult {
        let Some(sys) = self.sys.as_ref() else {
            return Ok(());
        };
        let step = sys.step;
        for d in self.dumps.iter_mut() {
            if step % d.every != 0 || d.last == Some(step) {
                continue;
            }
            let _ = setup;
            d.last = Some(step);
            let bit = sys.groups.bit(&d.group).unwrap_or(1);
            let mut order: Vec<usize> = (0..sys.atoms.len())
                .filter(|&i| sys.atoms.mask_of(i) & bit != 0)
                .collect();
            let n = order.len();
            order.sort_by_key(|&i| sys.atoms.tag[i]);
            let w = &mut d.writer;
            let io = |e: std::io::Error| format!("cannot write dump file: {e}");
            // A triclinic box: LAMMPS's header (the bounding box, then the tilts).
            let tilt = sys.tri.as_ref().map(|t| t.reported_xy(&sys.bx));
            writeln!(
                w,
                "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS {}pp pp pp",
                if tilt.is_some() { "xy xz yz " } else { "" }
            )
            .map_err(io)?;
            for a in 0..3 {
                let (mut lo, mut hi) = (sys.bx.lo[a], sys.bx.hi[a]);
                match tilt {
                    Some(xy) => {
                        if a == 0 {
                            lo += xy.min(0.0);
                            hi += xy.max(0.0);
                        }
                        let t = if a == 0 { xy } else { 0.0 };
                        writeln!(w, "{lo:.16e} {hi:.16e} {t:.16e}").map_err(io)?;
                    }
                    None => writeln!(w, "{lo:.16e} {hi:.16e}").map_err(io)?,
                }
            }
            writeln!(w, "ITEM: ATOMS {}", d.columns.join(" ")).map_err(io)?;
            let per_atom: Vec<Option<Vec<f64>>> = d
                .columns
                .iter()
                .map(|c| {
                    c.strip_prefix("c_")
                        .map(|body| {
                            let (id, col) = self.obs.per_atom_ref(body, "dump")?;
                            self.obs.per_atom_column(&id, col, sys)
                        })
                        .transpose()
                })
                .collect::<Result<_, _>>()?;
            let mut line = String::new();
            for &i in &order {
                line.clear();
                let mut x = sys.atoms.x[i];
                let mut im = sys.atoms.image[i];
                // A sheared box: positions as they are (as LAMMPS, wrapped when the lists are
                // rebuilt) and LAMMPS's unwrapped x + ix L_x + iy xy.
                let xu = match &sys.tri {
                    Some(t) => sys.bx.unwrap_tilted(x, im, t.reported_xy(&sys.bx)),
                    None => {
                        sys.bx.wrap(&mut x, &mut im);
                        sys.bx.unwrap(x, im)
                    }
                };
                // Scaled (LAMMPS's lamda) coordinates of the position as written in x y z.
                let xs = {
                    let l = |a: usize| sys.bx.hi[a] - sys.bx.lo[a];
                    let sy = (x[1] - sys.bx.lo[1]) / l(1);
                    let xy = sys.tri.as_ref().map_or(0.0, |t| t.reported_xy(&sys.bx));
                    [
                        (x[0] - sys.bx.lo[0] - xy * sy) / l(0),
                        sy,
                        (x[2] - sys.bx.lo[2]) / l(2),
                    ]
                };
                for (k, c) in d.columns.iter().enumerate() {
                    let (int, val) = match c.as_str() {
                        _ if per_atom[k].is_some() => {
                            (false, per_atom[k].as_ref().map_or(0.0, |v| v[i]))
                        }
                        "id" => (true, f64::from(sys.atoms.tag[i])),
                        "type" => (true, f64::from(sys.atoms.typ[i])),
                        "mol" => (true, f64::from(sys.atoms.mol_of(i))),
                        "ix" => (true, f64::from(im[0])),
                        "iy" => (true, f64::from(im[1])),
                        "iz" => (true, f64::from(im[2])),
                        "mass" => (false, sys.mass[sys.atoms.typ[i] as usize].unwrap_or(0.0)),
                        "x" => (false, x[0]),
                        "y" => (false, x[1]),
                        "z" => (false, x[2]),
                        "xu" => (false, xu[0]),
                        "yu" => (false, xu[1]),
                        "zu" => (false, xu[2]),
                        "xs" => (false, xs[0]),
                        "ys" => (false, xs[1]),
                        "zs" => (false, xs[2]),
                        "vx" => (false, sys.atoms.v[i][0]),
                        "vy" => (false, sys.atoms.v[i][1]),
                        "vz" => (false, sys.atoms.v[i][2]),
                        "fx" => (false, sys.atoms.f[i][0]),
                        "fy" => (false, sys.atoms.f[i][1]),
                        _ => (false, sys.atoms.f[i][2]),
                    };
                    let fmtstr = d
                        .fmt_line
                        .as_ref()
                        .and_then(|l| l.get(k).map(String::as_str))
                        .or(if int {
                            d.fmt_int.as_deref()
                        } else {
                            d.fmt_float.as_deref()
                        })
                        .unwrap_or(if int { "%d" } else { "%g" });
                    let arg = if int {
                        FmtArg::Int(val as i64)
                    } else {
                        FmtArg::Float(val)
                    };
                    if k > 0 {
                        line.push(' ');
                    }
                    line.push_str(&sprintf(fmtstr, &[arg])?);
                }
                writeln!(w, "{line}").map_err(io)?;
            }
            w.flush().map_err(io)?;
            let _ = &d.path;
        }
        Ok(())
    }

    /// `write_dump GROUP custom|atom FILE [COLUMNS…] [modify DUMP_MODIFY-ARGS…]` (LAMMPS's
    /// `WriteDump`): one snapshot of the current step, written as a dump of the same style with
    /// those `dump_modify` settings would write it, then closed; the script's own dumps are
    /// not touched.
    pub(super) fn cmd_write_dump(&mut self, args: &[String]) -> CmdResult {
        let usage = "write_dump GROUP custom|atom FILE [COLUMNS…] [modify DUMP_MODIFY-ARGS…]";
        need(args, 3, usage)?;
        let (dump_part, modify) = match args.iter().position(|a| a == "modify") {
            Some(k) => (&args[..k], Some(&args[k + 1..])),
            None => (args, None),
        };
        need(dump_part, 3, usage)?;
        const ID: &str = "WRITE_DUMP";
        let mut dump_args: Vec<String> =
            vec![ID.into(), dump_part[0].clone(), dump_part[1].clone()];
        dump_args.push("1".into());
        dump_args.extend(dump_part[2..].iter().cloned());
        let saved = std::mem::take(&mut self.dumps);
        let r = self.write_dump_now(&dump_args, modify);
        self.dumps = saved;
        r
    }

    /// Define the dump of `write_dump`, apply its `modify` words and write its one frame.
    fn write_dump_now(&mut self, dump_args: &[String], modify: Option<&[String]>) -> CmdResult {
        self.sys_mut()?;
        self.cmd_dump(dump_args)?;
        if let Some(m) = modify {
            if m.is_empty() {
                return Err("write_dump modify needs dump_modify arguments".into());
            }
            let mut margs = vec![dump_args[0].clone()];
            margs.extend(m.iter().cloned());
            self.cmd_dump_modify(&margs)?;
        }
        self.write_dumps(false)?;
        for d in self.dumps.iter_mut() {
            d.writer
                .flush()
                .map_err(|e| format!("cannot write dump file {}: {e}", d.path))?;
            if !self.written_dumps.contains(&d.path) {
                self.written_dumps.push(d.path.clone());
            }
        }
        Ok(())
    }

    pub(super) fn cmd_undump(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "undump ID")?;
        let before = self.dumps.len();
        self.dumps.retain(|d| d.id != args[0]);
        if self.dumps.len() == before {
            return Err(format!("no dump with ID '{}'", args[0]));
        }
        Ok(())
    }

    pub(super) fn cmd_print(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "print TEXT [file F] [append F] [screen yes|no]")?;
        let mut screen = true;
        let mut file: Option<(String, bool)> = None;
        let mut k = 1;
        while k < args.len() {
            need(
                &args[k..],
                2,
                "print TEXT [file F] [append F] [screen yes|no]",
            )?;
            match args[k].as_str() {
                "file" => file = Some((args[k + 1].clone(), false)),
                "append" => file = Some((args[k + 1].clone(), true)),
                "screen" => screen = args[k + 1] == "yes",
                o => return Err(format!("unknown print keyword '{o}'")),
            }
            k += 2;
        }
        // As LAMMPS's print: the text's own `$` variables are substituted now (those inside
        // quotes, which the line's substitution leaves).
        let text = self.substitute(&args[0])?;
        if let Some((path, append)) = file {
            let mut f = std::fs::OpenOptions::new()
                .create(true)
                .write(true)
                .append(append)
                .truncate(!append)
                .open(&path)
                .map_err(|e| format!("cannot open {path}: {e}"))?;
            writeln!(f, "{text}").map_err(|e| format!("cannot write {path}: {e}"))?;
        }
        if screen {
            self.out(&text);
        } else if let Some(l) = self.log.as_mut() {
            let _ = writeln!(l, "{text}");
        }
        Ok(())
    }

    pub(super) fn cmd_log(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "log FILE [append]")?;
        let append = args.get(1).is_some_and(|a| a == "append");
        if let Some(mut l) = self.log.take() {
            let _ = l.flush();
        }
        if args[0] != "none" {
            let f = std::fs::OpenOptions::new()
                .create(true)
                .write(true)
                .append(append)
                .truncate(!append)
                .open(&args[0])
                .map_err(|e| format!("cannot open log file {}: {e}", args[0]))?;
            self.log = Some(BufWriter::new(f));
        }
        Ok(())
    }
}
