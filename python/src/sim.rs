//! `Simulation`: the standalone engine's interpreter (`dpdnl::input::Interpreter`) driven from
//! Python. Commands go through the interpreter exactly as `dpdnl run` sends them, so the same
//! script gives the same bits; what the interpreter prints goes to an in-memory console, from
//! which `thermo` is parsed with the crate's own log parser.

use crate::{FormatError, arr, script_error};
use dpdnl::System;
use dpdnl::input::{Console, Interpreter, Options, ScriptError as CoreError};
use dpdnl::io::lammps_log::parse_log;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How often a run looks for a pending Ctrl-C (Python's signal handlers run only when the
/// interpreter is attached; attaching costs microseconds, so a run checks at most this often).
const SIGNAL_CHECK: Duration = Duration::from_millis(20);

/// What the console shares with the `Simulation` that owns it.
struct State {
    /// Every line the interpreter printed, in order.
    lines: Vec<String>,
    /// Also print each line to the process's standard output.
    echo: bool,
    /// The exception (KeyboardInterrupt) a signal handler raised during a run.
    pending: Option<PyErr>,
    last_check: Instant,
}

/// The interpreter's console: lines into [`State`]; Ctrl-C checks during runs.
struct PyConsole {
    state: Arc<Mutex<State>>,
}

fn lock(s: &Mutex<State>) -> MutexGuard<'_, State> {
    s.lock().unwrap_or_else(|p| p.into_inner())
}

impl PyConsole {
    /// Runs Python's signal handlers (at most every [`SIGNAL_CHECK`]); true when one raised
    /// (the exception is kept in `pending`).
    fn signalled(&mut self) -> bool {
        {
            let mut st = lock(&self.state);
            if st.pending.is_some() {
                return true;
            }
            if st.last_check.elapsed() < SIGNAL_CHECK {
                return false;
            }
            st.last_check = Instant::now();
        }
        // The state is not locked while attaching (no lock is held across the GIL).
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                lock(&self.state).pending = Some(e);
                true
            }
        }
    }
}

impl Console for PyConsole {
    fn line(&mut self, text: &str) {
        let mut st = lock(&self.state);
        if st.echo {
            println!("{text}");
        }
        st.lines.push(text.to_string());
    }

    /// Asked by the interpreter after every step: a Ctrl-C stops the run there (the run ends
    /// with `interrupted at step N`, which `Simulation` turns back into the KeyboardInterrupt).
    fn interrupted(&mut self) -> bool {
        self.signalled()
    }
}

/// The interpreter, owning its console (`Interpreter::with_console`).
struct Engine(Interpreter<'static>);

impl Engine {
    fn new(state: Arc<Mutex<State>>, opts: &Options) -> Result<Engine, String> {
        Interpreter::with_console(Box::new(PyConsole { state }), opts).map(Engine)
    }

    fn interp(&self) -> &Interpreter<'static> {
        &self.0
    }

    fn interp_mut(&mut self) -> &mut Interpreter<'static> {
        &mut self.0
    }
}

/// The standalone DPD engine, driven by commands of its LAMMPS-style script language
/// (``units lj`` by default: mass m, distance σ, energy ε, time τ, k_B = 1; ``units real`` and
/// ``metal`` as in LAMMPS).
///
/// ``Simulation(dimension=3)`` starts empty, as a script before its first line;
/// :meth:`from_script` runs a script as ``dpdnl run PATH -var NAME VALUE`` does. Then
/// :meth:`command`, :meth:`commands`, :meth:`file` and :meth:`run` issue more commands, with
/// the same bits as the CLI. Per-atom arrays are copies sorted by atom id; ``thermo`` holds the
/// thermo output of each run. The examples of the methods continue this one (``sim``).
///
/// Example:
///     >>> sim = dpdnl.Simulation()
///     >>> sim.commands([
///     ...     "region box block 0 5 0 5 0 5", "create_box 1 box",
///     ...     "create_atoms 1 random 375 8675 box", "mass 1 1.0",
///     ...     "velocity all create 1.0 4928 mom yes",
///     ...     "pair_style dpd/nonlinear 1.0 1.0 7919 friction cross",
///     ...     "pair_coeff * * 25.0 4.5 0.5",
///     ...     "fix 1 all nve", "timestep 0.01",
///     ...     "thermo 50", "thermo_style custom step temp press pxy",
///     ... ])
///     >>> sim.run(100)
///     >>> sim.step, sim.natoms, sim.positions.shape
///     (100, 375, (375, 3))
///     >>> sim.thermo[-1]["Step"].tolist()
///     [0.0, 50.0, 100.0]
#[pyclass(unsendable, module = "dpdnl")]
pub struct Simulation {
    engine: Engine,
    state: Arc<Mutex<State>>,
    threads: usize,
}

