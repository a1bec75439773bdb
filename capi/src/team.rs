//! The threads of a threaded walk ([`crate::compute`]'s `Workers`): a rayon pool of this
//! library's own, or the host's threads through a launcher it hands over
//! ([`crate::dpdnl_pair_launcher`]; the LAMMPS styles pass an OpenMP parallel region, so the
//! force pass runs on LAMMPS's own OpenMP threads instead of competing with them for the
//! cores). Either way every item of a phase is processed exactly once, by one thread, and
//! which thread does not change any result: the bits stay those of one thread.

use std::any::Any;
use std::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use rayon::prelude::*;

/// A team member's work: `body(ctx, thread)`, called once by each thread of a launch (never
/// null when this library calls a launcher).
pub type DpdnlTeamBody = Option<unsafe extern "C" fn(ctx: *mut c_void, thread: i32)>;

/// A host's parallel launcher: calls `body(ctx, t)` once on each of `nthreads` threads
/// (t = 0..nthreads, the calling thread may be one of them) and returns when every call has
/// returned, e.g. `#pragma omp parallel num_threads(nthreads) body(ctx, omp_get_thread_num());`.
/// Fewer threads than asked are allowed (the work is shared dynamically; the caller finishes
/// what is left); `body` never unwinds into the launcher. Null: none.
pub type DpdnlLaunch =
    Option<unsafe extern "C" fn(body: DpdnlTeamBody, ctx: *mut c_void, nthreads: i32)>;

/// A launcher that is there.
type Launch = unsafe extern "C" fn(body: DpdnlTeamBody, ctx: *mut c_void, nthreads: i32);

/// Who runs a threaded walk's phases.
pub(crate) enum Team {
    /// This library's pool (shared by the handles with the same count).
    Pool(Arc<rayon::ThreadPool>),
    /// The host's threads, through its launcher.
    Host { launch: Launch, threads: usize },
}

impl Team {
    /// `threads` (≥ 2) threads: the host's when it gave a launcher, else a pool created once per
    /// count.
    pub(crate) fn new(threads: usize, launch: DpdnlLaunch) -> Result<Team, String> {
        if let Some(launch) = launch {
            return Ok(Team::Host { launch, threads });
        }
        static POOLS: Mutex<Vec<Arc<rayon::ThreadPool>>> = Mutex::new(Vec::new());
        let mut pools = POOLS.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(p) = pools.iter().find(|p| p.current_num_threads() == threads) {
            return Ok(Team::Pool(p.clone()));
        }
        let p = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|k| format!("dpdnl-pair-{k}"))
            .build()
            .map_err(|e| format!("cannot start {threads} threads: {e}"))?;
        let p = Arc::new(p);
        pools.push(p.clone());
        Ok(Team::Pool(p))
    }

    /// The number of threads.
    pub(crate) fn threads(&self) -> usize {
        match self {
            Team::Pool(p) => p.current_num_threads(),
            Team::Host { threads, .. } => *threads,
        }
    }

    /// Whether this team runs on the host's launcher.
    pub(crate) fn is_host(&self) -> bool {
        matches!(self, Team::Host { .. })
    }

    /// Runs `f`, inside which [`Team::for_each`] is called: in the pool (one entry for all the
    /// phases of a call), or on the calling thread for the host's team.
    pub(crate) fn scope<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match self {
            Team::Pool(p) => p.install(f),
            Team::Host { .. } => f(),
        }
    }

    /// `f(k, &mut items[k])` for every k, in parallel, each item once; returns when all are done.
    /// A panic in `f` is raised again on the calling thread. Called inside [`Team::scope`]
    /// (outside it a pool's items would run on rayon's global pool).
    pub(crate) fn for_each<T: Send>(&self, items: &mut [T], f: &(dyn Fn(usize, &mut T) + Sync)) {
        match self {
            Team::Pool(_) => items.par_iter_mut().enumerate().for_each(|(k, t)| f(k, t)),
            Team::Host { launch, threads } => host_for_each(*launch, *threads, items, f),
        }
    }
}

