//! `dpdnl diff A B`: compare two LAMMPS-format logs (thermo blocks) or two text dumps.
//!
//! Exit status: 0 when the files agree, 1 when they differ, 2 when they cannot be compared
//! (unreadable file, no thermo block, mismatched columns, …).

use crate::report::{TableStyle, c, write_exact_table};
use clap::ValueEnum;
use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::io::lammps_log::{
    ExactReport, StatsReport, ThermoBlock, Tolerance, compare_dumps_exact, compare_exact_logs,
    compare_stats, looks_like_dump, parse_log,
};
use dpdnl::stats::BlockEstimate;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    /// Short runs: every value must agree within --rtol / --atol (rows matched by Step, or by
    /// (step, id) for dumps).
    Exact,
    /// Long runs: column means must agree within --zmax block-averaged standard errors.
    Stats,
}

/// Compare two LAMMPS-format logs or text dumps column by column.
///
/// The kind of each file (log or dump) is detected from its content. Timing columns (CPU,
/// T/CPU, S/CPU, CPULeft, …) are left out unless named in --columns. Exit status: 0 same,
/// 1 different, 2 error.
#[derive(clap::Args)]
pub struct DiffArgs {
    /// First file (the reference, "A").
    pub a: PathBuf,
    /// Second file ("B").
    pub b: PathBuf,
    /// exact: value-by-value within tolerances; stats: means within block-averaged errors
    /// (logs only).
    #[arg(long, value_enum, default_value = "exact")]
    pub mode: Mode,
    /// Relative tolerance (exact mode): |A−B| / max(|A|, |B|).
    #[arg(long, default_value_t = 1e-9)]
    pub rtol: f64,
    /// Absolute tolerance (exact mode): a value differs only if both tolerances are exceeded.
    #[arg(long, default_value_t = 0.0)]
    pub atol: f64,
    /// Stats mode: rows to skip at the start of each log's block (equilibration).
    #[arg(long, default_value_t = 0)]
    pub skip: usize,
    /// Stats mode: largest |z| = |mean_A − mean_B| / sqrt(err_A² + err_B²) that passes.
    #[arg(long, default_value_t = 3.0)]
    pub zmax: f64,
    /// Comma-separated columns to compare (default: all common columns, which must match).
    #[arg(long, value_delimiter = ',')]
    pub columns: Option<Vec<String>>,
    /// Logs: compare only thermo block N (1-based) of each file. Default: all blocks in exact
    /// mode, the last block in stats mode.
    #[arg(long)]
    pub block: Option<usize>,
    /// Exact mode: rows present in only one file do not make the files differ.
    #[arg(long)]
    pub allow_missing: bool,
    /// Print a JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

enum Input {
    Log(Vec<ThermoBlock>),
    Dump(Vec<DumpFrame>),
}

impl Input {
    fn describe(&self) -> String {
        match self {
            Input::Log(b) => {
                let rows: usize = b.iter().map(|b| b.rows.len()).sum();
                format!("log, {} thermo block(s), {rows} rows", b.len())
            }
            Input::Dump(f) => {
                let atoms = f.first().map_or(0, |f| f.rows.len());
                format!("dump, {} frame(s), {atoms} atoms", f.len())
            }
        }
    }

    fn kind(&self) -> &'static str {
        match self {
            Input::Log(_) => "log",
            Input::Dump(_) => "dump",
        }
    }
}

fn read_input(path: &Path) -> Result<Input, String> {
    let p = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {p}: {e}"))?;
    if looks_like_dump(&text) {
        let frames = parse_dump(&text).map_err(|e| format!("{p}: {e}"))?;
        if frames.is_empty() {
            return Err(format!("{p}: the dump has no frames"));
        }
        Ok(Input::Dump(frames))
    } else {
        let blocks = parse_log(&text).map_err(|e| format!("{p}: {e}"))?;
        if blocks.is_empty() {
            return Err(format!(
                "{p}: no thermo block found (expected a line starting with 'Step' followed by \
                 rows of numbers)"
            ));
        }
        Ok(Input::Log(blocks))
    }
}

