//! Type-I scaling against a tangency located by continuation.
//!
//! Type-I intermittency is what an orbit does just past a saddle-node
//! (fold) of a cycle: f^p no longer meets the diagonal, a narrow channel is
//! left between them, and the time to cross it grows as ε^(−1/2) with ε
//! the distance to the fold. So the mean laminar length is fitted against
//! ε only where such a fold has been located: a periodic window near θν is
//! looked for (orbits at θν ± k·[`WINDOW_STEP`], nearest first, out to
//! [`WINDOW_SPAN`]), its cycle is followed in θν towards θν by the
//! continuation code ([`crate::sim::continuation`]), and the first fold on
//! that branch is the tangency, with |m − 1| within the location accuracy.
//! Then orbits at θν_f + ε, ε = |θν − θν_f|·2^−k on θν's side, measure the
//! mean laminar length (runs of creep slips), and the creep channel's
//! passage time ([`super::channel`]) is computed beside each. Where no
//! fold is found, there is nothing to fit against, and that is the answer.

use super::channel::PassageRun;
use super::{Intermittency, creep_flags, log_log_fit, supports_type_one};
use crate::integrate::SolverSettings;
use crate::model::Params;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use crate::sim::continuation::{
    Branch, ContOptions, ContParam, Pace, Problem, Reach, SpecialKind, SpecialPoint,
    continue_branch_paced, one_piece,
};
use crate::sim::{CycleFailure, OrbitOptions, OrbitRun, Period, SimError, Simulator};

/// How far from θν a periodic window is looked for, in radians.
pub const WINDOW_SPAN: f64 = 0.05;
/// The spacing of the orbits that look for a window.
pub const WINDOW_STEP: f64 = 5e-4;
/// The most windows whose branch is followed before giving up.
pub const MAX_WINDOWS: usize = 4;
/// Distances from the fold the scaling measures at: |θν − θν_f|·2^−k.
pub const SCAN_POINTS: usize = 8;
/// Orbits of the scaling: this many iterates dropped, then kept.
pub const SCAN_TRANSIENT: usize = 300;
pub const SCAN_KEEP: usize = 2000;

/// A fold of a periodic window's cycle, located by continuation.
#[derive(Clone, Debug, PartialEq)]
pub struct Tangency {
    /// θν at the fold.
    pub theta_nu: f64,
    /// The cycle's period.
    pub period: usize,
    /// A point of the cycle there.
    pub theta: f64,
    /// The multiplier there (1 within the location accuracy).
    pub multiplier: f64,
    /// The θν where the window's stable cycle was found.
    pub window: f64,
    /// The longest run of creep onsets around the cycle at the fold.
    pub creep_run: usize,
}

/// One distance from the fold: the measured mean laminar length and the
/// channel's passage time there.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalePoint {
    /// ε = |θν − θν_f|.
    pub eps: f64,
    /// θν there.
    pub theta_nu: f64,
    /// Complete laminar phases, their mean length and its error.
    pub phases: usize,
    pub mean: Option<f64>,
    pub stderr: Option<f64>,
    /// The creep channel's passage time, when it is open.
    pub passage: Option<f64>,
}

/// The outcome of a scaling scan.
#[derive(Clone, Debug, PartialEq)]
pub enum Scaling {
    /// No fold was found by continuation in [lo, hi]: nothing to fit
    /// against. `windows` periodic windows had their branch followed.
    NoTangency { lo: f64, hi: f64, windows: usize },
    /// A fold, the measurements at distances from it, and the
    /// least-squares (slope, intercept) of log10 mean against log10 ε over
    /// the points with a mean (`None` under three).
    Fitted {
        tangency: Tangency,
        points: Vec<ScalePoint>,
        fit: Option<(f64, f64)>,
    },
}

impl Scaling {
    /// Whether the fit supports type-I intermittency's slope −1/2.
    pub fn supports_type_one(&self) -> bool {
        match self {
            Scaling::Fitted { fit, .. } => fit.is_some_and(|(s, _)| supports_type_one(s)),
            Scaling::NoTangency { .. } => false,
        }
    }

