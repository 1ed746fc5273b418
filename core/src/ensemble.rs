//! [`Ensemble`]: many independent runs of one kind (initial conditions, parameter sets, the
//! grids of an untimed convergence study), mapped over a slice in parallel on rayon's
//! work-stealing pool when the `parallel` feature is on (the default), one after another
//! otherwise, the results in input order either way.
//!
//! Every member is computed by the same code from the same inputs on whichever thread runs
//! it, and nothing is shared between members but read-only data, so a parallel run returns
//! the serial run's results bit for bit: the schedule changes when a member runs, never what
//! it computes.

use std::sync::atomic::{AtomicUsize, Ordering};

/// The progress callback: members finished so far, and the ensemble's size.
type Progress<'a> = dyn Fn(usize, usize) + Sync + 'a;

/// How the members of an ensemble run: in parallel on rayon's work-stealing pool (with the
/// `parallel` feature, on by default) or one after another on the calling thread, with an
/// optional progress callback. The results come back in input order either way, and equal
/// bit for bit: each member runs the same code on the same inputs, wherever it runs.
///
/// The runs of [`Problem::solve_ivp_ensemble`](crate::Problem::solve_ivp_ensemble),
/// [`Problem::solve_ivp_models`](crate::Problem::solve_ivp_models) and their
/// [`DynProblem`](crate::DynProblem) counterparts take one; [`map`](Self::map) runs any
/// closure over a slice the same way.
///
/// # Example
///
/// ```
/// use varembed::Ensemble;
/// use std::sync::atomic::{AtomicUsize, Ordering};
///
/// let finished = AtomicUsize::new(0);
/// let ensemble = Ensemble::new().with_progress(|done, total| {
///     assert!(done <= total && total == 4);
///     finished.fetch_max(done, Ordering::Relaxed);
/// });
/// let squares = ensemble.map(&[1, 2, 3, 4], |x| x * x);
/// assert_eq!(squares, [1, 4, 9, 16]); // input order
/// assert_eq!(finished.load(Ordering::Relaxed), 4);
/// assert_eq!(Ensemble::serial().map(&[1, 2, 3, 4], |x| x * x), squares);
/// ```
pub struct Ensemble<'a> {
    parallel: bool,
    progress: Option<Box<Progress<'a>>>,
}

impl Default for Ensemble<'_> {
    /// [`Ensemble::new`].
    fn default() -> Self {
        Ensemble::new()
    }
}

impl std::fmt::Debug for Ensemble<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ensemble")
            .field("parallel", &self.parallel)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl<'a> Ensemble<'a> {
    /// Members in parallel on rayon's global pool (as many threads as cores, or
    /// `RAYON_NUM_THREADS`) when the `parallel` feature is on; without it, as
    /// [`serial`](Self::serial). No progress callback.
    ///
    /// ```
    /// assert_eq!(varembed::Ensemble::new().is_parallel(), cfg!(feature = "parallel"));
    /// ```
    pub fn new() -> Self {
        Ensemble {
            parallel: cfg!(feature = "parallel"),
            progress: None,
        }
    }

    /// Members one after another on the calling thread, in input order: the reference a
    /// parallel run equals, and the choice where the members are too small to be worth a
    /// thread or where their wall times are measured.
    ///
    /// ```
    /// assert!(!varembed::Ensemble::serial().is_parallel());
    /// ```
    pub fn serial() -> Self {
        Ensemble {
            parallel: false,
            progress: None,
        }
    }

    /// Calls `progress(done, total)` each time a member finishes, `done` the number finished
    /// so far (each of `1..=total` once) and `total` the ensemble's size. It is called on the
    /// thread that ran the member, so calls may overlap and arrive out of order (`done = 3`
    /// before `done = 2`); keep it short, and take the largest `done` seen, as a progress bar
    /// does.
    ///
    /// ```
    /// use std::sync::Mutex;
    /// let seen = Mutex::new(Vec::new());
    /// varembed::Ensemble::serial()
    ///     .with_progress(|done, total| seen.lock().unwrap().push((done, total)))
    ///     .map(&[0.5, 1.5], |x: &f64| x.sqrt());
    /// assert_eq!(*seen.lock().unwrap(), [(1, 2), (2, 2)]);
    /// ```
    pub fn with_progress(mut self, progress: impl Fn(usize, usize) + Sync + 'a) -> Self {
        self.progress = Some(Box::new(progress));
        self
    }

    /// Whether the members run in parallel.
    ///
    /// ```
    /// assert!(!varembed::Ensemble::serial().is_parallel());
    /// ```
    pub fn is_parallel(&self) -> bool {
        self.parallel
    }

    /// `f` on every member, the results in input order. In parallel, `f` runs on rayon's
    /// worker threads (hence `Sync`); a member whose `f` panics propagates the panic to the
    /// caller once the others have stopped.
    ///
    /// ```
    /// let lengths = [0.5, 1.0, 2.0];
    /// // The small-angle period of a pendulum per length, computed in parallel.
    /// let periods = varembed::Ensemble::new().map(&lengths, |l: &f64| 2.0 * std::f64::consts::PI * (l / 9.81).sqrt());
    /// assert!(periods[0] < periods[1] && periods[1] < periods[2]);
    /// ```
    pub fn map<'m, T, R>(&self, members: &'m [T], f: impl Fn(&'m T) -> R + Sync) -> Vec<R>
    where
        T: Sync,
        R: Send,
    {
        let total = members.len();
        let done = AtomicUsize::new(0);
        let run = |member: &'m T| {
            let result = f(member);
            if let Some(progress) = &self.progress {
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            }
            result
        };
        if self.parallel {
            parallel_map(members, run)
        } else {
            members.iter().map(run).collect()
        }
    }
}

