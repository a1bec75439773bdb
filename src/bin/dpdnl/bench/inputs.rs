//! What a benchmark runs on: the machine line, generated data files and input scripts.

use super::*;

/// "CPU: …, N cores" from /proc/cpuinfo and the OS.
pub(super) fn machine_line(threads: usize) -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "machine: {cpu}, {cores} cores available; threads used: {threads}; dpdnl {} ({})",
        env!("CARGO_PKG_VERSION"),
        if cfg!(debug_assertions) {
            "debug build: numbers are meaningless"
        } else {
            "release build"
        }
    )
}

pub(super) fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// The first line of `exe -h` that names the LAMMPS version.
pub(super) fn lammps_version(exe: &Path) -> String {
    let Ok(o) = Command::new(exe).arg("-h").output() else {
        return "cannot run".into();
    };
    let text = String::from_utf8_lossy(&o.stdout);
    text.lines()
        .find(|l| l.starts_with("LAMMPS version") || l.contains("LAMMPS ("))
        .or_else(|| text.lines().find(|l| l.contains("Large-scale")))
        .map_or("version unknown".into(), |l| l.trim().to_string())
}

pub(super) fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

pub(super) fn range(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

pub(super) fn data_name(sys: &RefSystem) -> String {
    format!("data.{}", sys.key)
}

/// N atoms uniformly in a cube of side (N/n)^(1/3), Maxwell velocities at kT (m = 1) with the
/// centre-of-mass motion removed; keyed random numbers, so the file is the same every time.
pub(super) fn write_data(dir: &Path, sys: &RefSystem, n: usize) -> Result<(), String> {
    if n < 100 || n > u32::MAX as usize / 2 {
        return Err(format!("--atoms {n} must be between 100 and 2^31"));
    }
    let dim = sys.dim;
    let l = (n as f64 / sys.density).powf(1.0 / dim as f64);
    if l < 2.0 * 1.3 {
        return Err(format!(
            "--atoms {n} gives a box of side {l:.2} at n = {}: too small (needs > 2.6)",
            sys.density
        ));
    }
    // 2-D: a square of side l, z in [−0.5, 0.5), atoms at z = 0.
    let (lo, hi) = if dim == 2 {
        ([0.0, 0.0, -0.5], [l, l, 0.5])
    } else {
        ([0.0; 3], [l; 3])
    };
    let mut d = DataFile {
        ntypes: 1,
        lo,
        hi,
        masses: vec![None, Some(1.0)],
        ..Default::default()
    };
    let sd = sys.kt.sqrt();
    let mut vsum = [0.0; 3];
    for k in 0..n {
        let tag = k as u32 + 1;
        let x = [0, 1, 2].map(|c| {
            if (c as usize) < dim {
                l * keyed_uniform(DATA_SEED, STREAM_CREATE_ATOMS, 0, tag, c)
            } else {
                0.0
            }
        });
        let v = [0, 1, 2].map(|c| {
            if (c as usize) < dim {
                sd * keyed_gaussian(DATA_SEED, STREAM_VELOCITY, 0, tag, c)
            } else {
                0.0
            }
        });
        for c in 0..3 {
            vsum[c] += v[c];
        }
        d.atoms.push((tag, 1, x, [0; 3]));
        d.velocities.push((tag, v));
    }
    for (_, v) in d.velocities.iter_mut() {
        for c in 0..3 {
            v[c] -= vsum[c] / n as f64;
        }
    }
    let path = dir.join(data_name(sys));
    std::fs::write(&path, format_data(&d, "dpdnl bench"))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The input script: identical for every engine except the pair style lines.
pub(super) fn script(
    sys: &RefSystem,
    data: &str,
    variant: Variant,
    native: bool,
    steps: u64,
) -> String {
    let pair = if native {
        format!(
            "pair_style dpd {} 1.0 {PAIR_SEED}\npair_coeff 1 1 {} {}\n",
            sys.kt, sys.a, sys.gamma0
        )
    } else if variant == Variant::Sdpd {
        format!(
            "pair_style sdpd {} 1.0 {PAIR_SEED} kernel lucy\npair_coeff 1 1 {} {} 1.0\n",
            sys.kt,
            sys.density,
            4.0 * sys.kt.sqrt()
        )
    } else {
        let (friction, noise, g1) = match variant {
            Variant::DotTwoStep => ("dot", "twostep", sys.gamma1),
            _ => ("none", "plain", 0.0),
        };
        format!(
            "pair_style dpd/nonlinear {} 1.0 {PAIR_SEED} friction {friction} noise {noise}\n\
             pair_coeff 1 1 {} {} {g1}\n",
            sys.kt, sys.a, sys.gamma0
        )
    };
    let (dimension, enforce) = if sys.dim == 2 {
        ("dimension 2\n", "fix 3 all enforce2d\n")
    } else {
        ("", "")
    };
    let (triclinic, deform) = if variant == Variant::Sheared {
        (
            "change_box all triclinic\n".to_string(),
            format!("fix 2 all deform 1 xy erate {SHEAR_RATE} remap v\n"),
        )
    } else {
        (String::new(), String::new())
    };
    format!(
        "# dpdnl bench: {}\nunits lj\n{dimension}atom_style atomic\ncomm_modify vel yes\n\
         read_data {data}\n{triclinic}{pair}neighbor 0.3 bin\n\
         neigh_modify every 1 delay 0 check yes\ntimestep {}\nfix 1 all nve\n{deform}{enforce}\
         thermo {steps}\nrun {steps}\n",
        sys.title, sys.dt
    )
}

/// The scaling series' script: ideal DPD at n = 16 from `create_atoms random`.
pub(super) fn scaling_script(n: usize, steps: u64) -> String {
    format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\n\
         variable L equal ({n}/16.0)^(1.0/3.0)\nregion box block 0 ${{L}} 0 ${{L}} 0 ${{L}}\n\
         create_box 1 box\ncreate_atoms 1 random {n} {DATA_SEED} box\nmass 1 1.0\n\
         velocity all create 0.1 4928 mom yes dist gaussian\n\
         pair_style dpd/nonlinear 0.1 1.0 {PAIR_SEED}\npair_coeff 1 1 0.0 5.0 0.0\n\
         neighbor 0.3 bin\ntimestep 0.001\nfix 1 all nve\nthermo {steps}\nrun {steps}\n"
    )
}

/// Quote a path for an input script when it contains blanks.
pub(super) fn script_path(p: &Path) -> String {
    let s = p.display().to_string();
    if s.contains(char::is_whitespace) {
        format!("\"{s}\"")
    } else {
        s
    }
}