    /// The verdict in plain words, with why where −1/2 is not supported.
    pub fn describe(&self) -> String {
        let (t, fit) = match self {
            Scaling::NoTangency { lo, hi, windows: 0 } => {
                return format!(
                    "no tangency: no periodic orbit found for theta-nu in [{lo:.4}, {hi:.4}], \
                     so no cycle to follow to a fold, and type-I scaling is not fitted"
                );
            }
            Scaling::NoTangency { lo, hi, windows } => {
                return format!(
                    "no tangency: continuation found no fold on the cycles of the {windows} \
                     periodic orbits found for theta-nu in [{lo:.4}, {hi:.4}], so type-I \
                     scaling is not fitted"
                );
            }
            Scaling::Fitted { tangency, fit, .. } => (tangency, fit),
        };
        let fold = format!(
            "the fold of the P{} cycle at theta-nu = {:.6} (multiplier {:.7})",
            t.period, t.theta_nu, t.multiplier
        );
        let Some((slope, _)) = fit else {
            return format!(
                "{fold}: at under 3 of the distances does the orbit have 3 or more laminar \
                 phases (runs of creep slips) to measure, so nothing is fitted"
            );
        };
        if supports_type_one(*slope) {
            return format!("slope {slope:.2} against {fold}: type-I (-1/2) supported");
        }
        let why = if t.period > 1 {
            format!(
                ": near it the orbit follows the P{} cycle's ghost, whose creep runs are at most \
                 {} long, so the laminar phases tend to that length instead of growing; \
                 type-I's eps^(-1/2) is the stay near the ghost, which spans many laminar phases",
                t.period,
                if t.creep_run == 1 {
                    "1 slip".to_string()
                } else {
                    format!("{} slips", t.creep_run)
                }
            )
        } else {
            ": the creep runs do not lengthen towards it (the channel passage beside each \
             point says how wide the creep channel is)"
                .into()
        };
        format!("slope {slope:.2} against {fold}, not -1/2 (within 0.15){why}")
    }
}

/// The longest cyclic run of creep onsets among `points`.
fn longest_creep_run(kappa: f64, gamma: f64, points: &[f64]) -> usize {
    let c = creep_flags(kappa, gamma, points.iter().copied());
    if c.iter().all(|x| *x) {
        return c.len();
    }
    let (mut best, mut run) = (0, 0);
    for x in c.iter().chain(c.iter()) {
        run = if *x { run + 1 } else { 0 };
        best = best.max(run);
    }
    best
}

/// The orbits that look for a periodic window.
fn window_options(settings: &SolverSettings) -> OrbitOptions {
    OrbitOptions {
        transient: 1000,
        keep: 256,
        lyapunov: false,
        period_tol: OrbitOptions::period_tol_for(settings.rtol),
    }
}

/// The first fold on the branch of a periodic window's cycle nearest
/// `params.theta_nu` (see the module notes), and how many windows' branches
/// were followed.
pub fn find_tangency(
    params: Params,
    settings: SolverSettings,
    cancel: &dyn Fn() -> bool,
) -> Result<(Option<Tangency>, usize), SimError> {
    let mut search = Search::new(params, settings);
    loop {
        if let Some(r) = search.advance(cancel) {
            return r;
        }
    }
}

/// [`find_tangency`] in pieces: one slip cycle of an orbit looking for a
/// window, or one map evaluation of the continuation of a window's cycle.
struct Search {
    params: Params,
    settings: SolverSettings,
    /// The next position looked at: θν ∓ k·[`WINDOW_STEP`], k = pos/2 + 1,
    /// below θν first.
    pos: usize,
    windows: usize,
    /// The orbit under way at the current position.
    orbit: Option<(Simulator, OrbitRun)>,
    /// A window found, whose branch is followed next: (θν, period, point).
    found: Option<(f64, usize, f64)>,
    /// The window's branch under way.
    following: Option<Following>,
}

/// The continuation of a window's cycle at `at`, paused between its map
/// evaluations.
struct Following {
    at: f64,
    period: usize,
    pace: Arc<Pace>,
    walk: Pin<Box<dyn Future<Output = Result<Branch, CycleFailure>> + Send>>,
}

impl Search {
    fn new(params: Params, settings: SolverSettings) -> Self {
        Search {
            params,
            settings,
            pos: 0,
            windows: 0,
            orbit: None,
            found: None,
            following: None,
        }
    }

    /// θν at `pos`.
    fn at(&self, pos: usize) -> f64 {
        let k = pos / 2 + 1;
        let sign = if pos.is_multiple_of(2) { -1.0 } else { 1.0 };
        self.params.theta_nu + sign * k as f64 * WINDOW_STEP
    }

