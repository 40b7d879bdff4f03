//! What `oneblock continue` writes: the branch and curve CSVs, the special
//! points CSV, and the summary (text or JSON).

use std::fmt::Write as _;

use crate::sim::continuation::{Branch, Cascade, ContParam, Curve, SpecialPoint};

/// What a run computed beyond its branches.
pub enum Extra {
    /// Branches only.
    None,
    /// A cascade (its branches are the run's).
    Cascade(Cascade),
    /// Curves, one per start not on an earlier one (the run's branch
    /// located the starts).
    Curves([ContParam; 2], Vec<Curve>),
}

/// `<param>,period,theta_1,…,theta_P,multiplier,stable`, one row per
/// computed point; P is the longest period (shorter cycles leave the
/// extra cells empty).
pub fn branches_csv(branches: &[Branch]) -> String {
    let Some(first) = branches.first() else {
        return String::new();
    };
    let width = branches.iter().map(|b| b.period).max().unwrap_or(1);
    let rows: usize = branches.iter().map(|b| b.points.len()).sum();
    let mut s = String::with_capacity((rows + 1) * (40 + 20 * width));
    s.push_str(first.param.column());
    s.push_str(",period");
    for i in 1..=width {
        write!(s, ",theta_{i}").ok();
    }
    s.push_str(",multiplier,stable\n");
    for b in branches {
        for p in &b.points {
            write!(s, "{},{}", p.lambda, b.period).ok();
            for i in 0..width {
                match p.points.get(i) {
                    Some(th) => write!(s, ",{th}").ok(),
                    None => write!(s, ",").ok(),
                };
            }
            writeln!(s, ",{},{}", p.multiplier, p.stable).ok();
        }
    }
    s
}

/// `kind,period,parameter,value,theta,multiplier,criticality`, one row
/// per special point of every branch, in order (`criticality` empty but
/// for a PD).
pub fn points_csv(branches: &[Branch]) -> String {
    let mut s = String::from("kind,period,parameter,value,theta,multiplier,criticality\n");
    for b in branches {
        for p in &b.special {
            writeln!(
                s,
                "{},{},{},{},{},{},{}",
                p.kind.name(),
                p.period,
                b.param.name(),
                shown(p, p.lambda),
                shown(p, p.theta),
                shown(p, p.multiplier),
                p.criticality_name()
            )
            .ok();
        }
    }
    s
}

/// `curve,kind,period,<p1>,<p2>,theta,multiplier`, one row per point of
/// each polyline (`curve` numbers the polylines from 0).
pub fn curve_csv(params: [ContParam; 2], curves: &[Curve]) -> String {
    let mut s = format!(
        "curve,kind,period,{},{},theta,multiplier\n",
        params[0].column(),
        params[1].column()
    );
    for (i, c) in curves.iter().enumerate() {
        for p in &c.points {
            writeln!(
                s,
                "{i},{},{},{},{},{},{}",
                c.kind.name(),
                c.period,
                p.lambda[0],
                p.lambda[1],
                p.theta,
                p.multiplier
            )
            .ok();
        }
    }
    s
}

/// Where a curve ends, as "(λ₁, λ₂)".
pub fn curve_end(c: &Curve, last: bool) -> String {
    let p = if last {
        c.points.last()
    } else {
        c.points.first()
    };
    p.map_or(String::new(), |p| {
        format!("({}, {})", p.lambda[0], p.lambda[1])
    })
}

/// One line on a curve: its size, its ends and why each ended.
pub fn curve_line(i: usize, c: &Curve) -> String {
    let (a, b) = (c.params[0].name(), c.params[1].name());
    format!(
        "{} curve {i} of P{} in ({a}, {b}): {} points from {} to {}; ends: {}; {}",
        c.kind.name(),
        c.period,
        c.points.len(),
        curve_end(c, false),
        curve_end(c, true),
        c.ends[0],
        c.ends[1]
    ) + &generalised_flips_text(c)
}

/// A PD curve's generalised flips, as the end of its line: where the
/// flip's coefficient changes sign, or that it keeps its sign.
fn generalised_flips_text(c: &Curve) -> String {
    if c.kind != crate::sim::continuation::CurveKind::PeriodDoubling {
        return String::new();
    }
    if c.generalised_flips.is_empty() {
        return "; no generalised flip (the flip's coefficient keeps its sign where decided)"
            .into();
    }
    let at: Vec<String> = c
        .generalised_flips
        .iter()
        .map(|g| format!("({:.6}, {:.6})", g.lambda[0], g.lambda[1]))
        .collect();
    format!(
        "; generalised flip (criticality changes) at {}",
        at.join(", ")
    )
}