fn pick_block<'a>(
    blocks: &'a [ThermoBlock],
    block: Option<usize>,
    path: &Path,
) -> Result<&'a [ThermoBlock], String> {
    match block {
        None => Ok(blocks),
        Some(n) if n >= 1 && n <= blocks.len() => Ok(&blocks[n - 1..n]),
        Some(n) => Err(format!(
            "{}: --block {n} asked for, but the log has {} thermo block(s)",
            path.display(),
            blocks.len()
        )),
    }
}

pub fn main(a: DiffArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    match run(&a) {
        Ok(true) => Ok(ExitCode::SUCCESS),
        Ok(false) => Ok(ExitCode::from(1)),
        Err(e) => {
            eprintln!("ERROR: dpdnl diff: {e}");
            Ok(ExitCode::from(2))
        }
    }
}

/// Compares and prints; `Ok(true)` when the files agree.
fn run(args: &DiffArgs) -> Result<bool, String> {
    for (name, v) in [
        ("--rtol", args.rtol),
        ("--atol", args.atol),
        ("--zmax", args.zmax),
    ] {
        if v.is_nan() || v < 0.0 {
            return Err(format!("{name} must be a non-negative number, got {v}"));
        }
    }
    let ia = read_input(&args.a)?;
    let ib = read_input(&args.b)?;
    let context = |e: String| {
        format!(
            "comparing {} (A) with {} (B): {e}",
            args.a.display(),
            args.b.display()
        )
    };
    let columns = args.columns.as_deref();
    let tol = Tolerance {
        rtol: args.rtol,
        atol: args.atol,
    };
    match (&ia, &ib, args.mode) {
        (Input::Log(la), Input::Log(lb), Mode::Exact) => {
            let ba = pick_block(la, args.block, &args.a)?;
            let bb = pick_block(lb, args.block, &args.b)?;
            let r = compare_exact_logs(ba, bb, columns, tol).map_err(context)?;
            Ok(print_exact(args, &ia, &ib, &r))
        }
        (Input::Dump(da), Input::Dump(db), Mode::Exact) => {
            let r = compare_dumps_exact(da, db, columns, tol).map_err(context)?;
            Ok(print_exact(args, &ia, &ib, &r))
        }
        (Input::Log(la), Input::Log(lb), Mode::Stats) => {
            let n = args.block;
            let last =
                |blocks: &[ThermoBlock], path: &Path| -> Result<(ThermoBlock, usize), String> {
                    let k = n.unwrap_or(blocks.len());
                    let b = pick_block(blocks, Some(k), path)?;
                    Ok((b[0].clone(), k))
                };
            let (ba, ka) = last(la, &args.a)?;
            let (bb, kb) = last(lb, &args.b)?;
            let r = compare_stats(&ba, &bb, columns, args.skip, args.zmax).map_err(context)?;
            Ok(print_stats(args, (&ia, ka), (&ib, kb), &r))
        }
        (Input::Dump(_), Input::Dump(_), Mode::Stats) => Err(context(
            "--mode stats compares thermo logs; use --mode exact for dumps".to_string(),
        )),
        _ => Err(context(format!(
            "A is a {} but B is a {}",
            ia.kind(),
            ib.kind()
        ))),
    }
}

/// The report's first lines: the two inputs and what they are.
fn inputs_header(args: &DiffArgs, ia: &Input, ib: &Input) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "A: {} ({})", args.a.display(), ia.describe());
    let _ = writeln!(out, "B: {} ({})", args.b.display(), ib.describe());
    out
}

/// The JSON report's last fields (the columns, the verdict), printed as one line: `pass`.
fn print_json(mut o: JsonObject, cols: &[String], pass: bool, verdict: &str) -> bool {
    o.raw("columns", &format!("[{}]", cols.join(",")));
    o.bool("pass", pass);
    o.str("verdict", verdict);
    println!("{}", o.finish());
    pass
}

fn tol_text(t: Tolerance) -> String {
    format!("rtol {}, atol {}", c("%g", t.rtol), c("%g", t.atol))
}

