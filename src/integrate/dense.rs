//! Dense output over one accepted step: the solution at any t in [t0, t0+h].

use super::State;

/// A polynomial interpolant of one step, in θ = (t − t0)/h ∈ [0, 1].
#[derive(Clone, Debug)]
pub struct Dense {
    pub t0: f64,
    pub h: f64,
    pub y0: State,
    kind: Kind,
}

#[derive(Clone, Debug)]
enum Kind {
    /// y0 + h θ (q1 + θ (q2 + θ (q3 + θ q4))).
    Power([State; 4]),
    /// DOP853's nested form: F0 … F6 alternately multiplied by θ and 1 − θ.
    Dop853([State; 7]),
    /// Cubic Hermite from the end values and derivatives.
    Hermite { y1: State, f0: State, f1: State },
}

impl Dense {
    pub(crate) fn power(t0: f64, h: f64, y0: State, q: [State; 4]) -> Self {
        Dense {
            t0,
            h,
            y0,
            kind: Kind::Power(q),
        }
    }
    pub(crate) fn dop853(t0: f64, h: f64, y0: State, f: [State; 7]) -> Self {
        Dense {
            t0,
            h,
            y0,
            kind: Kind::Dop853(f),
        }
    }
    pub(crate) fn hermite(t0: f64, h: f64, y0: State, y1: State, f0: State, f1: State) -> Self {
        Dense {
            t0,
            h,
            y0,
            kind: Kind::Hermite { y1, f0, f1 },
        }
    }

    /// The end of the step.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }

    /// The interpolated state at θ ∈ [0, 1].
    pub fn at_fraction(&self, th: f64) -> State {
        let mut y = [0.0; 4];
        match &self.kind {
            Kind::Power(q) => {
                for i in 0..4 {
                    let p = q[0][i] + th * (q[1][i] + th * (q[2][i] + th * q[3][i]));
                    y[i] = self.y0[i] + self.h * th * p;
                }
            }
            Kind::Dop853(f) => {
                let th1 = 1.0 - th;
                for i in 0..4 {
                    let mut acc = 0.0;
                    for (n, fk) in f.iter().rev().enumerate() {
                        acc += fk[i];
                        acc *= if n % 2 == 0 { th } else { th1 };
                    }
                    y[i] = self.y0[i] + acc;
                }
            }
            Kind::Hermite { y1, f0, f1 } => {
                let t2 = th * th;
                let t3 = t2 * th;
                let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
                let h10 = t3 - 2.0 * t2 + th;
                let h01 = -2.0 * t3 + 3.0 * t2;
                let h11 = t3 - t2;
                for i in 0..4 {
                    y[i] = h00 * self.y0[i]
                        + h10 * self.h * f0[i]
                        + h01 * y1[i]
                        + h11 * self.h * f1[i];
                }
            }
        }
        y
    }

    /// The interpolated state at time t.
    pub fn at(&self, t: f64) -> State {
        self.at_fraction((t - self.t0) / self.h)
    }
}
