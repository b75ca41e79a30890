//! # Why B-spline MPM stops converging: one convention at a time (issue #38)
//!
//! The runs behind the table `mls-convergence-study`: hompm's BSMPM
//! (quadratic B-splines, direct mapping, lumped mass; MLS paper Eqs. 18–37
//! with MUSL, FLIP, the positions of Eq. 30, the body force of Eq. 24 from
//! the particles and open knots) on the aligned vibration (MLS paper
//! Eqs. 38–42: E = 1e7 Pa, A = 0.1 m, 9 PPC, Δt = 1e-5 s), with one
//! convention of another code switched at a time (`mpm::conventions`,
//! docs/conventions.md "Conventions of other codes"), and a Taichi-style
//! MLS-MPM step (APIC, the affine gradient, padded knots and USL; Hu et
//! al. 2018) with one switched back at a time, and the total-Lagrangian
//! reference on the same splines, which never crosses cells
//! ([`combinations`]).
//!
//! Each run records the RMS errors of Eq. (43) after one period of
//! sin(cπt/L), at a time where u is at its peak and at its end, its mapping errors of mass and momentum, its
//! wall time and, if it stops (a step's own refusal or the stability
//! monitor of `mpm2d::monitor`, as `hompm run` stops), the step and the
//! cause ([`run_combination`]). Each combination also gets the largest
//! stable Δt on one grid, by a scan in steps of √2 and a bisection
//! ([`largest_stable_dt`]). Orders between successive sizes are
//! log(e_coarse/e_fine)/log(cells_fine/cells_coarse) ([`pair_order`]).
//!
//! Every run is independent and single-threaded; one worker per rayon
//! thread takes the next job of a longest-first list, and the results are
//! put back in input order, so the numbers do not depend on the scheduling
//! (the wall times do). A stability scan whose first trial is one of the
//! convergence runs (the default run: 16 cells, Δt = 1e-5 s, 2000 steps)
//! takes that run's stop instead of repeating it, the same bits.
//!
//! The combinations themselves are in the child module `combinations`
//! (re-exported here).
//!
//! Items: [`Combination`], [`combinations()`], [`BSMPM`], [`TAICHI`], [`REFERENCE`],
//! [`StabilityOptions`], [`ConventionStudyOptions`], [`Stop`],
//! [`ConventionRun`], [`run_combination`], [`StabilityLimit`],
//! [`largest_stable_dt`], [`ConventionStudy`], [`convention_study`],
//! [`pair_order`].

mod combinations;
pub use combinations::{combinations, Combination, BSMPM, REFERENCE, TAICHI};

use crate::error::Result;
use crate::mpm2d::monitor::stability_monitor;
use crate::mpm2d::Conservation2d;
use crate::scenes::aligned_vibration::{parameters, AlignedErrors, AlignedVibration};
use rayon::prelude::*;
use serde::Serialize;

/// The stability part: the largest stable Δt of every combination on one
/// grid, run to a given time (as the 1D map's Courant scan, thesis
/// Eq. 3.5, [`super::critical_courant`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StabilityOptions {
    /// Cells per direction.
    pub cells: usize,
    /// Each trial runs to this time \[s\].
    pub end_time: f64,
    /// The scan starts here \[s\] and multiplies Δt by √2 up to the first
    /// unstable value.
    pub smallest_dt: f64,
    /// The scan gives up (and reports no unstable Δt) above this \[s\].
    pub largest_dt: f64,
    /// Geometric bisections between the last stable and the first
    /// unstable Δt (each halves the ratio's logarithm).
    pub bisections: usize,
}

/// What to run: the MLS paper's aligned vibration (§4: 8–64 cells, 9 PPC,
/// Δt = 1e-5 s, T = 0.2 s) or less of it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConventionStudyOptions {
    /// Cells per direction of the convergence runs.
    pub sizes: Vec<usize>,
    /// Particles per side of a cell (3: the MLS paper's 9 PPC).
    pub per_side: usize,
    /// Time step \[s\].
    pub dt: f64,
    /// The errors are also recorded after this many steps (one period).
    pub early_steps: usize,
    /// And after this many (a time where u is at its peak and v is 0;
    /// `None`: not recorded).
    pub peak_steps: Option<usize>,
    /// Steps per run.
    pub steps: usize,
    /// The stability part, if run.
    pub stability: Option<StabilityOptions>,
}

impl ConventionStudyOptions {
    /// `hompm reproduce` and `hompm table`: 8 and 16 cells for one period
    /// (2000 steps), the largest stable Δt on 16 cells to one period.
    pub fn default_run() -> Self {
        Self {
            sizes: vec![8, 16],
            per_side: 3,
            dt: 1e-5,
            early_steps: 2000,
            peak_steps: None,
            steps: 2000,
            stability: Some(StabilityOptions {
                cells: 16,
                end_time: 0.02,
                smallest_dt: 1e-5,
                largest_dt: 3e-3,
                bisections: 3,
            }),
        }
    }