/// [`Team::for_each`] on the host's threads: each thread takes the next item until none is left.
fn host_for_each<T: Send>(
    launch: Launch,
    threads: usize,
    items: &mut [T],
    f: &(dyn Fn(usize, &mut T) + Sync),
) {
    let slots: Vec<Mutex<&mut T>> = items.iter_mut().map(Mutex::new).collect();
    let next = AtomicUsize::new(0);
    let panic: Mutex<Option<Box<dyn Any + Send>>> = Mutex::new(None);
    let work = || {
        let r = catch_unwind(AssertUnwindSafe(|| {
            loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(slot) = slots.get(k) else { break };
                let mut item = slot.lock().unwrap_or_else(PoisonError::into_inner);
                f(k, &mut item);
            }
        }));
        if let Err(p) = r {
            // The other threads stop at their next item.
            next.store(slots.len(), Ordering::Relaxed);
            panic
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .get_or_insert(p);
        }
    };
    let body: &(dyn Fn() + Sync) = &work;
    let ctx = &body as *const &(dyn Fn() + Sync) as *mut c_void;
    // SAFETY: the launcher calls `member` with `ctx` only until it returns (its contract), and
    // `body` lives until then; `member` never unwinds (the work catches panics).
    unsafe { launch(Some(member), ctx, threads as i32) };
    // Whatever a launcher that ran fewer threads (or none) left.
    work();
    if let Some(p) = panic.into_inner().unwrap_or_else(PoisonError::into_inner) {
        resume_unwind(p);
    }
}

/// The team body ([`DpdnlTeamBody`]) of [`host_for_each`].
unsafe extern "C" fn member(ctx: *mut c_void, _thread: i32) {
    // SAFETY: `ctx` is the `&&(dyn Fn() + Sync)` of `host_for_each`, alive during the launch.
    let body = unsafe { &*(ctx as *const &(dyn Fn() + Sync)) };
    body();
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicBool;

    /// A launcher on scoped threads, as an OpenMP region would do it.
    unsafe extern "C" fn scoped(body: DpdnlTeamBody, ctx: *mut c_void, n: i32) {
        let (Some(body), ctx) = (body, ctx as usize) else {
            return;
        };
        std::thread::scope(|s| {
            for t in 0..n {
                // SAFETY: the body's contract, forwarded.
                s.spawn(move || unsafe { body(ctx as *mut c_void, t) });
            }
        });
    }

    /// A launcher that runs nothing: the caller must do all the work.
    unsafe extern "C" fn idle(_: DpdnlTeamBody, _: *mut c_void, _: i32) {}

    #[test]
    fn every_item_is_processed_once_by_any_launcher() {
        for launch in [scoped as Launch, idle] {
            let team = Team::new(3, Some(launch)).expect("host team");
            assert!(team.is_host() && team.threads() == 3);
            let mut items = vec![0_u32; 1000];
            team.scope(|| team.for_each(&mut items, &|k, x| *x += k as u32 + 1));
            assert!(items.iter().enumerate().all(|(k, &x)| x == k as u32 + 1));
        }
        let pool = Team::new(2, None).expect("pool");
        assert!(!pool.is_host() && pool.threads() == 2);
        let mut items = vec![0_u32; 100];
        pool.scope(|| pool.for_each(&mut items, &|k, x| *x += k as u32 + 1));
        assert!(items.iter().enumerate().all(|(k, &x)| x == k as u32 + 1));
    }

    #[test]
    fn a_panic_on_a_host_thread_reaches_the_caller() {
        let team = Team::new(2, Some(scoped)).expect("host team");
        let after = AtomicBool::new(false);
        let mut items = vec![0_u8; 64];
        let r = catch_unwind(AssertUnwindSafe(|| {
            team.for_each(&mut items, &|k, _| {
                if k == 5 {
                    panic!("item five");
                }
            });
            after.store(true, Ordering::Relaxed);
        }));
        let msg = r.expect_err("the panic is raised again");
        assert_eq!(msg.downcast_ref::<&str>(), Some(&"item five"));
        assert!(!after.load(Ordering::Relaxed));
    }
}