/// Where a run stopped by --max-seconds was: the last branch's end, and
/// each curve's last point.
pub fn where_stopped(branches: &[Branch], extra: &Extra) -> String {
    let branch = branches
        .last()
        .map(|b| format!("the P{} branch {}", b.period, b.stop_message()))
        .unwrap_or_default();
    match extra {
        Extra::Curves(_, curves) if !curves.is_empty() => {
            let ends: Vec<String> = curves
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    format!(
                        "curve {i} with {} points from {} to {}",
                        c.points.len(),
                        curve_end(c, false),
                        curve_end(c, true)
                    )
                })
                .collect();
            format!("{}; {branch}", ends.join(", "))
        }
        Extra::Cascade(c) => format!("the cascade {}; {branch}", c.stop),
        _ => branch,
    }
}

/// The run's summary.
pub struct Summary<'a> {
    pub described: &'a str,
    pub branches: &'a [Branch],
    pub extra: &'a Extra,
    pub seconds: f64,
}

/// `v` to 10 significant digits, printed shortest: what a located point
/// is known to (its λ within ~1e-10 relative; its θ and multiplier, from
/// the tighter solver, to about 1e-9), and no more.
pub fn located(v: f64) -> f64 {
    format!("{v:.9e}").parse().unwrap_or(v)
}

/// `v`, a value of `p`: to 10 significant digits where `p` was located
/// ([`located`]), every digit where it is the last computed point.
fn shown(p: &SpecialPoint, v: f64) -> f64 {
    if p.is_located() { located(v) } else { v }
}

fn special_line(s: &mut String, name: &str, p: &SpecialPoint) {
    writeln!(
        s,
        "  {:<7}P{:<3} {name} = {}  theta = {}  multiplier = {}{}{}",
        p.kind.name(),
        p.period,
        shown(p, p.lambda),
        shown(p, p.theta),
        shown(p, p.multiplier),
        p.flip
            .map_or(String::new(), |f| flip_words(name, p.period, &f)),
        if p.note.is_empty() {
            String::new()
        } else {
            format!("  ({})", p.note)
        }
    )
    .ok();
}

/// "  supercritical: a stable P2 cycle above, half-width 0.35·√(theta-nu − b)".
fn flip_words(name: &str, period: usize, f: &crate::sim::continuation::Flip) -> String {
    use crate::sim::continuation::Criticality::*;
    let (side, delta) = if f.side() > 0.0 {
        ("above", format!("{name} - b"))
    } else {
        ("below", format!("b - {name}"))
    };
    let cycle = match f.criticality() {
        Supercritical => "a stable",
        Subcritical => "an unstable",
        Undecided => {
            let narrow = if f.stencil.rounding >= f.coefficient.abs() {
                format!(
                    "; f^p is smooth only within {:.1e} of the cycle point, too narrow for the stencil ({:.1e})",
                    f.stencil.piece, f.stencil.h
                )
            } else {
                String::new()
            };
            let why = if f.born.is_none() {
                format!(
                    "{narrow}: no P{} cycle found next to it on either side with the stability either sign of c gives",
                    2 * period
                )
            } else {
                narrow
            };
            return format!(
                "  undecided criticality (c = {:.3e} ± {:.1e}{why})",
                f.coefficient, f.error
            );
        }
    };
    let confirmed = match f.born {
        Some(b) if b.predicted_side => format!(
            "; confirmed: the P{} cycle at {name} = {:.10} has half-width {:.3e}, m = {:.6}",
            2 * period,
            b.lambda,
            b.half_width,
            b.multiplier
        ),
        Some(b) => format!(
            "; set by the P{} cycle at {name} = {:.10} (half-width {:.3e}, m = {:.6}): the coefficient's stencil gave the other sign",
            2 * period,
            b.lambda,
            b.half_width,
            b.multiplier
        ),
        None => String::new(),
    };
    format!(
        "  {}: {cycle} P{} cycle {side}, half-width {:.4e}*sqrt({delta}){confirmed}",
        f.criticality().name(),
        2 * period,
        f.amplitude()
    )
}

/// A branch's line (its range, points, bifurcations and end), then a line
/// per special point.
fn branch_text(s: &mut String, b: &Branch) {
    let name = b.param.name();
    let count = |k| b.of_kind(k).count();
    use crate::sim::continuation::SpecialKind::*;
    let (from, to) = (
        b.points.first().map_or(f64::NAN, |p| p.lambda),
        b.points.last().map_or(f64::NAN, |p| p.lambda),
    );
    writeln!(
        s,
        "P{} branch in {name} from {from} to {to}: {} points, {} PD, {} fold, {} border{}; it {}",
        b.period,
        b.points.len(),
        count(PeriodDoubling),
        count(Fold),
        count(Border),
        match count(Jump) {
            0 => String::new(),
            n => format!(", {n} jump of m (no bifurcation)"),
        },
        b.stop_message()
    )
    .ok();
    for p in &b.special {
        special_line(s, name, p);
    }
}