    /// `--full`: 8 to 64 cells to T = 0.2 s (20 000 steps; one period and
    /// t = 0.195 s, where u is at its peak, recorded on the way), the
    /// largest stable Δt on 16 cells to T.
    pub fn full_run() -> Self {
        let d = Self::default_run();
        Self {
            sizes: vec![8, 16, 32, 64],
            steps: 20_000,
            peak_steps: Some(19_500),
            stability: d.stability.map(|s| StabilityOptions { end_time: 0.2, ..s }),
            ..d
        }
    }

    /// The time of the early record \[s\].
    pub fn early_time(&self) -> f64 {
        self.early_steps as f64 * self.dt
    }

    /// The time of the peak record \[s\], if any.
    pub fn peak_time(&self) -> Option<f64> {
        self.peak_steps.map(|k| k as f64 * self.dt)
    }

    /// The time at the end of a run \[s\].
    pub fn end_time(&self) -> f64 {
        self.steps as f64 * self.dt
    }
}

/// Where and why a run stopped: a step's own refusal (MLS paper Eq. 41's
/// det F ≤ 0, a particle leaving the square) or the stability monitor's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stop {
    /// The step that failed (1-based).
    pub step: usize,
    /// Its time, step × Δt \[s\].
    pub time: f64,
    /// The error, as `hompm run` prints it.
    pub cause: String,
}

/// One run of one combination on one grid: RMS errors of MLS paper
/// Eq. (43), mapping errors, cost and stop.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConventionRun {
    /// Index into [`combinations`].
    pub combination: usize,
    /// Cells per direction.
    pub cells: usize,
    /// Particles.
    pub particles: usize,
    /// RMS errors (MLS paper Eq. 43) after the early steps, if reached.
    pub early: Option<AlignedErrors>,
    /// After the peak steps, if asked for and reached.
    pub peak: Option<AlignedErrors>,
    /// RMS errors at the end, if reached.
    pub end: Option<AlignedErrors>,
    /// Why it stopped, if it did.
    pub stop: Option<Stop>,
    /// The largest mapping errors of mass and momentum up to the end or
    /// the stop.
    pub conservation: Conservation2d,
    /// Steps completed.
    pub steps_done: usize,
    /// Wall-clock seconds of the stepping (with the one or two evaluations of the errors).
    pub seconds: f64,
}

impl ConventionRun {
    /// Wall-clock nanoseconds per particle and step.
    pub fn ns_per_particle_step(&self) -> f64 {
        1e9 * self.seconds / (self.particles * self.steps_done.max(1)) as f64
    }
}

