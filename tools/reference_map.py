#!/usr/bin/env python3
"""An independent reference of the one-block map f: theta -> theta'.

What it computes
----------------
One iterate of the map f of docs' MODEL.md (/work/shared/MODEL.md in the
project's workspace; docs/model.md restates it), written from that page
alone and sharing no code with the Rust crate: a different language, a
different integrator (scipy's DOP853 through `solve_ivp`, rtol = atol =
1e-12, its own step control and event location), and a different
treatment of the stop. From it: orbits, and period-p cycles by Newton's
method with a finite-difference derivative.

Which equations (MODEL.md's section "One cycle: stick, then slip")
---------------------------------------------------------------------
- Onset at theta: P0 = (cos(theta)/kappa, sin(theta)), relative velocity 0.
  theta must lie on the exit arc kappa cos(theta) cos(theta_nu)
  + sin(theta) sin(theta_nu) > 0 ("Domain").
- Acceleration phase (rule 3), integrated in time t on the state
  (x, y, vrx, vry) (numerical notes: the relative velocity, not the lab
  one): x'' = -kappa x + Phi cos(phi_fr), y'' = -y + Phi sin(phi_fr),
  Phi = 1/(1 + 2 gamma v_r), phi_fr = pi + phi_el - Delta (1 - exp(-Omega
  v_r)), Delta = wrap(phi_el - phi_vr) in (-pi, pi]. It ends at the event
  v_r . (x'', y'') = 0 crossed from above (solve_ivp's event, direction -1;
  it is exactly 0 at the onset and solve_ivp does not fire there).
- Deceleration phase (rule 4): friction -Phi v_r/|v_r|. The stop, v_r = 0,
  is approached like a fractional power of (T - t) in t; this script
  integrates it instead in the time s with dt/ds = v_r, where the field
  d(v_r)/ds = v_r F_el - Phi v_r, d(x, y)/ds = v_r (v_r + V), dt/ds = v_r
  is smooth and v_r decays exponentially (the direction of v_r turns
  towards F_el at a rate |F_el|, not |F_el|/v_r); v_r is held in polar
  form (ln v_r, its direction), so the tolerance is relative all the way. It stops at the event
  v_r = 1e-9 * (peak v_r), then places the stop by the linear extrapolation
  T = t + v_r/|dv_r/dt| (an error O(v_r^2), below 1e-20 here). This is the
  same physics as MODEL.md states, and deliberately not the crate's
  treatment (capped steps and a cut-off near sqrt(tol)).
- Stop (rule 5): inside C the block sticks; on or outside C a new slip
  starts at once from the stop point, theta' = atan2(y, kappa x) of it
  (counted in the output as "restarted").
- Stick (rule 1): (x, y) = stop + V t until kappa^2 x^2 + y^2 = 1, the
  positive root of the quadratic in closed form, cancellation-free;
  theta' = atan2(y0, kappa x0) of the exit point.

The derivative f' and the multiplier of a cycle come from central
differences of f with a step of 1e-6 (error about 1e-6: enough to see a
multiplier pass -1, not to locate it better than that).

How to run
----------
Needs Python 3 with numpy and scipy (`pip install scipy`). Each iterate
takes a few hundredths of a second.

  python3 tools/reference_map.py examples
      MODEL.md's four worked examples, with this script's values beside.
  python3 tools/reference_map.py map --kappa 18.95 --gamma 6.5 --nu 1e-3 \\
      --theta-nu 1.0 --theta 0.5 0.3
      f at each theta (with --details: the slip's durations and stop).
  python3 tools/reference_map.py orbit --kappa 7 --gamma 4 --nu 1e-3 \\
      --theta-nu 1.2 --theta 0.5 --n 200 --keep 8
      An orbit: the last --keep of --n iterates.
  python3 tools/reference_map.py cycle --kappa 7 --gamma 4 --nu 1e-3 \\
      --theta-nu 1.29 --period 4 --theta 0.3
      A period-p cycle by Newton's method on f^p(theta) - theta from the
      seed, with its points and multiplier.

Parameters: --kappa, --gamma, --nu, --theta-nu, --omega (default 50).
"""

