//! What the continuation jobs sent: the branches of "Find bifurcations"
//! and the curves of "Boundaries", and what the views derive from them
//! without drawing: a branch cut into stable and unstable runs, the special
//! points as table rows, the CSV line a row copies, numbers to 9
//! significant digits, and which marker or branch point the pointer is on.

use super::jobs::Receive;
use crate::sim::continuation::{Branch, ContParam, Curve, SpecialKind, SpecialPoint};
use crate::worker::Update;

/// The branches of a "Find bifurcations" job, in the order they ended.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BranchData {
    /// The parameter varied (θν from the bifurcation view).
    pub param: Option<ContParam>,
    /// The range followed.
    pub range: (f64, f64),
    /// The branches: the attractor's over the whole range, then each
    /// doubled level of the cascade.
    pub branches: Vec<Branch>,
    /// The cascade's doublings b₁, b₂, … in order (periods p, 2p, 4p, …),
    /// once the cascade has ended (`oneblock continue --cascade`'s table).
    pub doublings: Vec<SpecialPoint>,
}

/// The curves of a "Boundaries" job.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurveData {
    /// The curves in (θν, κ), in the order they ended.
    pub curves: Vec<Curve>,
}

/// A stretch of one cycle point's path along a branch, all stable or all
/// unstable: (λ, θᵢ) in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// |multiplier| < 1 along it.
    pub stable: bool,
    /// The points (λ, θ).
    pub points: Vec<[f64; 2]>,
}

/// The paths of the branch's p cycle points, cut where the stability
/// changes (the point where it changes ends one run and starts the next,
/// so the drawn path is unbroken) and where θ wraps across ±π (a jump of
/// more than π between neighbours is the wrap, not the path).
pub fn runs(b: &Branch) -> Vec<Run> {
    let mut out = Vec::new();
    for i in 0..b.period {
        let mut cur: Option<Run> = None;
        let mut last: Option<[f64; 2]> = None;
        for p in &b.points {
            let Some(&th) = p.points.get(i) else {
                continue;
            };
            let xy = [p.lambda, th];
            let wrapped = last.is_some_and(|l| (l[1] - th).abs() > std::f64::consts::PI);
            match &mut cur {
                Some(r) if wrapped => {
                    out.push(std::mem::replace(
                        r,
                        Run {
                            stable: p.stable,
                            points: vec![xy],
                        },
                    ));
                }
                Some(r) if r.stable != p.stable => {
                    r.points.push(xy);
                    let done = std::mem::replace(
                        r,
                        Run {
                            stable: p.stable,
                            points: vec![xy],
                        },
                    );
                    out.push(done);
                }
                Some(r) => r.points.push(xy),
                None => {
                    cur = Some(Run {
                        stable: p.stable,
                        points: vec![xy],
                    });
                }
            }
            last = Some(xy);
        }
        out.extend(cur);
    }
    out
}

/// The special points the table lists and the view marks: PD, fold and
/// border points of every branch (a branch's end is not a bifurcation).
pub fn special_rows(data: &BranchData) -> Vec<&SpecialPoint> {
    data.branches
        .iter()
        .flat_map(|b| b.special.iter())
        .filter(|s| s.kind != SpecialKind::End)
        .collect()
}