    /// One piece; the search's answer once it has one.
    fn advance(
        &mut self,
        cancel: &dyn Fn() -> bool,
    ) -> Option<Result<(Option<Tangency>, usize), SimError>> {
        if let Some((at, period, seed)) = self.found.take() {
            self.following = Some(self.follow(at, period, seed));
        }
        if let Some(f) = self.following.as_mut() {
            let followed = one_piece(&f.pace, f.walk.as_mut(), cancel)?;
            let (at, period) = (f.at, f.period);
            self.following = None;
            return self.followed(at, period, followed, cancel);
        }
        let steps = (WINDOW_SPAN / WINDOW_STEP).round() as usize;
        if self.pos >= 2 * steps {
            return Some(Ok((None, self.windows)));
        }
        if self.orbit.is_none() {
            let at = self.at(self.pos);
            let started = Simulator::new(
                Params {
                    theta_nu: at,
                    ..self.params
                },
                self.settings,
            )
            .and_then(|sim| {
                let run = OrbitRun::new(&sim, at, &window_options(&self.settings))?;
                Ok((sim, run))
            });
            match started {
                Ok(o) => self.orbit = Some(o),
                Err(e) => return Some(Err(e)),
            }
        }
        let (sim, run) = self.orbit.as_mut()?;
        let orbit = match run.advance(sim, cancel)? {
            Ok(o) => o,
            Err(e) => return Some(Err(e)),
        };
        self.orbit = None;
        let at = self.at(self.pos);
        self.pos += 1;
        // The stable cycle there, when the orbit is periodic.
        if let (Period::Periodic(p), Some(c)) = (orbit.period, orbit.cycle)
            && c.stable
        {
            self.windows += 1;
            self.found = Some((at, p, c.points[0]));
        }
        None
    }

    /// The continuation of the cycle of the window at `at` towards θν,
    /// nothing evaluated yet.
    fn follow(&self, at: f64, period: usize, seed: f64) -> Following {
        let (params, settings) = (self.params, self.settings);
        let top = params.theta_nu;
        let prob = Problem {
            base: params,
            settings,
            param: ContParam::ThetaNu,
            period,
        };
        let opts = ContOptions::for_range(&settings, at, top);
        let pace = Arc::new(Pace::new());
        let walk_pace = pace.clone();
        let walk = Box::pin(async move {
            let quiet = &mut |_: &SpecialPoint| {};
            let reach = Reach::new(&prob, at, top, &opts);
            continue_branch_paced(&walk_pace, reach, seed, quiet).await
        });
        Following {
            at,
            period,
            pace,
            walk,
        }
    }

    /// The window's branch, `followed` from `at`: its first fold is the
    /// tangency.
    fn followed(
        &mut self,
        at: f64,
        period: usize,
        followed: Result<Branch, CycleFailure>,
        cancel: &dyn Fn() -> bool,
    ) -> Option<Result<(Option<Tangency>, usize), SimError>> {
        let params = self.params;
        match followed {
            Ok(b) => {
                if let Some(f) = b.of_kind(SpecialKind::Fold).next() {
                    let near = b.points.iter().min_by(|a, c| {
                        (a.lambda - f.lambda)
                            .abs()
                            .total_cmp(&(c.lambda - f.lambda).abs())
                    });
                    let creep_run = near.map_or(0, |p| {
                        longest_creep_run(params.kappa, params.gamma, &p.points)
                    });
                    let t = Tangency {
                        theta_nu: f.lambda,
                        period,
                        theta: f.theta,
                        multiplier: f.multiplier,
                        window: at,
                        creep_run,
                    };
                    return Some(Ok((Some(t), self.windows)));
                }
            }
            Err(CycleFailure::Sim(SimError::Cancelled)) => {
                return Some(Err(SimError::Cancelled));
            }
            Err(_) => {}
        }
        if cancel() {
            return Some(Err(SimError::Cancelled));
        }
        (self.windows >= MAX_WINDOWS).then_some(Ok((None, self.windows)))
    }
}

/// The measurement at one distance from the fold in pieces: the orbit's
/// slip cycles, then the channel passage's map evaluations.
struct Measure {
    sim: Simulator,
    theta_nu: f64,
    eps: f64,
    orbit: OrbitRun,
    /// Once the orbit is done: its statistics and the passage under way
    /// (`None`: no creep onset, so none).
    measured: Option<(Intermittency, Option<PassageRun>)>,
}