import argparse
import math
import sys

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-12
# The deceleration phase stops integrating at this fraction of the peak
# relative speed and extrapolates the rest linearly.
STOP_FRACTION = 1e-9
# Central-difference step for f'.
FD_STEP = 1e-6


def wrap(a):
    """a mapped into (-pi, pi]."""
    a = math.remainder(a, 2.0 * math.pi)
    return math.pi if a <= -math.pi else a


class Model:
    """The parameters of MODEL.md's table and the pieces of one cycle."""

    def __init__(self, kappa, gamma, nu, theta_nu, omega=50.0):
        self.kappa = kappa
        self.gamma = gamma
        self.nu = nu
        self.theta_nu = theta_nu
        self.omega = omega
        self.vx = nu * math.cos(theta_nu)
        self.vy = nu * math.sin(theta_nu)

    # -- rule 3: acceleration phase, time t, state (x, y, vrx, vry) --
    def accel_force(self, s):
        x, y, rx, ry = s
        k = self.kappa
        vr = math.hypot(rx, ry)
        phi_el = math.atan2(-y, -k * x)
        phi_vr = math.atan2(ry, rx)
        delta = wrap(phi_el - phi_vr)
        phi_fr = math.pi + phi_el + delta * math.expm1(-self.omega * vr)
        mag = 1.0 / (1.0 + 2.0 * self.gamma * vr)
        return (-k * x + mag * math.cos(phi_fr), -y + mag * math.sin(phi_fr))

    def accel_rhs(self, _t, s):
        ax, ay = self.accel_force(s)
        return [s[2] + self.vx, s[3] + self.vy, ax, ay]

    def accel_end(self, _t, s):
        ax, ay = self.accel_force(s)
        return s[2] * ax + s[3] * ay

    # -- rule 4: deceleration phase, time s with dt/ds = v_r, state
    #    (t, x, y, ln v_r, phi_vr): the relative velocity in polar form --
    def decel_rhs(self, _s, z):
        _, x, y, lnv, phi = z
        vr = math.exp(lnv)
        c, s = math.cos(phi), math.sin(phi)
        fx, fy = -self.kappa * x, -y
        mag = 1.0 / (1.0 + 2.0 * self.gamma * vr)
        return [
            vr,
            vr * (vr * c + self.vx),
            vr * (vr * s + self.vy),
            fx * c + fy * s - mag,
            fy * c - fx * s,
        ]

    def on_exit_arc(self, theta):
        return (
            self.kappa * math.cos(theta) * math.cos(self.theta_nu)
            + math.sin(theta) * math.sin(self.theta_nu)
            > 0.0
        )

    # -- rule 1: stick phase, closed form --
    def stick_exit(self, xs, ys):
        """Time until stop + V t reaches C, and the exit point."""
        k2 = self.kappa * self.kappa
        a = k2 * self.vx * self.vx + self.vy * self.vy
        b = k2 * xs * self.vx + ys * self.vy
        c = k2 * xs * xs + ys * ys - 1.0  # < 0 inside C
        disc = math.sqrt(b * b - a * c)
        t = -c / (b + disc) if b >= 0.0 else (disc - b) / a
        return t, xs + self.vx * t, ys + self.vy * t

    def slip(self, theta):
        """One slip from the onset at theta, then the stick phase.

        Returns a dict: theta_next, accel_duration, slip_duration, stop
        (x, y), peak_vr, stick_duration, restarted.
        """
        if not self.on_exit_arc(theta):
            raise ValueError(
                f"theta = {theta} is not on the exit arc "
                "kappa cos(theta) cos(theta_nu) + sin(theta) sin(theta_nu) > 0"
            )
        k = self.kappa
        s0 = [math.cos(theta) / k, math.sin(theta), 0.0, 0.0]
        def ev(t, s):
            return self.accel_end(t, s)

        ev.terminal = True
        ev.direction = -1
        acc = solve_ivp(
            self.accel_rhs, (0.0, 1e3), s0, method="DOP853",
            rtol=RTOL, atol=ATOL, events=ev,
        )
        if acc.status != 1:
            raise RuntimeError(f"acceleration phase did not end: {acc.message}")
        t1 = acc.t_events[0][0]
        x, y, rx, ry = acc.y_events[0][0]
        peak = math.hypot(rx, ry)
        cut = STOP_FRACTION * peak

        def stop_event(_s, z):
            return z[3] - ln_cut

        ln_cut = math.log(cut)
        stop_event.terminal = True
        stop_event.direction = -1
        z0 = [t1, x, y, math.log(peak), math.atan2(ry, rx)]
        dec = solve_ivp(
            self.decel_rhs, (0.0, 1e7), z0, method="DOP853",
            rtol=RTOL, atol=ATOL, events=stop_event,
        )
        if dec.status != 1:
            raise RuntimeError(f"deceleration phase did not stop: {dec.message}")
        t, x, y, lnv, phi = dec.y_events[0][0]
        vr = math.exp(lnv)
        rx, ry = vr * math.cos(phi), vr * math.sin(phi)
        mag = 1.0 / (1.0 + 2.0 * self.gamma * vr)
        # d v_r/dt = F_el . v_hat - Phi < 0 near the stop.
        dvdt = (-k * x * rx - y * ry) / vr - mag
        dt = -vr / dvdt
        t += dt
        x += (self.vx + 0.5 * rx) * dt
        y += (self.vy + 0.5 * ry) * dt
        out = {
            "accel_duration": t1,
            "slip_duration": t,
            "stop_x": x,
            "stop_y": y,
            "peak_vr": peak,
        }
        if k * k * x * x + y * y >= 1.0:
            out.update(theta_next=math.atan2(y, k * x), stick_duration=0.0,
                       restarted=True)
            return out
        ts, x0, y0 = self.stick_exit(x, y)
        out.update(theta_next=math.atan2(y0, k * x0), stick_duration=ts,
                   restarted=False)
        return out

    def f(self, theta):
        return self.slip(theta)["theta_next"]

    def fp(self, theta, p):
        """f^p(theta) and the points theta, f(theta), ..."""
        pts = [theta]
        for _ in range(p):
            pts.append(self.f(pts[-1]))
        return pts

    def derivative(self, theta):
        h = FD_STEP
        return wrap(self.f(theta + h) - self.f(theta - h)) / (2.0 * h)

    def cycle(self, seed, p, tol=1e-13, max_iter=40):
        """A period-p cycle by Newton on g = wrap(f^p(theta) - theta)."""
        theta = seed
        for _ in range(max_iter):
            g = wrap(self.fp(theta, p)[-1] - theta)
            h = FD_STEP
            gp = wrap(self.fp(theta + h, p)[-1] - self.fp(theta - h, p)[-1]) / (2 * h)
            step = -g / (gp - 1.0)
            theta = wrap(theta + step)
            if abs(step) < tol:
                break
        else:
            raise RuntimeError("Newton did not converge")
        pts = self.fp(theta, p)[:-1]
        m = 1.0
        for q in pts:
            m *= self.derivative(q)
        return pts, m, abs(wrap(self.fp(theta, p)[-1] - theta))