fn exact_verdict(args: &DiffArgs, r: &ExactReport) -> (bool, String) {
    let failing = r.failing_columns();
    let rows_ok = r.rows_match() || args.allow_missing;
    let mut why = Vec::new();
    if !failing.is_empty() {
        why.push(format!(
            "{} exceed{} {}",
            failing.join(", "),
            if failing.len() == 1 { "s" } else { "" },
            tol_text(r.tolerance)
        ));
    }
    if !rows_ok {
        why.push(format!(
            "rows only in A: {}, only in B: {}",
            r.n_only_in_a, r.n_only_in_b
        ));
    }
    if why.is_empty() {
        (
            true,
            format!(
                "SAME: {} column(s) over {} row(s) within {}",
                r.columns.len(),
                r.n_matched,
                tol_text(r.tolerance)
            ),
        )
    } else {
        (false, format!("DIFFERENT: {}", why.join("; ")))
    }
}

fn print_exact(args: &DiffArgs, ia: &Input, ib: &Input, r: &ExactReport) -> bool {
    let (pass, verdict) = exact_verdict(args, r);
    if args.json {
        let mut o = JsonObject::default();
        o.str("mode", "exact");
        o.raw("a", &file_json(&args.a, ia));
        o.raw("b", &file_json(&args.b, ib));
        o.str("key", &r.key);
        o.num("rtol", r.tolerance.rtol);
        o.num("atol", r.tolerance.atol);
        o.int("n_matched", r.n_matched);
        o.int("n_only_in_a", r.n_only_in_a);
        o.int("n_only_in_b", r.n_only_in_b);
        o.raw("only_in_a", &json_str_array(&r.only_in_a));
        o.raw("only_in_b", &json_str_array(&r.only_in_b));
        let cols: Vec<String> = r
            .columns
            .iter()
            .map(|cd| {
                let mut c = JsonObject::default();
                c.str("column", &cd.column);
                c.num("max_abs", cd.max_abs);
                c.num("max_rel", cd.max_rel);
                c.int("n_fail", cd.n_fail);
                match &cd.worst {
                    Some((at, va, vb)) => {
                        let mut w = JsonObject::default();
                        w.str("at", at);
                        w.num("a", *va);
                        w.num("b", *vb);
                        c.raw("worst", &w.finish());
                    }
                    None => c.raw("worst", "null"),
                }
                c.bool("pass", cd.pass());
                c.finish()
            })
            .collect();
        return print_json(o, &cols, pass, &verdict);
    }
    let mut out = inputs_header(args, ia, ib);
    let _ = writeln!(
        out,
        "mode exact: {} row(s) matched by {}; {}",
        r.n_matched,
        r.key,
        tol_text(r.tolerance)
    );
    write_exact_table(
        &mut out,
        r,
        &TableStyle {
            labels: ["A", "B"],
            value_fmt: "%.10g",
            value_width: 17,
            blank_before_header: true,
        },
    );
    let _ = writeln!(out, "\nverdict: {verdict}");
    print!("{out}");
    pass
}