fn new_sim(
    variables: Option<BTreeMap<String, String>>,
    log: Option<PathBuf>,
    threads: Option<usize>,
    echo: bool,
) -> PyResult<Simulation> {
    // The engine's parallel loops use rayon's global pool (the interpreter runs on the calling
    // thread, so that Python's signal handlers can run from its console). Its size is fixed
    // once, by the first `threads=` given (or RAYON_NUM_THREADS, else all cores).
    if let Some(n) = threads.filter(|&n| n > 0) {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
        let have = rayon::current_num_threads();
        if have != n {
            return Err(PyValueError::new_err(format!(
                "threads={n}: the engine's thread pool was already started with {have} threads \
                 in this process (the first Simulation fixes it)"
            )));
        }
    }
    let threads = rayon::current_num_threads();
    let opts = Options {
        log,
        vars: variables.unwrap_or_default().into_iter().collect(),
        threads,
        ..Options::default()
    };
    let state = Arc::new(Mutex::new(State {
        lines: Vec::new(),
        echo,
        pending: None,
        last_check: Instant::now(),
    }));
    let engine = Engine::new(state.clone(), &opts).map_err(PyOSError::new_err)?;
    Ok(Simulation {
        engine,
        state,
        threads,
    })
}

/// A 3-vector as a Python tuple.
type V3 = (f64, f64, f64);

fn t3(a: [f64; 3]) -> V3 {
    (a[0], a[1], a[2])
}

/// Atom `i`'s position and image counters wrapped into the box, as the dump command writes
/// them (between neighbour-list builds the stored position may have left the box).
fn wrapped(s: &System, i: usize) -> ([f64; 3], [i32; 3]) {
    let mut x = s.atoms.x[i];
    let mut im = s.atoms.image[i];
    s.bx.wrap(&mut x, &mut im);
    (x, im)
}

/// The (internal index) order of the atoms sorted by id.
fn by_id(tags: &[u32]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..tags.len()).collect();
    idx.sort_by_key(|&i| tags[i]);
    idx
}

impl Simulation {
    /// Runs script text with the GIL released; a Ctrl-C raised during it comes back as
    /// KeyboardInterrupt, an input error as ScriptError.
    fn exec(&mut self, py: Python<'_>, text: &str, name: &str) -> PyResult<()> {
        lock(&self.state).pending = None;
        // The interpreter is `Send` (its console is); `detach` runs this on the calling thread,
        // with the GIL released.
        let interp = self.engine.interp_mut();
        let result = py.detach(move || interp.run_text(text, name));
        self.finish(py, result)
    }

    fn exec_file(&mut self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        lock(&self.state).pending = None;
        let interp = self.engine.interp_mut();
        let result = py.detach(move || interp.run_file(&path));
        self.finish(py, result)
    }

    fn finish(&mut self, py: Python<'_>, result: Result<(), CoreError>) -> PyResult<()> {
        let pending = lock(&self.state).pending.take();
        result.map_err(|e| pending.unwrap_or_else(|| script_error(py, &e)))
    }