WORKED = [
    # kappa, gamma, nu, theta_nu, theta, theta', accel, slip, stop x, stop y, stick
    (18.95, 6.5, 1e-3, 1.0, 0.5, 0.2037551562, 1.125355434, 3.123143632,
     -0.003275131363, 0.1167625165, 101.7096366),
    (50, 6.5, 1e-4, 0.3, 0.3, 0.2995442543, 0.8136794637, 0.9852905504,
     0.01219639680, 0.2929463363, 72.36219612),
    (3, 0.5, 1e-3, 0.7, 0.9, 0.8971492439, 2.542307918, 3.629856483,
     0.2042770278, 0.7784606323, 4.798127107),
    (10, 6.5, 1e-3, 1.2, 1.0, -0.2667076065, 2.333676717, 3.782995674,
     -0.02635567172, -0.5794686934, 338.9469545),
]


def model_from(args):
    return Model(args.kappa, args.gamma, args.nu, args.theta_nu, args.omega)


def cmd_examples(_args):
    worst = 0.0
    for k, g, nu, tn, th, *ref in WORKED:
        r = Model(k, g, nu, tn).slip(th)
        got = [r["theta_next"], r["accel_duration"], r["slip_duration"],
               r["stop_x"], r["stop_y"], r["stick_duration"]]
        print(f"kappa={k} gamma={g} nu={nu} theta_nu={tn} theta={th}")
        for name, a, b in zip(
            ["theta'", "accel", "slip", "stop x", "stop y", "stick"], ref, got
        ):
            rel = abs(a - b) / max(abs(a), 1e-300)
            worst = max(worst, rel)
            print(f"  {name:7} MODEL.md {a:<18.12g} here {b:<20.15g} rel {rel:.1e}")
    print(f"worst relative difference {worst:.1e} (MODEL.md prints 10 digits)")


