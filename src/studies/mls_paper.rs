//! # The MLS paper's study: convergence of MPM, BSMPM and BSMPM with MLS
//!
//! MLS paper Figs. 2–4: RMS errors (Eq. 43) of displacement, velocity and
//! stress at T on 8, 16, 32 and 64 cells per direction, 9 particles per
//! cell, for the three methods on the aligned vibration. Beyond the paper:
//! the errors as functions of time, the sensitivity of MLS to the number of
//! particles per cell (4, 9, 16; the paper's conclusion), the mapping errors
//! of mass and momentum (as TLS paper Table 3 does in 1D), the cost per
//! particle-step, the other reading of E, and hompm's diagnostic variant
//! with MLS in phase 1 only; and hompm's BSMPM with conservative Taylor
//! least squares in place of MLS (TLS paper §5 in 2D, issue #27), on the
//! same sizes and in the PPC study.
//!
//! Every run is independent and single-threaded; one worker per rayon
//! thread takes the next run of a longest-first list. The results are put
//! back in input order, so the numbers do not depend on the scheduling (the
//! wall times do).
//!
//! Items: [`AlignedStudyOptions`], [`RunOutcome`], [`AlignedStudy`],
//! [`aligned_study`], [`METHODS`], [`TLS_METHOD`], [`EARLY_TIME`], [`PAPER_PARAMETERS`],
//! [`PAPER_PARTICLES_PER_SIDE`].

use crate::error::Result;
use crate::mpm2d::{Conservation2d, Mapping2d};
use crate::scenes::aligned_vibration::{
    parameters, AlignedErrors, AlignedMethod, AlignedRun, AlignedVibration,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The time of the early rows and chart points: one period of sin(cπt/L)
/// for E = 1e7 Pa.
pub const EARLY_TIME: f64 = 0.02;

/// The parameter set of the paper's study (E = 1e7 Pa).
pub const PAPER_PARAMETERS: &str = "mls-paper-e1e7";
/// Particles per side of a cell in the paper's study: 3 × 3 = 9 PPC.
pub const PAPER_PARTICLES_PER_SIDE: usize = 3;

/// BSMPM with 2D TLS in place of MLS (not in the paper).
pub const TLS_METHOD: AlignedMethod = AlignedMethod::bsmpm_with(2, Mapping2d::Tls);

/// The three methods of the paper's figures (quadratic B-splines).
pub const METHODS: [AlignedMethod; 3] = [
    AlignedMethod::Mpm,
    AlignedMethod::bsmpm(2),
    AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
];

/// What to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AlignedStudyOptions {
    /// Cells per direction of the convergence study.
    pub sizes: Vec<usize>,
    /// Steps per run (T/Δt = 20 000 for the paper).
    pub steps: usize,
    /// Errors are recorded every this many steps.
    pub record_every: usize,
    /// Particles per side of a cell for the PPC study (empty: no study).
    pub ppc_per_side: Vec<usize>,
    /// Cells per direction of the PPC study.
    pub ppc_cells: usize,
    /// Sizes run with the other reading of E (empty: none).
    pub other_young_sizes: Vec<usize>,
    /// Sizes run with MLS in phase 1 only (empty: none).
    pub phase1_sizes: Vec<usize>,
    /// Sizes run with the total-Lagrangian reference (no grid crossing).
    pub reference_sizes: Vec<usize>,
}

impl AlignedStudyOptions {
    /// `hompm reproduce`: 8, 16 and 32 cells, the paper's T, and the
    /// diagnostic variant on the same sizes.
    pub fn default_run() -> Self {
        Self {
            sizes: vec![8, 16, 32],
            steps: 20_000,
            record_every: 500,
            ppc_per_side: Vec::new(),
            ppc_cells: 16,
            other_young_sizes: Vec::new(),
            phase1_sizes: vec![8, 16],
            reference_sizes: vec![8, 16, 32],
        }
    }

    /// `hompm reproduce --full`: adds 64 cells, the PPC study at 16 cells and
    /// E = 1e8 Pa on 8–32 cells.
    pub fn full_run() -> Self {
        Self {
            sizes: vec![8, 16, 32, 64],
            ppc_per_side: vec![2, 3, 4],
            other_young_sizes: vec![8, 16, 32],
            reference_sizes: vec![8, 16, 32, 64],
            ..Self::default_run()
        }
    }

    /// `--quick`: 4 and 8 cells for 400 steps (a smoke test of the pipeline).
    pub fn quick_run() -> Self {
        Self {
            sizes: vec![4, 8],
            steps: 400,
            record_every: 100,
            ppc_per_side: vec![2, 3],
            ppc_cells: 4,
            other_young_sizes: Vec::new(),
            phase1_sizes: vec![4],
            reference_sizes: vec![4, 8],
        }
    }
}

/// One run: its parameters and either its result or why it stopped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunOutcome {
    /// Parameter set.
    pub parameter_set: String,
    /// Method.
    pub method: AlignedMethod,
    /// Cells per direction.
    pub cells: usize,
    /// Particles per cell.
    pub ppc: usize,
    /// The run, if it reached T.
    pub run: Option<AlignedRun>,
    /// The error that stopped it, if any.
    pub failure: Option<String>,
    /// The errors recorded up to T or up to the stop (t = 0 first).
    pub history: Vec<AlignedErrors>,
    /// For a run that stopped: its largest mapping errors up to and
    /// including the step that failed.
    #[serde(default)]
    pub conservation_until_stop: Option<Conservation2d>,
}