    fn with_atoms<'py, T>(
        &self,
        py: Python<'py>,
        k: usize,
        get: impl Fn(&System, usize) -> [T; 3],
    ) -> PyResult<Bound<'py, PyAny>>
    where
        T: numpy::Element + Copy,
    {
        let (flat, n) = match self.engine.interp().system() {
            None => (Vec::new(), 0),
            Some(s) => {
                let order = by_id(&s.atoms.tag);
                let mut flat = Vec::with_capacity(order.len() * k);
                for &i in &order {
                    flat.extend_from_slice(&get(s, i)[..k]);
                }
                (flat, order.len())
            }
        };
        Ok(PyArray1::from_vec(py, flat).reshape([n, k])?.into_any())
    }

    fn set_vectors(
        &mut self,
        values: PyReadonlyArray2<'_, f64>,
        what: &str,
        set: impl Fn(&mut dpdnl::Atoms, usize, [f64; 3]),
    ) -> PyResult<()> {
        let view = values.as_array();
        let sys = self
            .engine
            .interp_mut()
            .system_mut()
            .ok_or_else(|| PyValueError::new_err("no atoms yet: create the box first"))?;
        let order = by_id(&sys.atoms.tag);
        if view.nrows() != order.len() || !(view.ncols() == 3 || view.ncols() == sys.bx.dim) {
            return Err(PyValueError::new_err(format!(
                "{what}: expected an array of shape ({}, 3), got {:?}",
                order.len(),
                view.shape()
            )));
        }
        for (k, &i) in order.iter().enumerate() {
            let mut v = [0.0; 3];
            for c in 0..view.ncols() {
                v[c] = view[[k, c]];
            }
            if !v.iter().all(|x| x.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "{what}: row {k} (atom id {}) is not finite",
                    sys.atoms.tag[i]
                )));
            }
        }
        for (k, &i) in order.iter().enumerate() {
            let mut v = [0.0; 3];
            for c in 0..view.ncols() {
                v[c] = view[[k, c]];
            }
            set(&mut sys.atoms, i, v);
        }
        Ok(())
    }
}

#[pymethods]
impl Simulation {
    /// A fresh engine, with no box yet.
    ///
    /// Args:
    ///     dimension: 2 or 3 (the ``dimension`` command).
    ///     variables: index-style variables, name → value, as ``-var NAME VALUE`` on the
    ///         command line; None: none.
    ///     log: path of a log file to write, as ``-log``; None: no log file.
    ///     threads: worker threads of the engine; None: ``RAYON_NUM_THREADS``, else all
    ///         cores. The results are the same bits for any number. The first Simulation of
    ///         the process that gives a number fixes it; a different number later raises
    ///         ValueError.
    ///     echo: also print every output line to standard output.
    #[new]
    #[pyo3(signature = (dimension = 3, *, variables = None, log = None, threads = None, echo = false))]
    fn new(
        py: Python<'_>,
        dimension: u32,
        variables: Option<BTreeMap<String, String>>,
        log: Option<PathBuf>,
        threads: Option<usize>,
        echo: bool,
    ) -> PyResult<Simulation> {
        let mut s = new_sim(variables, log, threads, echo)?;
        s.exec(
            py,
            &format!("dimension {dimension}"),
            "Simulation(dimension)",
        )?;
        Ok(s)
    }

    /// Runs a script as ``dpdnl run PATH -var NAME VALUE …`` does.
    ///
    /// Paths inside the script are relative to the current directory, as in LAMMPS.
    ///
    /// Args:
    ///     path: the input script.
    ///     variables: index-style variables, name → value (``-var NAME VALUE``); None: none.
    ///     log: path of a log file to write; None: no log file.
    ///     threads: worker threads, as for ``Simulation()``.
    ///     echo: also print every output line to standard output.
    ///
    /// Returns:
    ///     The simulation in the state the script left it.
    ///
    /// Raises:
    ///     ScriptError: a command of the script is wrong (file and line of the script).
    ///     OSError: the script cannot be read.
    ///
    /// Example:
    ///     >>> with open("in.short", "w") as f:
    ///     ...     _ = f.write("\n".join([
    ///     ...         "region box block 0 4 0 4 0 4", "create_box 1 box",
    ///     ...         "create_atoms 1 random 192 1234 box", "mass 1 1.0",
    ///     ...         "velocity all create 1.0 87287 mom yes",
    ///     ...         "pair_style dpd/nonlinear 1.0 1.0 4242", "pair_coeff * * 25.0 4.5 0.0",
    ///     ...         "fix 1 all nve", "timestep 0.01", "run ${n}"]))
    ///     >>> s = dpdnl.Simulation.from_script("in.short", {"n": "20"})
    ///     >>> s.step
    ///     20
    #[staticmethod]
    #[pyo3(signature = (path, variables = None, *, log = None, threads = None, echo = false))]
    fn from_script(
        py: Python<'_>,
        path: PathBuf,
        variables: Option<BTreeMap<String, String>>,
        log: Option<PathBuf>,
        threads: Option<usize>,
        echo: bool,
    ) -> PyResult<Simulation> {
        let mut s = new_sim(variables, log, threads, echo)?;
        s.exec_file(py, path)?;
        Ok(s)
    }