/// `x` to 9 significant digits, without trailing zeros ("1.08957189",
/// "-1", "3.2e-12").
pub fn sig9(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if !(-4..9).contains(&e) {
        let s = format!("{x:.8e}");
        let (m, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let m = trim_zeros(m);
        return format!("{m}e{exp}");
    }
    let decimals = (8 - e).max(0) as usize;
    trim_zeros(&format!("{x:.decimals$}"))
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// The row's line of `oneblock continue --points`:
/// `kind,period,parameter,value,theta,multiplier,criticality` (full
/// precision, as the command line writes it).
pub fn csv_line(param: ContParam, p: &SpecialPoint) -> String {
    format!(
        "{},{},{},{},{},{},{}",
        p.kind.name(),
        p.period,
        param.name(),
        p.lambda,
        p.theta,
        p.multiplier,
        p.criticality_name()
    )
}

/// The header of `oneblock continue --points`.
pub const CSV_HEADER: &str = "kind,period,parameter,value,theta,multiplier,criticality";

/// The words a hover shows for a point at (λ, θ) with its multiplier.
pub fn hover_text(
    what: &str,
    param: ContParam,
    lambda: f64,
    theta: f64,
    multiplier: f64,
) -> String {
    let name = param.symbol();
    format!(
        "{what}\n{name} = {}\nθ = {}\nmultiplier = {}",
        sig9(lambda),
        sig9(theta),
        sig9(multiplier)
    )
}

/// The hover of the marker or branch point nearest to `pointer`, if one
/// lies within `radius` (all in screen units: `to_screen` maps (λ, θ)
/// there). Markers win over branch points at equal distance.
pub fn nearest(
    data: &BranchData,
    to_screen: impl Fn([f64; 2]) -> [f32; 2],
    pointer: [f32; 2],
    radius: f32,
) -> Option<String> {
    let param = data.param?;
    let dist = |xy: [f64; 2]| {
        let s = to_screen(xy);
        (s[0] - pointer[0]).hypot(s[1] - pointer[1])
    };
    let mut best: Option<(f32, String)> = None;
    let mut consider = |d: f32, text: &dyn Fn() -> String| {
        if d <= radius && best.as_ref().is_none_or(|(b, _)| d < *b) {
            best = Some((d, text()));
        }
    };
    for s in special_rows(data) {
        let d = dist([s.lambda, s.theta]);
        consider(d - 0.5, &|| {
            hover_text(
                &format!("{} of P{}", s.kind.name(), s.period),
                param,
                s.lambda,
                s.theta,
                s.multiplier,
            )
        });
    }
    for b in &data.branches {
        for p in &b.points {
            for &th in &p.points {
                let d = dist([p.lambda, th]);
                consider(d, &|| {
                    let what = format!(
                        "P{} branch ({})",
                        b.period,
                        if p.stable { "stable" } else { "unstable" }
                    );
                    hover_text(&what, param, p.lambda, th, p.multiplier)
                });
            }
        }
    }
    best.map(|(_, t)| t)
}

impl Receive for BranchData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Branch { branch, .. } => self.branches.push(branch),
            Update::Cascade { cascade, .. } => self.doublings = cascade.doublings,
            u => return Some(u),
        }
        None
    }
}

impl Receive for CurveData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Curve { curve, .. } => {
                self.curves.push(curve);
                None
            }
            u => Some(u),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::continuation::{BranchPoint, Stop};

    fn point(lambda: f64, points: Vec<f64>, multiplier: f64) -> BranchPoint {
        BranchPoint {
            lambda,
            minimal_period: points.len(),
            points,
            multiplier,
            stable: multiplier.abs() < 1.0,
        }
    }

    #[test]
    fn nine_significant_digits() {
        assert_eq!(sig9(1.089_571_894_977_762), "1.08957189");
        assert_eq!(sig9(-0.999_999_999_761_115_4), "-1");
        assert_eq!(sig9(0.418_572_534_978_968_2), "0.418572535");
        assert_eq!(sig9(123.456_789_012_3), "123.456789");
        assert_eq!(sig9(-3.2e-12), "-3.2e-12");
        assert_eq!(sig9(0.0), "0");
    }

    #[test]
    fn a_branch_is_cut_where_its_stability_changes_and_where_theta_wraps() {
        let b = Branch {
            param: ContParam::ThetaNu,
            period: 1,
            points: vec![
                point(1.0, vec![0.3], -0.5),
                point(1.1, vec![0.4], -0.9),
                point(1.2, vec![0.5], -1.2),
                point(1.3, vec![3.1], -1.5),
                point(1.4, vec![-3.1], -1.6),
            ],
            special: vec![],
            stop: Stop::Reached,
            map_evals: 0,
        };
        let r = runs(&b);
        assert_eq!(r.len(), 3);
        assert!(r[0].stable && !r[1].stable && !r[2].stable);
        // The stability change is shared, the wrap is not drawn.
        assert_eq!(r[0].points, [[1.0, 0.3], [1.1, 0.4], [1.2, 0.5]]);
        assert_eq!(r[1].points, [[1.2, 0.5], [1.3, 3.1]]);
        assert_eq!(r[2].points, [[1.4, -3.1]]);
    }
}