/// Runs one combination on `cells` × `cells` quadratic B-spline cells with
/// `per_side`² particles per cell for `steps` steps of `dt`, under the
/// stability monitor as `hompm run` (MLS paper Eqs. 18–37 with the
/// combination's conventions; errors of Eq. 43 after each of `records`
/// (the early and the peak step), if given, and at the end). Errors only
/// if the run cannot start; a run that fails on the way is returned with
/// its [`Stop`].
pub fn run_combination(
    base: &AlignedVibration,
    combination: &Combination,
    cells: usize,
    per_side: usize,
    dt: f64,
    steps: usize,
    records: [Option<usize>; 2],
) -> Result<ConventionRun> {
    let scene = combination.scene(base);
    let mut sim = scene.simulation_with(
        combination.method,
        cells,
        per_side,
        1.0,
        combination.conventions,
    )?;
    let work = scene.work_bound(sim.particles.total_mass())?;
    let mut monitor = stability_monitor(&sim, work);
    let (mut early, mut peak, mut end, mut stop) = (None, None, None, None);
    let start = std::time::Instant::now();
    for k in 1..=steps {
        let recorded = sim
            .step(dt)
            .and_then(|()| monitor.check_watched(&sim))
            .and_then(|()| {
                let (at_early, at_peak) = (records[0] == Some(k), records[1] == Some(k));
                if at_early || at_peak || k == steps {
                    let e = scene.errors(&sim)?;
                    early = early.or(at_early.then_some(e));
                    peak = peak.or(at_peak.then_some(e));
                    end = (k == steps).then_some(e);
                }
                Ok(())
            });
        if let Err(e) = recorded {
            stop = Some(Stop {
                step: k,
                time: k as f64 * dt,
                cause: e.to_string(),
            });
            break;
        }
    }
    Ok(ConventionRun {
        combination: 0,
        cells,
        particles: sim.particles.len(),
        early,
        peak,
        end,
        stop,
        conservation: sim.conservation,
        steps_done: sim.steps,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The largest stable Δt of one combination on one grid
/// ([`largest_stable_dt`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityLimit {
    /// Index into [`combinations`].
    pub combination: usize,
    /// The largest Δt tried that reached the end time \[s\] (`None`: even
    /// the smallest stopped).
    pub largest_stable: Option<f64>,
    /// The smallest Δt tried that stopped \[s\] (`None`: none up to the
    /// scan's largest).
    pub smallest_unstable: Option<f64>,
    /// Where and why the run at `smallest_unstable` stopped.
    pub stop: Option<Stop>,
    /// Runs made.
    pub trials: usize,
}

/// The largest stable Δt of `combination` on `o.cells` cells: Δt =
/// smallest_dt · √2^k up to the first run that stops before `o.end_time`,
/// then `o.bisections` geometric bisections between the last stable and
/// the first unstable value (stability need not be monotone in Δt, so the
/// scan comes first, as in [`super::critical_courant`]).
pub fn largest_stable_dt(
    base: &AlignedVibration,
    combination: &Combination,
    per_side: usize,
    o: &StabilityOptions,
) -> Result<StabilityLimit> {
    scan_stable_dt(base, combination, per_side, o, None)
}

/// The steps of a stability trial of Δt `dt` to `end_time`.
fn trial_steps(end_time: f64, dt: f64) -> usize {
    ((end_time / dt) - 1e-9).ceil().max(1.0) as usize
}

/// [`largest_stable_dt`], with the stop of the first trial (Δt =
/// `o.smallest_dt`) given when a run of the study already made it (the
/// same run: same combination, cells, Δt and steps).
fn scan_stable_dt(
    base: &AlignedVibration,
    combination: &Combination,
    per_side: usize,
    o: &StabilityOptions,
    first: Option<Option<Stop>>,
) -> Result<StabilityLimit> {
    let mut trials = 0;
    let mut first = first;
    let mut trial = |dt: f64| -> Result<Option<Stop>> {
        trials += 1;
        if let Some(stop) = first.take() {
            return Ok(stop);
        }
        let steps = trial_steps(o.end_time, dt);
        let run = run_combination(base, combination, o.cells, per_side, dt, steps, [None; 2])?;
        Ok(run.stop)
    };
    let mut lo: Option<f64> = None;
    let mut hi: Option<(f64, Stop)> = None;
    let mut k = 0;
    loop {
        let dt = o.smallest_dt * 2f64.powf(0.5 * k as f64);
        if dt > o.largest_dt {
            break;
        }
        match trial(dt)? {
            None => lo = Some(dt),
            Some(s) => {
                hi = Some((dt, s));
                break;
            }
        }
        k += 1;
    }
    if let (Some(mut l), Some((mut h, mut s))) = (lo, hi.clone()) {
        for _ in 0..o.bisections {
            let mid = (l * h).sqrt();
            match trial(mid)? {
                None => l = mid,
                Some(stop) => (h, s) = (mid, stop),
            }
        }
        lo = Some(l);
        hi = Some((h, s));
    }
    let (smallest_unstable, stop) = hi.map_or((None, None), |(h, s)| (Some(h), Some(s)));
    Ok(StabilityLimit {
        combination: 0,
        largest_stable: lo,
        smallest_unstable,
        stop,
        trials,
    })
}

/// Everything the table shows: the runs of [`run_combination`] and the
/// limits of [`largest_stable_dt`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConventionStudy {
    /// The options run.
    pub options: ConventionStudyOptions,
    /// The combinations, in the order of [`combinations`].
    pub combinations: Vec<Combination>,
    /// Every run: combination by combination, sizes in order.
    pub runs: Vec<ConventionRun>,
    /// The stability limits, one per combination (empty without the
    /// stability part).
    pub stability: Vec<StabilityLimit>,
}

impl ConventionStudy {
    /// The run of combination `label` on `cells` cells.
    pub fn run(&self, label: &str, cells: usize) -> Option<&ConventionRun> {
        let c = self.combinations.iter().position(|c| c.label == label)?;
        self.runs
            .iter()
            .find(|r| r.combination == c && r.cells == cells)
    }
}

enum Job {
    Run {
        combination: usize,
        cells: usize,
    },
    Stability {
        combination: usize,
        options: StabilityOptions,
    },
}

enum Done {
    Run(ConventionRun),
    Stability(StabilityLimit),
}

/// Runs the study (every job in parallel, longest first; results in input
/// order) on the MLS paper's parameters (`mls-paper-e1e7`).
pub fn convention_study(o: &ConventionStudyOptions) -> Result<ConventionStudy> {
    let base = parameters("mls-paper-e1e7")?;
    let all = combinations();
    let mut jobs = Vec::new();
    for combination in 0..all.len() {
        for &cells in &o.sizes {
            jobs.push(Job::Run { combination, cells });
        }
    }
    if let Some(options) = o.stability {
        jobs.extend((0..all.len()).map(|combination| Job::Stability {
            combination,
            options,
        }));
    }
    let per_cell = (o.per_side * o.per_side) as f64;
    let cost = |j: &Job| match j {
        Job::Run { cells, .. } => per_cell * (cells * cells) as f64 * o.steps as f64,
        // The scan's geometric sum: about 3.4 runs at the smallest Δt.
        Job::Stability { options: s, .. } => {
            3.4 * per_cell * (s.cells * s.cells) as f64 * s.end_time / s.smallest_dt
        }
    };
    // Work items: one job, or a run and the stability scan whose first
    // trial it is (same combination, cells, Δt and steps, and no error
    // evaluation before its end that could stop it earlier), run in that
    // order so that the scan takes the run's stop instead of repeating it.
    let mut work: Vec<Vec<usize>> = Vec::new();
    let mut paired = vec![false; jobs.len()];
    for (i, j) in jobs.iter().enumerate() {
        let Job::Stability {
            combination,
            options: s,
        } = j
        else {
            continue;
        };
        let only_at_end = [Some(o.early_steps), o.peak_steps]
            .iter()
            .all(|r| r.is_none_or(|k| k >= o.steps));
        let same_run = s.smallest_dt.to_bits() == o.dt.to_bits()
            && trial_steps(s.end_time, s.smallest_dt) == o.steps
            && only_at_end;
        let run = jobs.iter().position(|r| {
            matches!(r, Job::Run { combination: c, cells } if c == combination && *cells == s.cells)
        });
        if let (true, Some(r)) = (same_run, run) {
            paired[r] = true;
            paired[i] = true;
            work.push(vec![r, i]);
        }
    }
    work.extend((0..jobs.len()).filter(|&i| !paired[i]).map(|i| vec![i]));
    let work_cost = |w: &Vec<usize>| -> f64 {
        let total: f64 = w.iter().map(|&i| cost(&jobs[i])).sum();
        // A paired scan does not repeat its first trial.
        total - if w.len() > 1 { cost(&jobs[w[0]]) } else { 0.0 }
    };
    let mut order: Vec<usize> = (0..work.len()).collect();
    order.sort_by(|&a, &b| work_cost(&work[b]).total_cmp(&work_cost(&work[a])));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done: std::sync::Mutex<Vec<(usize, Result<Done>)>> = std::sync::Mutex::new(Vec::new());
    (0..rayon::current_num_threads().max(1))
        .into_par_iter()
        .for_each(|_| loop {
            let k = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let Some(&w) = order.get(k) else { break };
            // The stop of the item's run, for the scan that follows it.
            let mut first: Option<Option<Stop>> = None;
            for &i in &work[w] {
                let result = match jobs[i] {
                    Job::Run { combination, cells } => run_combination(
                        &base,
                        &all[combination],
                        cells,
                        o.per_side,
                        o.dt,
                        o.steps,
                        [Some(o.early_steps), o.peak_steps],
                    )
                    .map(|r| {
                        first = Some(r.stop.clone());
                        Done::Run(ConventionRun { combination, ..r })
                    }),
                    Job::Stability {
                        combination,
                        options,
                    } => {
                        scan_stable_dt(&base, &all[combination], o.per_side, &options, first.take())
                            .map(|l| Done::Stability(StabilityLimit { combination, ..l }))
                    }
                };
                if let Ok(mut d) = done.lock() {
                    d.push((i, result));
                }
            }
        });
    let mut results = done.into_inner().unwrap_or_default();
    results.sort_by_key(|(i, _)| *i);
    let (mut runs, mut stability) = (Vec::new(), Vec::new());
    for (_, r) in results {
        match r? {
            Done::Run(r) => runs.push(r),
            Done::Stability(s) => stability.push(s),
        }
    }
    Ok(ConventionStudy {
        options: o.clone(),
        combinations: all,
        runs,
        stability,
    })
}

/// The order between two sizes, log(e_coarse/e_fine)/log(n_fine/n_coarse)
/// for (cells, error) pairs (2 for second order; the pairwise orders of
/// `mls-aligned`'s claims, MLS paper Figs. 2–4).
pub fn pair_order(coarse: (usize, f64), fine: (usize, f64)) -> f64 {
    (coarse.1 / fine.1).ln() / (fine.0 as f64 / coarse.0 as f64).ln()
}