/// Everything the table and the charts show.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AlignedStudy {
    /// The options run.
    pub options: AlignedStudyOptions,
    /// The paper's study (E = 1e7 Pa): every method on every size, 9 PPC.
    pub convergence: Vec<RunOutcome>,
    /// BSMPM, BSMPM with MLS and BSMPM with TLS at 4, 9, 16 PPC.
    pub ppc: Vec<RunOutcome>,
    /// The three methods with E = 1e8 Pa.
    pub other_young: Vec<RunOutcome>,
    /// MLS in phase 1 only.
    pub phase1: Vec<RunOutcome>,
    /// The total-Lagrangian reference (quadratic B-splines, no grid
    /// crossing): whether the manufactured solution is still followed at T.
    pub reference: Vec<RunOutcome>,
    /// BSMPM with 2D TLS ([`TLS_METHOD`]) on the convergence sizes, 9 PPC.
    #[serde(default)]
    pub tls: Vec<RunOutcome>,
}

impl AlignedStudy {
    /// The convergence run of `method` on `cells` cells, if it reached T.
    pub fn run(&self, method: AlignedMethod, cells: usize) -> Option<&AlignedRun> {
        self.outcome(method, cells).and_then(|o| o.run.as_ref())
    }

    /// The convergence outcome of `method` on `cells` cells.
    pub fn outcome(&self, method: AlignedMethod, cells: usize) -> Option<&RunOutcome> {
        self.convergence
            .iter()
            .find(|o| o.method == method && o.cells == cells)
    }
}

struct Job {
    set: &'static str,
    method: AlignedMethod,
    cells: usize,
    per_side: usize,
    group: usize,
}

fn outcome(job: &Job, scene: &AlignedVibration, o: &AlignedStudyOptions) -> RunOutcome {
    let result =
        scene.run_until_stopped(job.method, job.cells, job.per_side, o.steps, o.record_every);
    let mut conservation_until_stop = None;
    let (run, failure) = match result {
        Ok((run, None)) => (Some(run), None),
        Ok((run, Some(e))) => {
            conservation_until_stop = Some(run.conservation);
            (None, Some((run.history, e.to_string())))
        }
        Err(e) => (None, Some((Vec::new(), e.to_string()))),
    };
    let (history, failure) = match failure {
        Some((h, f)) => (h, Some(f)),
        None => (
            run.as_ref().map(|r| r.history.clone()).unwrap_or_default(),
            None,
        ),
    };
    RunOutcome {
        parameter_set: job.set.into(),
        method: job.method,
        cells: job.cells,
        ppc: job.per_side * job.per_side,
        failure,
        run,
        history,
        conservation_until_stop,
    }
}

fn jobs(o: &AlignedStudyOptions) -> Vec<Job> {
    let mut jobs = Vec::new();
    let mut add = |set, methods: &[AlignedMethod], sizes: &[usize], per_side: &[usize], group| {
        for &cells in sizes {
            for &method in methods {
                for &ps in per_side {
                    jobs.push(Job {
                        set,
                        method,
                        cells,
                        per_side: ps,
                        group,
                    });
                }
            }
        }
    };
    let paper = [PAPER_PARTICLES_PER_SIDE];
    add(PAPER_PARAMETERS, &METHODS, &o.sizes, &paper, 0);
    add(
        PAPER_PARAMETERS,
        &[METHODS[1], METHODS[2], TLS_METHOD],
        &[o.ppc_cells],
        &o.ppc_per_side,
        1,
    );
    add("mls-paper-e1e8", &METHODS, &o.other_young_sizes, &paper, 2);
    add(
        PAPER_PARAMETERS,
        &[AlignedMethod::bsmpm_with(2, Mapping2d::MlsPhase1)],
        &o.phase1_sizes,
        &paper,
        3,
    );
    add(
        PAPER_PARAMETERS,
        &[AlignedMethod::TotalLagrangian { degree: 2 }],
        &o.reference_sizes,
        &paper,
        4,
    );
    add(PAPER_PARAMETERS, &[TLS_METHOD], &o.sizes, &paper, 5);
    jobs
}

/// Runs the study: all jobs in parallel (longest first), results in input
/// order.
pub fn aligned_study(o: &AlignedStudyOptions) -> Result<AlignedStudy> {
    let scenes = [parameters(PAPER_PARAMETERS)?, parameters("mls-paper-e1e8")?];
    let jobs = jobs(o);
    let cost = |j: &Job| {
        let per = match j.method {
            AlignedMethod::Mpm => 1.0,
            AlignedMethod::Bsmpm {
                mapping: Mapping2d::Direct,
                ..
            } => 2.0,
            _ => 8.0,
        };
        per * (j.cells * j.cells * j.per_side * j.per_side) as f64
    };
    // Longest first, greedily: every worker takes the next job of the
    // sorted list when it is free (rayon's splitting of a list can leave
    // a core idle behind one long run).
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done: std::sync::Mutex<Vec<(usize, RunOutcome)>> = std::sync::Mutex::new(Vec::new());
    (0..rayon::current_num_threads().max(1))
        .into_par_iter()
        .for_each(|_| loop {
            let k = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let Some(&i) = order.get(k) else { break };
            let j = &jobs[i];
            let scene = if j.set == "mls-paper-e1e8" {
                &scenes[1]
            } else {
                &scenes[0]
            };
            let result = outcome(j, scene, o);
            if let Ok(mut d) = done.lock() {
                d.push((i, result));
            }
        });
    let mut results = done.into_inner().unwrap_or_default();
    results.sort_by_key(|(i, _)| *i);
    let mut groups: [Vec<RunOutcome>; 6] = Default::default();
    for (i, r) in results {
        groups[jobs[i].group].push(r);
    }
    let [convergence, ppc, other_young, phase1, reference, tls] = groups;
    Ok(AlignedStudy {
        options: o.clone(),
        convergence,
        ppc,
        other_young,
        phase1,
        reference,
        tls,
    })
}