/// The cascade's table: each doubling, the gap to the one before, and the
/// ratio δₙ of the gaps, with Feigenbaum's δ to compare.
fn cascade_text(s: &mut String, name: &str, c: &Cascade) {
    writeln!(
        s,
        "cascade: {} doublings; ended: {}",
        c.doublings.len(),
        c.stop
    )
    .ok();
    writeln!(
        s,
        "  {:<3} {:<7} {:<22} {:<12} delta_n",
        "n", "period", name, "gap"
    )
    .ok();
    let ratios = c.ratios();
    for (i, d) in c.doublings.iter().enumerate() {
        let gap = if i > 0 {
            format!("{:.6e}", d.lambda - c.doublings[i - 1].lambda)
        } else {
            String::new()
        };
        let ratio = if i >= 2 {
            format!("{:.4}", ratios[i - 2])
        } else {
            String::new()
        };
        writeln!(
            s,
            "  {:<3} {:<7} {:<22} {:<12} {ratio}",
            i + 1,
            d.period,
            located(d.lambda).to_string(),
            gap
        )
        .ok();
    }
    if let Some(last) = ratios.last() {
        writeln!(
            s,
            "  Feigenbaum's delta is 4.6692...; the last ratio here is {last:.4} ({:+.1} %)",
            100.0 * (last / 4.669_201_609 - 1.0)
        )
        .ok();
    }
}

impl Summary<'_> {
    /// The text summary (for stderr).
    pub fn text(&self) -> String {
        let mut s = format!("continue: {}\n", self.described);
        let evals: u64 = self.branches.iter().map(|b| b.map_evals).sum();
        for b in self.branches {
            branch_text(&mut s, b);
        }
        match self.extra {
            Extra::None => {}
            Extra::Cascade(c) => {
                let name = self.branches.first().map_or("", |b| b.param.name());
                cascade_text(&mut s, name, c);
            }
            Extra::Curves(_, curves) => {
                for (i, c) in curves.iter().enumerate() {
                    writeln!(s, "{}", curve_line(i, c)).ok();
                }
            }
        }
        let curve_evals: u64 = match self.extra {
            Extra::Curves(_, curves) => curves.iter().map(|c| c.map_evals).sum(),
            _ => 0,
        };
        writeln!(
            s,
            "{:.2} s, {} map evaluations (each with its derivatives)",
            self.seconds,
            evals + curve_evals
        )
        .ok();
        s
    }

    /// One JSON object (for stdout).
    pub fn json(&self) -> String {
        let special = |p: &SpecialPoint| {
            serde_json::json!({
                "kind": p.kind.name(),
                "period": p.period,
                "value": shown(p, p.lambda),
                "theta": shown(p, p.theta),
                "multiplier": shown(p, p.multiplier),
                "note": p.note,
                "criticality": p.flip.map(|f| f.criticality().name()),
                "normal_form": p.flip.map(|f| serde_json::json!({
                    "coefficient": f.coefficient,
                    "error": f.error,
                    "dm_dlambda": f.dm_dlambda,
                    "amplitude": f.amplitude(),
                    "side": f.side(),
                    "stencil": f.stencil.h,
                    "smooth_piece": f.stencil.piece,
                    "rounding": f.stencil.rounding,
                })),
            })
        };
        let branches: Vec<_> = self
            .branches
            .iter()
            .map(|b| {
                serde_json::json!({
                    "param": b.param.name(),
                    "period": b.period,
                    "points": b.points.len(),
                    "stop": b.stop_message(),
                    "special": b.special.iter().map(special).collect::<Vec<_>>(),
                    "map_evals": b.map_evals,
                })
            })
            .collect();
        let mut obj = serde_json::json!({
            "branches": branches,
            "seconds": self.seconds,
        });
        if let Some(m) = obj.as_object_mut() {
            match self.extra {
                Extra::None => {}
                Extra::Cascade(c) => {
                    m.insert(
                        "cascade".into(),
                        serde_json::json!({
                            "doublings": c.doublings.iter().map(special).collect::<Vec<_>>(),
                            "ratios": c.ratios(),
                            "stop": c.stop,
                        }),
                    );
                }
                Extra::Curves(_, curves) => {
                    let list: Vec<_> = curves
                        .iter()
                        .map(|c| {
                            serde_json::json!({
                                "kind": c.kind.name(),
                                "period": c.period,
                                "params": [c.params[0].name(), c.params[1].name()],
                                "points": c.points.len(),
                                "ends": c.ends,
                                "map_evals": c.map_evals,
                            })
                        })
                        .collect();
                    m.insert("curves".into(), serde_json::Value::Array(list));
                }
            }
        }
        format!("{obj}\n")
    }
}