    /// Runs one command, or several lines, of the script language.
    ///
    /// Args:
    ///     text: the command line(s), as in a script.
    ///
    /// Raises:
    ///     ScriptError: the command is wrong (file ``<command>``, the line within ``text``).
    ///
    /// Example:
    ///     >>> sim.command("thermo_style custom step temp ke pe")
    ///     >>> sim.command("run 10")
    ///     >>> sorted(sim.thermo[-1])
    ///     ['KinEng', 'PotEng', 'Step', 'Temp']
    fn command(&mut self, py: Python<'_>, text: &str) -> PyResult<()> {
        self.exec(py, text, "<command>")
    }

    /// Runs a list of commands in order, as the lines of one script named ``<commands>``.
    ///
    /// Args:
    ///     lines: the commands, one per item.
    ///
    /// Raises:
    ///     ScriptError: a command is wrong (file ``<commands>``, its 1-based position).
    ///
    /// Example:
    ///     >>> sim.commands(["variable n equal 10", "run ${n}"])
    ///     >>> sim.step
    ///     120
    fn commands(&mut self, py: Python<'_>, lines: Vec<String>) -> PyResult<()> {
        self.exec(py, &lines.join("\n"), "<commands>")
    }

    /// Runs a script file in this simulation, as ``include PATH`` does.
    ///
    /// Args:
    ///     path: the script; paths inside it are relative to the current directory.
    ///
    /// Raises:
    ///     ScriptError: a command of the file is wrong (its file and line).
    ///     OSError: the file cannot be read.
    ///
    /// Example:
    ///     >>> with open("more.in", "w") as f:
    ///     ...     _ = f.write("thermo 5\nrun 10\n")
    ///     >>> sim.file("more.in")
    ///     >>> sim.step
    ///     130
    fn file(&mut self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        self.exec_file(py, path)
    }

    /// Runs ``n`` steps: the ``run N`` command (``upto=True``: ``run N upto``).
    ///
    /// The GIL is released while it runs. Ctrl-C stops it at a step boundary with
    /// KeyboardInterrupt, the system left as it was after that step, so it can go on.
    ///
    /// Args:
    ///     n: number of steps, or with ``upto`` the step to run to.
    ///     upto: run up to step ``n`` instead of ``n`` more steps.
    ///
    /// Raises:
    ///     ScriptError: the run cannot start (no box, no pair style, …).
    ///     KeyboardInterrupt: Ctrl-C during the run.
    ///
    /// Example:
    ///     >>> sim.run(200, upto=True)
    ///     >>> sim.step
    ///     200
    #[pyo3(signature = (n, upto = false))]
    fn run(&mut self, py: Python<'_>, n: u64, upto: bool) -> PyResult<()> {
        let cmd = if upto {
            format!("run {n} upto")
        } else {
            format!("run {n}")
        };
        self.exec(py, &cmd, "<run>")
    }

    /// The current time step number.
    #[getter]
    fn step(&self) -> u64 {
        self.engine.interp().system().map_or(0, |s| s.step)
    }

    /// Number of atoms.
    #[getter]
    fn natoms(&self) -> usize {
        self.engine.interp().system().map_or(0, |s| s.atoms.len())
    }

    /// The dimension of the box, 2 or 3 (None before the box exists).
    #[getter]
    fn dimension(&self) -> Option<usize> {
        self.engine.interp().system().map(|s| s.bx.dim)
    }

    /// The time step δt, time units (lj: τ); None before the box exists.
    #[getter]
    fn dt(&self) -> Option<f64> {
        self.engine.interp().system().map(|s| s.dt)
    }

    /// ``(lo, hi, (xy, xz, yz))``: the box bounds and the tilt factors as thermo and dumps report them (all 0 for an orthogonal box), distance units (lj: σ); None before the box exists.
    #[getter(r#box)]
    fn get_box(&self) -> Option<(V3, V3, V3)> {
        self.engine.interp().system().map(|s| {
            let xy = s.tri.as_ref().map_or(0.0, |t| t.reported_xy(&s.bx));
            (t3(s.bx.lo), t3(s.bx.hi), (xy, 0.0, 0.0))
        })
    }

