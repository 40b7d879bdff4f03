//! What a session keeps of the window's results ([`Results`]): the
//! branches of "Find bifurcations" with their special points, and the
//! curves of "Boundaries" with their generalised flips, each with its
//! status line. They reopen drawn, without a job, bound to the session's
//! parameters ([`super::jobs::Jobs::restore`]), so the window's one rule
//! for stale results clears them on any later change of what they
//! depend on.
//!
//! Read as the session's other fields are: a result whose numbers are not
//! all finite, whose lists are longer than the window ever makes them, or
//! whose text is too long is dropped whole and named in the session's one
//! message; the rest of the file is kept.
//!
//! Seeded attractors are not kept: they are columns of the diagram and
//! cells of the phase grid, which the window computes again by itself from
//! the session's settings (their seeds included).

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::branches::{BranchData, CurveData};
use crate::sim::PERIOD_MAX;
use crate::sim::continuation::{Branch, ContParam, Curve, SpecialPoint, Stop};

/// The most branches kept: a cascade to period 32 is six levels, each
/// a branch or a few.
pub const MAX_BRANCHES: usize = 64;
/// The most points of one branch: the window's continuation stops at
/// 5000 (`ContOptions::for_range`).
pub const MAX_BRANCH_POINTS: usize = 5000;
/// The most special points of one branch.
pub const MAX_SPECIAL_POINTS: usize = 512;
/// The most curves kept.
pub const MAX_CURVES: usize = 64;
/// The most points of one curve: 2000 each way from its start
/// (`CurveOptions::for_box`), and the start.
pub const MAX_CURVE_POINTS: usize = 4001;
/// The longest text kept (a status line, a note, why a branch ended).
pub const MAX_TEXT: usize = 500;

/// A result as the window showed it: its data and its status line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Kept<T> {
    pub data: T,
    pub summary: Option<String>,
}

/// What a session keeps of the window's results (none by default: an
/// older session, or nothing computed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Results {
    /// "Find bifurcations": the branches over the diagram.
    pub branches: Option<Kept<BranchData>>,
    /// "Boundaries": the curves over the phase diagram.
    pub curves: Option<Kept<CurveData>>,
}

/// The branches as the file holds them.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BranchesFile {
    param: ContParam,
    range: (f64, f64),
    #[serde(default)]
    summary: Option<String>,
    branches: Vec<Branch>,
    /// The cascade's doublings (δₙ's table); none in older sessions.
    #[serde(default)]
    doublings: Vec<SpecialPoint>,
}

/// The curves as the file holds them.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CurvesFile {
    #[serde(default)]
    summary: Option<String>,
    curves: Vec<Curve>,
}

/// The file's keys of the results.
pub const KEYS: [&str; 2] = ["branches", "curves"];

impl Results {
    /// Whether it keeps nothing.
    pub fn is_empty(&self) -> bool {
        self.branches.is_none() && self.curves.is_none()
    }

    /// The results as the file's fields (compact JSON each: a branch holds
    /// thousands of numbers), in the order of [`KEYS`].
    pub fn to_fields(&self) -> Vec<(&'static str, String)> {
        let mut out = Vec::new();
        if let Some(k) = &self.branches
            && let Some(param) = k.data.param
        {
            let f = BranchesFile {
                param,
                range: k.data.range,
                summary: k.summary.clone(),
                branches: k.data.branches.clone(),
                doublings: k.data.doublings.clone(),
            };
            out.extend(serde_json::to_string(&f).ok().map(|t| ("branches", t)));
        }
        if let Some(k) = &self.curves {
            let f = CurvesFile {
                summary: k.summary.clone(),
                curves: k.data.curves.clone(),
            };
            out.extend(serde_json::to_string(&f).ok().map(|t| ("curves", t)));
        }
        out
    }

    /// The results a session's `root` holds, taken out of it; each one
    /// that cannot be read or fails its check is left out and named in
    /// `dropped` with why. Branches must be in `varied`, the parameter
    /// the session's diagram varies (they are drawn over it).
    pub fn take_from(
        root: &mut Map<String, Value>,
        varied: ContParam,
        dropped: &mut Vec<String>,
    ) -> Results {
        let mut r = Results::default();
        if let Some(v) = root.remove("branches") {
            match serde_json::from_value::<BranchesFile>(v) {
                Err(_) => dropped.push("branches (unreadable)".into()),
                Ok(f) if f.param != varied => dropped.push(format!(
                    "branches (in {}, the diagram in {})",
                    f.param.name(),
                    varied.name()
                )),
                Ok(f) => match check_branches(&f) {
                    Err(why) => dropped.push(format!("branches ({why})")),
                    Ok(()) => {
                        let data = BranchData {
                            param: Some(f.param),
                            range: f.range,
                            branches: f.branches,
                            doublings: f.doublings,
                        };
                        r.branches = Some(Kept {
                            data,
                            summary: f.summary,
                        });
                    }
                },
            }
        }
        if let Some(v) = root.remove("curves") {
            match serde_json::from_value::<CurvesFile>(v) {
                Err(_) => dropped.push("curves (unreadable)".into()),
                Ok(f) => match check_curves(&f) {
                    Err(why) => dropped.push(format!("curves ({why})")),
                    Ok(()) => {
                        let data = CurveData { curves: f.curves };
                        r.curves = Some(Kept {
                            data,
                            summary: f.summary,
                        });
                    }
                },
            }
        }
        r
    }
}

