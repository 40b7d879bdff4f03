//! The interval extended to take in an iterate that left it: resolved like
//! the first interval ([`Resolve`]), in bounded pieces, so that an orbit on
//! a slice of time can pause in the middle of an extension.

use std::f64::consts::FRAC_PI_2;

use super::build::Resolve;
use super::{InterpolantError, MapInterpolant};
use crate::model::wrap_angle;

/// An extension of the interval under way ([`MapInterpolant::extension_to`]):
/// advanced by [`MapInterpolant::extend_step`], one bounded piece a call.
#[derive(Debug)]
pub struct Extension(Resolve);

impl MapInterpolant {
    /// The extension that takes θ in (with `pad` radians beyond it, kept
    /// inside the arc), within what is left of the piece budget; `None`
    /// when θ is inside already. Refused at once off the arc or with no
    /// pieces left.
    pub fn extension_to(
        &self,
        theta: f64,
        pad: f64,
    ) -> Result<Option<Extension>, InterpolantError> {
        let (lo, hi) = self.u_interval();
        let u = wrap_angle(theta - self.psi);
        if !(u > -FRAC_PI_2 && u < FRAC_PI_2) {
            return Err(InterpolantError::OffArc {
                lo: theta,
                hi: theta,
                arc_lo: self.psi - FRAC_PI_2,
                arc_hi: self.psi + FRAC_PI_2,
            });
        }
        let edge = FRAC_PI_2 - 1e-9;
        let (a, b) = if u < lo {
            ((u - pad).max(-edge).min(u), lo)
        } else if u >= hi {
            (hi, (u + pad).min(edge).max(u))
        } else {
            return Ok(None);
        };
        let left = self.opts.max_pieces.saturating_sub(self.pieces.len());
        if left == 0 || !(b > a) {
            return Err(InterpolantError::Unresolved {
                tol: self.opts.tol,
                max_pieces: self.opts.max_pieces,
                near: theta,
            });
        }
        Ok(Some(Extension(Resolve::new(a, b, left))))
    }

    /// One bounded piece of `ext` (the build's pieces: a chunk of samples,
    /// a piece settled or checked); true once the new pieces are in, and
    /// `ext` must not be advanced again. An error refuses the extension:
    /// the interval stays as it was.
    pub fn extend_step(&mut self, ext: &mut Extension) -> Result<bool, InterpolantError> {
        match self.advance(&mut ext.0)? {
            Some(new) => {
                self.insert(new);
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// Extends the interval to take in θ, all at once
    /// ([`Self::extension_to`] and [`Self::extend_step`] in pieces).
    /// Nothing changes when it is refused.
    pub fn extend_to(&mut self, theta: f64, pad: f64) -> Result<(), InterpolantError> {
        if let Some(mut ext) = self.extension_to(theta, pad)? {
            while !self.extend_step(&mut ext)? {}
        }
        Ok(())
    }
}

/// How a run keeps its iterates on the interpolant: the interval extended
/// to an iterate that leaves it, once per excursion, until an extension is
/// refused (the iterates out there are then integrated); the extension in
/// flight, if a piece of one was made and the run paused.
#[derive(Debug, Default)]
pub struct Cover {
    extending: Option<Extension>,
    /// Why an extension was refused, if one was.
    pub refused: Option<String>,
    /// Extensions made.
    pub extensions: usize,
}

impl Cover {
    /// One bounded piece towards θ inside `interp`'s interval (padded by
    /// `pad`): true once there is nothing more to do for θ (inside, newly
    /// taken in, or refused: the caller evaluates, from the series or
    /// integrated), false after a piece of an extension (the caller asks
    /// again with the same θ, now or after a pause). Asked until true, it
    /// does what one blocking extension does.
    pub fn piece(&mut self, interp: &mut MapInterpolant, theta: f64, pad: f64) -> bool {
        let mut ext = match self.extending.take() {
            Some(ext) => ext,
            None => {
                let (lo, hi) = interp.interval();
                let u = wrap_angle(theta - lo) + lo;
                if self.refused.is_some() || (u >= lo && u <= hi) {
                    return true;
                }
                match interp.extension_to(theta, pad) {
                    Ok(Some(ext)) => ext,
                    Ok(None) => {
                        self.extensions += 1;
                        return true;
                    }
                    Err(e) => {
                        self.refused = Some(e.to_string());
                        return true;
                    }
                }
            }
        };
        match interp.extend_step(&mut ext) {
            Ok(true) => {
                self.extensions += 1;
                true
            }
            Ok(false) => {
                self.extending = Some(ext);
                false
            }
            Err(e) => {
                self.refused = Some(e.to_string());
                true
            }
        }
    }

    /// What the series give at θ (`f` of the interpolant), after a piece
    /// of the interval's extension to θ if θ is outside it: the series'
    /// value, a piece of the extension made (ask again with the same θ), or
    /// no verified series there (integrate).
    pub fn reach<T>(
        &mut self,
        interp: &mut MapInterpolant,
        theta: f64,
        pad: f64,
        f: impl Fn(&MapInterpolant) -> Option<T>,
    ) -> Reach<T> {
        if let Some(r) = f(interp) {
            return Reach::Series(r);
        }
        if !self.piece(interp, theta, pad) {
            return Reach::Extending;
        }
        match f(interp) {
            Some(r) => Reach::Series(r),
            None => Reach::Direct,
        }
    }
}

/// Where a run's next iterate comes from ([`Cover::reach`]).
pub enum Reach<T> {
    /// The verified series' value.
    Series(T),
    /// A piece of an extension was made; θ is not reached yet.
    Extending,
    /// No verified series at θ: integrate.
    Direct,
}