    /// Per-type masses, mass units (lj: m); index 0 unused, None for a type without a mass.
    #[getter]
    fn masses(&self) -> Vec<Option<f64>> {
        self.engine
            .interp()
            .system()
            .map_or(Vec::new(), |s| s.mass.clone())
    }

    /// Atom ids, ascending (int64).
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let v = match self.engine.interp().system() {
            None => Vec::new(),
            Some(s) => by_id(&s.atoms.tag)
                .iter()
                .map(|&i| s.atoms.tag[i] as i64)
                .collect(),
        };
        PyArray1::from_vec(py, v)
    }

    /// Atom types (1-based, int32), by atom id.
    #[getter]
    fn types<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let v = match self.engine.interp().system() {
            None => Vec::new(),
            Some(s) => by_id(&s.atoms.tag)
                .iter()
                .map(|&i| s.atoms.typ[i] as i32)
                .collect(),
        };
        PyArray1::from_vec(py, v)
    }

    /// Positions, shape (N, 3), by atom id, wrapped into the box as dumps write them (``x y z``), distance units (lj: σ). Settable with an (N, 3) array ((N, 2) in 2-D), by atom id; the image counters are kept.
    #[getter]
    fn get_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.with_atoms(py, 3, |s, i| wrapped(s, i).0)
    }

    /// Unwrapped positions x + image · L (dumps' ``xu yu zu``), shape (N, 3), by atom id, distance units (lj: σ).
    #[getter]
    fn unwrapped_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.with_atoms(py, 3, |s, i| {
            let (x, im) = wrapped(s, i);
            s.bx.unwrap(x, im)
        })
    }

    #[setter]
    fn set_positions(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        self.set_vectors(values, "positions", |a, i, v| a.x[i] = v)
    }

    /// Velocities, shape (N, 3), by atom id, velocity units (lj: σ/τ). Settable like ``positions``.
    #[getter]
    fn get_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.with_atoms(py, 3, |s, i| s.atoms.v[i])
    }

    #[setter]
    fn set_velocities(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        self.set_vectors(values, "velocities", |a, i, v| a.v[i] = v)
    }

    /// Forces of the last force evaluation, shape (N, 3), by atom id, force units (lj: ε/σ).
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.with_atoms(py, 3, |s, i| s.atoms.f[i])
    }

    /// Periodic image counters of ``positions`` (dumps' ``ix iy iz``), shape (N, 3), int32, by atom id.
    #[getter]
    fn images<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.with_atoms(py, 3, |s, i| wrapped(s, i).1)
    }

    /// Every line the interpreter printed (what ``dpdnl run`` shows and logs).
    #[getter]
    fn output(&self) -> Vec<String> {
        lock(&self.state).lines.clone()
    }

    /// The thermo output, one dict per run (per thermo header): column name as in the log header (``Step``, ``Temp``, ``Press``, …) → array, in the units of the thermo keyword (lj). Parsed from the printed lines with the crate's log parser, so it holds exactly what the log holds.
    #[getter]
    fn thermo<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let text = {
            let st = lock(&self.state);
            let mut t = st.lines.join("\n");
            t.push('\n');
            t
        };
        let blocks = parse_log(&text).map_err(FormatError::new_err)?;
        let out = PyList::empty(py);
        for b in &blocks {
            let d = PyDict::new(py);
            for (j, c) in b.columns.iter().enumerate() {
                let col: Vec<f64> = b.rows.iter().map(|r| r[j]).collect();
                d.set_item(c, arr(py, &col))?;
            }
            out.append(d)?;
        }
        Ok(out)
    }

    /// The file names of the dumps currently defined.
    #[getter]
    fn dump_files(&self) -> Vec<String> {
        self.engine.interp().dump_files()
    }

    /// Worker threads the runs use.
    #[getter]
    fn threads(&self) -> usize {
        self.threads
    }

    fn __repr__(&self) -> String {
        match self.engine.interp().system() {
            None => "Simulation(no box yet)".to_string(),
            Some(s) => format!(
                "Simulation(dimension={}, natoms={}, step={})",
                s.bx.dim,
                s.atoms.len(),
                s.step
            ),
        }
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Simulation>()
}
