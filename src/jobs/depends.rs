//! What a job's result depends on: the one rule for stale results, used by
//! the window (its slots' bounds, `app::jobs::stale`) and by the worker
//! (`Command::SetParams`, through [`super::Spec::on_params`]) alike. Each
//! kind's line of the job table names its [`Depends`]; a result is of
//! other parameters exactly when its [`ParamsKey`] changed.

use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::continuation::ContParam;

/// Which of the model's parameters a kind's result depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depends {
    /// Every one (a result at one point of the parameter space).
    All,
    /// Every one but the parameter it varies (a diagram's axis), and which
    /// one that is.
    ButVaried,
    /// Every one but θν and κ (the phase plane's axes).
    ButAxes,
}

/// The values a result depends on: the bit pattern of each parameter of
/// [`ContParam::ALL`] it depends on (`None` for the others), and the
/// parameter it varies, if it varies one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamsKey {
    values: [Option<u64>; 5],
    varied: Option<ContParam>,
}

impl Depends {
    /// The key of a result at `p` that varies `varied` (read by
    /// [`Depends::ButVaried`] only).
    pub fn key(self, p: &Params, varied: ContParam) -> ParamsKey {
        let free = |q: ContParam| match self {
            Depends::All => false,
            Depends::ButVaried => q == varied,
            Depends::ButAxes => matches!(q, ContParam::ThetaNu | ContParam::Kappa),
        };
        ParamsKey {
            values: ContParam::ALL.map(|q| (!free(q)).then(|| q.get(p).to_bits())),
            varied: (self == Depends::ButVaried).then_some(varied),
        }
    }
}

/// What a spec was computed for, for the rule: its parameters, its solver,
/// and the parameter it varies.
pub trait Bound: Clone {
    /// Its parameters and solver settings, to read or replace.
    fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings);

    /// The parameter it varies (θν unless it says otherwise; read only by
    /// kinds that depend on all but the varied one).
    fn varied(&self) -> ContParam {
        ContParam::ThetaNu
    }

    /// Its key under the dependence `d`, at parameters `p` (its own if
    /// `None`).
    fn key(&self, d: Depends, p: Option<&Params>) -> ParamsKey {
        let mut me = self.clone();
        let own = *me.params_mut().0;
        d.key(p.unwrap_or(&own), self.varied())
    }

    /// Whether new `params` (and `settings`, if given) make its result one
    /// of other parameters: the rule.
    fn changed_by(&self, d: Depends, params: &Params, settings: Option<SolverSettings>) -> bool {
        let mut me = self.clone();
        let solver = *me.params_mut().1;
        self.key(d, None) != self.key(d, Some(params)) || settings.is_some_and(|n| n != solver)
    }

    /// This spec with the new parameters (and settings), to run again.
    fn with(&self, params: Params, settings: Option<SolverSettings>) -> Self {
        let mut spec = self.clone();
        let (p, s) = spec.params_mut();
        *p = params;
        if let Some(settings) = settings {
            *s = settings;
        }
        spec
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rule_leaves_out_exactly_its_free_parameters() {
        let p = Params::default();
        for d in [Depends::All, Depends::ButVaried, Depends::ButAxes] {
            for moved in ContParam::ALL {
                let q = moved.set(&p, moved.get(&p) * 1.5 + 0.1);
                let free = match d {
                    Depends::All => false,
                    Depends::ButVaried => moved == ContParam::Gamma,
                    Depends::ButAxes => matches!(moved, ContParam::ThetaNu | ContParam::Kappa),
                };
                let same = d.key(&p, ContParam::Gamma) == d.key(&q, ContParam::Gamma);
                assert_eq!(same, free, "{d:?}, {moved:?} moved");
            }
        }
        // Another varied parameter is another result.
        let (a, b) = (ContParam::Gamma, ContParam::Kappa);
        assert_ne!(Depends::ButVaried.key(&p, a), Depends::ButVaried.key(&p, b));
        assert_eq!(Depends::All.key(&p, a), Depends::All.key(&p, b));
    }
}
