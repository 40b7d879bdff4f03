//! The switch of a cascade onto the doubled cycle born at a doubling:
//! the born cycle (or the nearest 2p-cycle a step past it), checked to
//! lead back to the doubling (see [`super::cascade`]).

use super::branch::SpecialPoint;
use super::pace::solve_cycle;
use super::{Criticality, Pace, Problem};
use crate::model::wrap_angle;
use crate::sim::cycles::CycleOptions;

/// The doubled cycle to follow past the doubling `pd` of `level`: its λ
/// and a point θ of it. The cycle born at the flip where its confirmation
/// solved one ([`super::flip::Born`]); otherwise the 2p-cycle nearest the
/// old one a step `delta` past the doubling ([`nearest_doubled`]). Either
/// must lead back to the doubling ([`leads_back`]): a cycle of the same
/// period born elsewhere is refused, and the cascade ends there.
pub(super) async fn switch(
    pace: &Pace,
    level: &Problem,
    pd: &SpecialPoint,
    delta: f64,
) -> Result<(f64, f64), String> {
    let (name, q) = (level.param.name(), 2 * level.period);
    let born = pd
        .flip
        .and_then(|f| f.born)
        .filter(|b| (b.lambda - pd.lambda) * delta > 0.0);
    let found = match born {
        Some(b) => Some((b.lambda, b.theta)),
        None => nearest_doubled(pace, level, pd, delta).await,
    };
    let Some((l1, theta)) = found else {
        return Err(format!(
            "no P{q} cycle found next to the doubling at {name} = {}",
            pd.lambda
        ));
    };
    match leads_back(pace, level, pd, l1, theta).await {
        Ok(()) => Ok((l1, theta)),
        Err(why) => Err(format!(
            "the P{q} cycle found at {name} = {l1} is not the one born at the doubling at {name} = {}: {why}",
            pd.lambda
        )),
    }
}

/// Whether the 2p-cycle through `theta` at `l1` continues back to the
/// doubling `pd` of `level`: solved by Newton at λ* + (l1 − λ*)/4 and
/// /16, each from the last (its point moved halfway towards θ*), its
/// half-width must halve each time (η ∝ √|λ − λ*|, within 30 %) and its
/// multiplier close in on +1. `Err` says where it does not.
async fn leads_back(
    pace: &Pace,
    level: &Problem,
    pd: &SpecialPoint,
    l1: f64,
    theta: f64,
) -> Result<(), String> {
    let (mut point, mut half, mut m) = doubled_at(pace, level, pd, l1, theta).await?;
    for k in 1..=2 {
        let lambda = pd.lambda + (l1 - pd.lambda) / 4f64.powi(k);
        let seed = pd.theta + 0.5 * wrap_angle(point - pd.theta);
        let (next, h, mk) = doubled_at(pace, level, pd, lambda, seed).await?;
        if !(1.4..=2.6).contains(&(half / h)) {
            return Err(format!(
                "its half-width goes from {half:.3e} to {h:.3e} at {lambda}, where a cycle born at the doubling halves it"
            ));
        }
        if (mk - 1.0).abs() > (m - 1.0).abs().max(1e-3) {
            return Err(format!(
                "its multiplier goes from {m:.6} to {mk:.6} at {lambda}, away from the +1 it is born with"
            ));
        }
        (point, half, m) = (next, h, mk);
    }
    Ok(())
}

/// The 2p-cycle of `level` through `seed` at `lambda`, solved by Newton
/// ([`leads_back`]): its point nearest the doubling `pd`, its half-width
/// and its multiplier; `Err` where there is none of minimal period 2p.
async fn doubled_at(
    pace: &Pace,
    level: &Problem,
    pd: &SpecialPoint,
    lambda: f64,
    seed: f64,
) -> Result<(f64, f64, f64), String> {
    // At the tolerance the doubling was located with (refine.rs), so
    // that the cycle's half-width grows from that λ*.
    let settings = super::refine::tighter(&level.settings).unwrap_or(level.settings);
    let fine = Problem { settings, ..*level };
    let cyc = CycleOptions::for_settings(&settings);
    let (p, q) = (level.period, 2 * level.period);
    let sim = fine.sim(lambda).map_err(|e| e.to_string())?;
    let c = solve_cycle(pace, &sim, seed, q, &cyc, &mut (0, 0))
        .await
        .map_err(|e| format!("Newton found no P{q} cycle at {lambda}: {e}"))?;
    if c.minimal_period != q {
        return Err(format!(
            "at {lambda} Newton fell onto a P{} cycle",
            c.minimal_period
        ));
    }
    let (i, half) = super::flip::nearest_half(&c.points, pd.theta, p);
    Ok((c.points[i], half, c.multiplier))
}

/// The 2p-cycle nearest the old one a step `delta` past the doubling `pd`
/// of `level` (×3, ×10 if none): its λ and a point θ of it.
async fn nearest_doubled(
    pace: &Pace,
    level: &Problem,
    pd: &SpecialPoint,
    delta: f64,
) -> Option<(f64, f64)> {
    // The solver's own tolerance: its points are no more accurate, so a
    // tighter one would tell the old cycle traversed twice from a new one
    // by noise.
    let cyc = CycleOptions::for_settings(&level.settings);
    // The halves of a genuine doubled cycle are apart by far more than
    // the points' error.
    let apart = 1e3 * cyc.tol;
    let doubled = 2 * level.period;
    let p = level.period;
    let fast = pd
        .flip
        .filter(|f| f.criticality() == Criticality::Supercritical);
    for k in [1.0, 3.0, 10.0] {
        let l1 = pd.lambda + delta * k;
        let Ok(sim) = level.sim(l1) else { continue };
        let old = solve_cycle(pace, &sim, pd.theta, level.period, &cyc, &mut (0, 0)).await;
        let Ok(old) = old else {
            continue;
        };
        // The doubled cycle nearest the old one: Newton from a seed may
        // also find another 2p-cycle (a saddle born elsewhere).
        let base = old.points[0];
        let mut best: Option<(f64, f64)> = None;
        // The normal form's half-width first: a cycle that grows fast is
        // further out than the fixed seeds reach.
        let predicted = fast.and_then(|f| f.predicted(pd.lambda, l1));
        for eps in predicted
            .into_iter()
            .chain([1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1])
        {
            for sign in [1.0, -1.0] {
                let seed = base + sign * eps;
                let solved = solve_cycle(pace, &sim, seed, doubled, &cyc, &mut (0, 0)).await;
                if let Ok(c) = solved
                    && c.minimal_period == doubled
                    && (0..p).all(|i| wrap_angle(c.points[i + p] - c.points[i]).abs() > apart)
                {
                    let near = c
                        .points
                        .iter()
                        .map(|&t| wrap_angle(t - base).abs())
                        .fold(f64::INFINITY, f64::min);
                    if best.is_none_or(|(d, _)| near < d) {
                        best = Some((near, c.points[0]));
                    }
                }
            }
        }
        if let Some((_, th)) = best {
            return Some((l1, th));
        }
    }
    None
}