impl Measure {
    fn new(
        params: Params,
        settings: SolverSettings,
        theta_nu: f64,
        eps: f64,
    ) -> Result<Self, SimError> {
        let sim = Simulator::new(Params { theta_nu, ..params }, settings)?;
        let opts = OrbitOptions {
            transient: SCAN_TRANSIENT,
            keep: SCAN_KEEP,
            lyapunov: false,
            period_tol: 1e-6,
        };
        let orbit = OrbitRun::new(&sim, theta_nu, &opts)?;
        Ok(Measure {
            sim,
            theta_nu,
            eps,
            orbit,
            measured: None,
        })
    }

    /// One piece; the point once it is measured.
    fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<ScalePoint, SimError>> {
        let Some((st, run)) = &mut self.measured else {
            let orbit = match self.orbit.advance(&self.sim, cancel)? {
                Ok(o) => o,
                Err(e) => return Some(Err(e)),
            };
            let p = self.sim.params();
            let (stats, first_creep) = Intermittency::of_events(p.kappa, p.gamma, &orbit.events);
            let passage = first_creep.map(|th| PassageRun::new(&self.sim, th));
            self.measured = Some((stats, passage));
            return None;
        };
        let passage = match run {
            Some(run) => match run.advance(&self.sim, cancel)? {
                Ok(p) => p.mean(),
                Err(e) => return Some(Err(e)),
            },
            None => None,
        };
        Some(Ok(ScalePoint {
            eps: self.eps,
            theta_nu: self.theta_nu,
            phases: st.laminar.len(),
            mean: st
                .mean_laminar
                .filter(|_| st.laminar.len() >= super::MIN_PHASES),
            stderr: st.mean_laminar_stderr,
            passage,
        }))
    }
}

/// The tangency nearest `params.theta_nu` and, when there is one, the
/// mean laminar length against the distance to it (module notes). A few
/// seconds to tens of seconds; `cancel` stops it.
pub fn scaling(
    params: Params,
    settings: SolverSettings,
    cancel: &dyn Fn() -> bool,
) -> Result<Scaling, SimError> {
    let mut run = ScalingRun::new(params, settings);
    loop {
        if let Some(r) = run.advance(cancel) {
            return r;
        }
    }
}

/// [`scaling`] in pieces, so that a host on a slice of time (the browser's)
/// can stop between two and go on later with the same result bit for bit:
/// each piece one slip cycle of an orbit, one map evaluation of a channel
/// passage, or one continuation of a window's cycle (the only piece not
/// divided: tens to hundreds of milliseconds).
pub struct ScalingRun {
    search: Search,
    tangency: Option<Tangency>,
    points: Vec<ScalePoint>,
    measuring: Option<Measure>,
}

impl ScalingRun {
    /// The scan at `params`, nothing computed yet.
    pub fn new(params: Params, settings: SolverSettings) -> Self {
        ScalingRun {
            search: Search::new(params, settings),
            tangency: None,
            points: Vec::with_capacity(SCAN_POINTS),
            measuring: None,
        }
    }

    /// One piece (`cancel` polled before each slip cycle or evaluation),
    /// then `None`, or the scan's result.
    pub fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<Scaling, SimError>> {
        let (params, settings) = (self.search.params, self.search.settings);
        let top = params.theta_nu;
        let Some(tangency) = &self.tangency else {
            return match self.search.advance(cancel)? {
                Ok((Some(t), _)) => {
                    self.tangency = Some(t);
                    None
                }
                Ok((None, windows)) => Some(Ok(Scaling::NoTangency {
                    lo: top - WINDOW_SPAN,
                    hi: top + WINDOW_SPAN,
                    windows,
                })),
                Err(e) => Some(Err(e)),
            };
        };
        if self.points.len() == SCAN_POINTS {
            let pts: Vec<(f64, f64)> = self
                .points
                .iter()
                .filter_map(|p| p.mean.map(|m| (p.eps, m)))
                .collect();
            return Some(Ok(Scaling::Fitted {
                tangency: tangency.clone(),
                points: std::mem::take(&mut self.points),
                fit: log_log_fit(&pts),
            }));
        }
        if self.measuring.is_none() {
            let dist = top - tangency.theta_nu;
            let eps = dist.abs() * 0.5f64.powi(self.points.len() as i32);
            let at = tangency.theta_nu + eps.copysign(dist);
            match Measure::new(params, settings, at, eps) {
                Ok(m) => self.measuring = Some(m),
                Err(e) => return Some(Err(e)),
            }
        }
        match self.measuring.as_mut()?.advance(cancel)? {
            Ok(point) => {
                self.points.push(point);
                self.measuring = None;
                None
            }
            Err(e) => Some(Err(e)),
        }
    }
}