def cmd_map(args):
    m = model_from(args)
    for th in args.theta:
        r = m.slip(th)
        line = f"{th!r} {r['theta_next']!r}"
        if args.derivative:
            line += f" {m.derivative(th)!r}"
        if args.details:
            line += (f" accel={r['accel_duration']!r} slip={r['slip_duration']!r}"
                     f" stop=({r['stop_x']!r}, {r['stop_y']!r})"
                     f" stick={r['stick_duration']!r} restarted={r['restarted']}")
        print(line)


def cmd_orbit(args):
    m = model_from(args)
    th = args.theta[0]
    pts = []
    for _ in range(args.n):
        th = m.f(th)
        pts.append(th)
    for q in pts[-args.keep:]:
        print(repr(q))


def cmd_cycle(args):
    m = model_from(args)
    pts, mult, res = m.cycle(args.theta[0], args.period)
    order = sorted(range(len(pts)), key=lambda i: pts[i])
    print(f"period {args.period} residual {res:.1e} multiplier {mult!r}")
    for i in order:
        print(repr(pts[i]))


def main(argv=None):
    global RTOL, ATOL
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("examples", help="MODEL.md's worked examples")
    for name in ["map", "orbit", "cycle"]:
        p = sub.add_parser(name)
        p.add_argument("--kappa", type=float, required=True)
        p.add_argument("--gamma", type=float, required=True)
        p.add_argument("--nu", type=float, required=True)
        p.add_argument("--theta-nu", type=float, required=True)
        p.add_argument("--omega", type=float, default=50.0)
        p.add_argument("--theta", type=float, nargs="+", required=True)
        p.add_argument("--tol", type=float,
                       default=1e-12,
                       help="solve_ivp's rtol = atol (default 1e-12)")
        if name == "map":
            p.add_argument("--details", action="store_true")
            p.add_argument("--derivative", action="store_true")
        if name == "orbit":
            p.add_argument("--n", type=int, default=200)
            p.add_argument("--keep", type=int, default=8)
        if name == "cycle":
            p.add_argument("--period", type=int, required=True)
    args = ap.parse_args(argv)
    RTOL = ATOL = getattr(args, "tol", 1e-12)
    {"examples": cmd_examples, "map": cmd_map, "orbit": cmd_orbit,
     "cycle": cmd_cycle}[args.cmd](args)


if __name__ == "__main__":
    sys.exit(main())