/// `f` over `members` on rayon's pool; an indexed collect keeps the input order.
#[cfg(feature = "parallel")]
fn parallel_map<'m, T: Sync, R: Send>(members: &'m [T], f: impl Fn(&'m T) -> R + Sync) -> Vec<R> {
    use rayon::prelude::*;
    // A reference to a `Sync` closure is `Send` too, which rayon's map asks of its operation.
    let f = &f;
    members.par_iter().map(f).collect()
}

/// Without the `parallel` feature no ensemble is parallel; kept so that [`Ensemble::map`]
/// reads the same under both.
#[cfg(not(feature = "parallel"))]
fn parallel_map<'m, T: Sync, R: Send>(members: &'m [T], f: impl Fn(&'m T) -> R + Sync) -> Vec<R> {
    members.iter().map(f).collect()
}

/// `f` over `members` as [`Ensemble::map`] does, the costliest first: `cost` orders the
/// members for the schedule (rayon hands out the front of the slice first, so a long member
/// started last would idle the other threads at the end), the results come back in input
/// order.
pub(crate) fn map_costliest_first<T, R>(
    ensemble: &Ensemble<'_>,
    members: &[T],
    cost: impl Fn(&T) -> usize,
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R>
where
    T: Sync,
    R: Send,
{
    let mut order: Vec<usize> = (0..members.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(cost(&members[i])));
    let results = ensemble.map(&order, |&i| (i, f(&members[i])));
    let mut slots: Vec<Option<R>> = std::iter::repeat_with(|| None)
        .take(members.len())
        .collect();
    for (i, r) in results {
        slots[i] = Some(r);
    }
    slots.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn results_keep_input_order_and_progress_counts_every_member() {
        let members: Vec<u64> = (0..200).collect();
        let calls = Mutex::new(Vec::new());
        let ensemble = Ensemble::new().with_progress(|done, total| {
            calls.lock().unwrap().push((done, total));
        });
        let out = ensemble.map(&members, |&k| k * k + 1);
        drop(ensemble);
        assert_eq!(out, members.iter().map(|k| k * k + 1).collect::<Vec<_>>());
        let mut calls = calls.into_inner().unwrap();
        calls.sort_unstable();
        assert_eq!(calls, (1..=200).map(|d| (d, 200)).collect::<Vec<_>>());
    }

    #[test]
    fn costliest_first_returns_input_order() {
        let members = [3usize, 9, 1, 4, 4, 0];
        for ensemble in [Ensemble::new(), Ensemble::serial()] {
            let out = map_costliest_first(&ensemble, &members, |&c| c, |&c| c * 10);
            assert_eq!(out, [30, 90, 10, 40, 40, 0]);
        }
    }

    #[test]
    fn an_empty_ensemble_is_empty() {
        let none: [f64; 0] = [];
        assert!(Ensemble::new().map(&none, |x| *x).is_empty());
    }
}