fn print_stats(
    args: &DiffArgs,
    (ia, ka): (&Input, usize),
    (ib, kb): (&Input, usize),
    r: &StatsReport,
) -> bool {
    let pass = r.pass();
    let failing = r.failing_columns();
    let verdict = if pass {
        format!(
            "SAME: {} column mean(s) agree within |z| <= {}",
            r.columns.len(),
            c("%g", r.zmax)
        )
    } else {
        format!(
            "DIFFERENT: |z| > {} for {}",
            c("%g", r.zmax),
            failing.join(", ")
        )
    };
    if args.json {
        let est = |e: &BlockEstimate| {
            let mut o = JsonObject::default();
            o.num("mean", e.mean);
            o.num("stderr", e.stderr);
            o.int("block_len", e.block_len);
            o.int("n_blocks", e.n_blocks);
            o.bool("converged", e.converged);
            o.num("n_eff", e.n_eff);
            o.finish()
        };
        let mut o = JsonObject::default();
        o.str("mode", "stats");
        o.raw("a", &file_json(&args.a, ia));
        o.raw("b", &file_json(&args.b, ib));
        o.int("block_a", ka);
        o.int("block_b", kb);
        o.int("skip", args.skip);
        o.int("n_a", r.n_a);
        o.int("n_b", r.n_b);
        o.num("zmax", r.zmax);
        let cols: Vec<String> = r
            .columns
            .iter()
            .map(|cs| {
                let mut c = JsonObject::default();
                c.str("column", &cs.column);
                c.raw("a", &est(&cs.a));
                c.raw("b", &est(&cs.b));
                c.num("z", cs.z);
                c.bool("pass", cs.pass(r.zmax));
                c.finish()
            })
            .collect();
        return print_json(o, &cols, pass, &verdict);
    }
    let mut out = inputs_header(args, ia, ib);
    let _ = writeln!(
        out,
        "mode stats: block {ka} of A ({} rows after skipping {}), block {kb} of B ({} rows); \
         errors by block averaging",
        r.n_a, args.skip, r.n_b
    );
    let w = r
        .columns
        .iter()
        .map(|c| c.column.chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    let _ = writeln!(
        out,
        "\n{:<w$}  {:>15}  {:>10}  {:>15}  {:>10}  {:>7}",
        "column", "mean A", "err A", "mean B", "err B", "z"
    );
    let mut any_unconverged = false;
    let err = |e: &BlockEstimate, flag: &mut bool| {
        *flag |= !e.converged;
        format!(
            "{}{}",
            c("%.3e", e.stderr),
            if e.converged { " " } else { "*" }
        )
    };
    for cs in &r.columns {
        let ea = err(&cs.a, &mut any_unconverged);
        let eb = err(&cs.b, &mut any_unconverged);
        let _ = writeln!(
            out,
            "{:<w$}  {:>15}  {:>10}  {:>15}  {:>10}  {:>7}{}",
            cs.column,
            c("%.8g", cs.a.mean),
            ea,
            c("%.8g", cs.b.mean),
            eb,
            c("%.2f", cs.z),
            if cs.pass(r.zmax) { "" } else { "  <- DIFFERS" }
        );
    }
    if any_unconverged {
        let _ = writeln!(
            out,
            "* error is a lower bound: the series is short for its correlation time (fewer \
             than 10 effective samples, or no plateau of the blocking)"
        );
    }
    let _ = writeln!(out, "\nverdict: {verdict}");
    print!("{out}");
    pass
}

// ---------------------------------------------------------------------------------------------
// A minimal JSON writer (no dependency): objects built field by field.
// ---------------------------------------------------------------------------------------------

#[derive(Default)]
struct JsonObject {
    fields: Vec<String>,
}

fn json_string(s: &str) -> String {
    let mut o = String::with_capacity(s.len() + 2);
    o.push('"');
    for ch in s.chars() {
        match ch {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            '\n' => o.push_str("\\n"),
            '\r' => o.push_str("\\r"),
            '\t' => o.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\u{:04x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

fn json_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:?}")
    } else {
        "null".to_string()
    }
}

fn json_str_array(items: &[String]) -> String {
    let v: Vec<String> = items.iter().map(|s| json_string(s)).collect();
    format!("[{}]", v.join(","))
}

fn file_json(path: &Path, input: &Input) -> String {
    let mut o = JsonObject::default();
    o.str("path", &path.display().to_string());
    o.str("kind", input.kind());
    o.finish()
}

impl JsonObject {
    fn raw(&mut self, key: &str, value: &str) {
        self.fields.push(format!("{}:{value}", json_string(key)));
    }
    fn str(&mut self, key: &str, value: &str) {
        self.raw(key, &json_string(value));
    }
    fn num(&mut self, key: &str, value: f64) {
        self.raw(key, &json_num(value));
    }
    fn int(&mut self, key: &str, value: usize) {
        self.raw(key, &value.to_string());
    }
    fn bool(&mut self, key: &str, value: bool) {
        self.raw(key, if value { "true" } else { "false" });
    }
    fn finish(self) -> String {
        format!("{{{}}}", self.fields.join(","))
    }
}
