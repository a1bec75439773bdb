//! What the averaging fixes share: LAMMPS's Nevery/Nrepeat/Nfreq schedule and the `ave
//! one|running|window M` average over the per-Nfreq results.

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Ave {
    One,
    Running,
    Window(usize),
}

/// LAMMPS's `ave one|running|window M` over the per-Nfreq results, with the same add and
/// subtract operations (so the same round-off).
#[derive(Debug)]
pub(super) struct Averager {
    pub(super) ave: Ave,
    pub(super) total: Vec<f64>,
    list: Vec<Vec<f64>>,
    pub(super) iwindow: usize,
    pub(super) full: bool,
    pub(super) norm: usize,
}

impl Averager {
    pub(super) fn new(ave: Ave) -> Averager {
        Averager {
            ave,
            total: Vec::new(),
            list: Vec::new(),
            iwindow: 0,
            full: false,
            norm: 0,
        }
    }

    pub(super) fn push(&mut self, x: &[f64]) {
        if self.total.len() != x.len() {
            self.total = vec![0.0; x.len()];
            self.list.clear();
            self.iwindow = 0;
            self.full = false;
            self.norm = 0;
        }
        match self.ave {
            Ave::One => {
                self.total.copy_from_slice(x);
                self.norm = 1;
            }
            Ave::Running => {
                for (t, v) in self.total.iter_mut().zip(x) {
                    *t += v;
                }
                self.norm += 1;
            }
            Ave::Window(n) => {
                // One slot per sample until the window is full (the old value of a slot is only
                // read once it is): memory follows the samples taken, not M (`ave window
                // 100000000000000` aborted in the allocator).
                if self.list.len() == self.iwindow {
                    self.list.push(vec![0.0; x.len()]);
                }
                let slot = &mut self.list[self.iwindow];
                for ((t, v), old) in self.total.iter_mut().zip(x).zip(slot.iter_mut()) {
                    *t += v;
                    if self.full {
                        *t -= *old;
                    }
                    *old = *v;
                }
                self.iwindow += 1;
                if self.iwindow == n {
                    self.iwindow = 0;
                    self.full = true;
                }
                self.norm = if self.full { n } else { self.iwindow };
            }
        }
    }
}

/// LAMMPS's Nevery/Nrepeat/Nfreq schedule (`nextvalid`, `end_of_step`).
#[derive(Clone, Debug)]
pub(super) struct Schedule {
    pub(super) nevery: i64,
    pub(super) nrepeat: i64,
    pub(super) nfreq: i64,
    pub(super) start: i64,
    pub(super) nvalid: i64,
    pub(super) nvalid_last: i64,
    pub(super) irepeat: i64,
}

impl Schedule {
    pub(super) fn next_valid(&self, step: i64) -> i64 {
        let mut nv = (step / self.nfreq) * self.nfreq + self.nfreq;
        while nv < self.start {
            nv += self.nfreq;
        }
        if nv - self.nfreq == step && self.nrepeat == 1 {
            nv = step;
        } else {
            nv -= (self.nrepeat - 1) * self.nevery;
        }
        if nv < step {
            nv += self.nfreq;
        }
        nv
    }

    /// At the start of every run (LAMMPS `init`).
    pub(super) fn init(&mut self, step: i64) {
        if self.nvalid < step {
            self.irepeat = 0;
            self.nvalid = self.next_valid(step);
        }
    }

    pub(super) fn due(&self, step: i64, style: &str) -> Result<bool, String> {
        if step < self.nvalid_last || step > self.nvalid {
            return Err(format!(
                "invalid timestep reset for fix {style} (step {step}, next sample {})",
                self.nvalid
            ));
        }
        Ok(step == self.nvalid)
    }

    /// Record a sample at `step`; true when it completes an Nfreq epoch.
    pub(super) fn sampled(&mut self, step: i64) -> bool {
        self.nvalid_last = self.nvalid;
        self.irepeat += 1;
        if self.irepeat < self.nrepeat {
            self.nvalid += self.nevery;
            return false;
        }
        self.irepeat = 0;
        self.nvalid = step + self.nfreq - (self.nrepeat - 1) * self.nevery;
        true
    }
}