const NOT_FINITE: &str = "a number not finite";
const TOO_LONG: &str = "a text too long or with control characters";

/// Whether a text may be shown: short, one line.
fn text_ok(s: &str) -> bool {
    s.chars().count() <= MAX_TEXT && !s.chars().any(char::is_control)
}

fn all_finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

/// A special point's numbers finite (a flip's smooth piece may be ∞,
/// never NaN) and its note a line.
fn special_ok(s: &SpecialPoint) -> bool {
    let flip_ok = s.flip.is_none_or(|f| {
        let st = f.stencil;
        let born = f
            .born
            .is_none_or(|b| all_finite(&[b.lambda, b.theta, b.half_width, b.multiplier]));
        all_finite(&[f.coefficient, f.error, f.dm_dlambda, st.h, st.rounding])
            && !st.piece.is_nan()
            && born
    });
    all_finite(&[s.lambda, s.theta, s.multiplier]) && flip_ok
}

/// One branch against the window's bounds.
fn check_branch(b: &Branch, param: ContParam) -> Result<(), String> {
    let period_ok = |p: usize| (1..=PERIOD_MAX).contains(&p);
    if b.param != param || !period_ok(b.period) {
        return Err(format!(
            "a branch of another parameter or of a period beyond {PERIOD_MAX}"
        ));
    }
    if b.points.len() > MAX_BRANCH_POINTS || b.special.len() > MAX_SPECIAL_POINTS {
        return Err(format!(
            "a branch of over {MAX_BRANCH_POINTS} points or {MAX_SPECIAL_POINTS} special points"
        ));
    }
    for p in &b.points {
        if p.points.len() > PERIOD_MAX || !period_ok(p.minimal_period) {
            return Err(format!("a cycle of over {PERIOD_MAX} points"));
        }
        if !all_finite(&p.points) || !all_finite(&[p.lambda, p.multiplier]) {
            return Err(NOT_FINITE.into());
        }
    }
    if !b.special.iter().all(special_ok) {
        return Err(NOT_FINITE.into());
    }
    let failed = match &b.stop {
        Stop::Failed(why) => why.as_str(),
        _ => "",
    };
    if !b.special.iter().all(|s| text_ok(&s.note)) || !text_ok(failed) {
        return Err(TOO_LONG.into());
    }
    Ok(())
}

/// The branches against the window's bounds: why not, if they fail.
fn check_branches(f: &BranchesFile) -> Result<(), String> {
    if f.branches.len() > MAX_BRANCHES {
        return Err(format!("over {MAX_BRANCHES} branches"));
    }
    if !all_finite(&[f.range.0, f.range.1]) {
        return Err(NOT_FINITE.into());
    }
    if !f.summary.as_deref().is_none_or(text_ok) {
        return Err(TOO_LONG.into());
    }
    // A cascade has a doubling per level, at most one per branch.
    if f.doublings.len() > MAX_BRANCHES || !f.doublings.iter().all(special_ok) {
        return Err("a cascade's doubling not finite, or too many".into());
    }
    f.branches.iter().try_for_each(|b| check_branch(b, f.param))
}

/// The curves against the window's bounds: why not, if they fail.
fn check_curves(f: &CurvesFile) -> Result<(), String> {
    if f.curves.len() > MAX_CURVES {
        return Err(format!("over {MAX_CURVES} curves"));
    }
    if !f.summary.as_deref().is_none_or(text_ok) {
        return Err(TOO_LONG.into());
    }
    for c in &f.curves {
        if !(1..=PERIOD_MAX).contains(&c.period)
            || c.points.len() > MAX_CURVE_POINTS
            || c.generalised_flips.len() > MAX_CURVE_POINTS
        {
            return Err(format!(
                "a curve of over {MAX_CURVE_POINTS} points or of a period beyond {PERIOD_MAX}"
            ));
        }
        let points = c
            .points
            .iter()
            .all(|p| all_finite(&[p.lambda[0], p.lambda[1], p.theta, p.multiplier]));
        let flips = c.generalised_flips.iter().all(|g| {
            all_finite(&[
                g.lambda[0],
                g.lambda[1],
                g.coefficients[0],
                g.coefficients[1],
            ])
        });
        if !points || !flips {
            return Err(NOT_FINITE.into());
        }
        if !c.ends.iter().all(|e| text_ok(e)) {
            return Err(TOO_LONG.into());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::continuation::{ContOptions, CurveOptions};

    /// The caps are the window's own bounds.
    #[test]
    fn the_caps_are_what_the_window_can_make() {
        let s = crate::integrate::SolverSettings::default();
        assert_eq!(
            ContOptions::for_range(&s, 0.0, 1.0).max_points,
            MAX_BRANCH_POINTS
        );
        let c = CurveOptions::for_box([[0.0, 1.0], [0.0, 1.0]]).max_points;
        assert_eq!(2 * c + 1, MAX_CURVE_POINTS);
        const { assert!(super::super::jobs::MAX_CASCADE_PERIOD <= PERIOD_MAX) };
    }
}
