"""Step counts of the acceleration phase: today's 4-variable field against
the 8-variable formulation that carries the friction direction (cos φ_fr,
sin φ_fr), Δ and e^(-Ω v_r) as state (docs/history.md, "What was tried and not kept").

Both run under SciPy's DOP853 (its own controller, not ours: the comparison
is between the formulations, not with oneblock's figures), from onsets on
the Fig. 3b attractor to the end of the acceleration phase, against a
reference at tol 1e-13. The 8-variable system is singular at v_r = 0, so
it starts at t1 from the 4-variable solution. Its four extra variables are
either left out of the error norm ("excl") or measured like the rest
("incl").

    pip install scipy numpy && python3 docs/experiments/augmented_steps.py

The output when measured: with the extra variables left out of the norm the step
count is the same but the end state is 10-100x less accurate; measured,
the accuracy is back and the step count is 1.7-1.9x. At 24 against 44 ns
per evaluation (a criterion prototype of the 8-variable field, since
removed from benches/map_iterate.rs; it is in git history) that
is no gain, so the formulation was not built.
"""
import math, numpy as np
from scipy.integrate import solve_ivp
k,g,om,nu,tn=18.95,6.5,50.0,1e-3,1.25
V=np.array([nu*math.cos(tn),nu*math.sin(tn)])
def wrap(a): return (a+math.pi)%(2*math.pi)-math.pi
def f4(t,s):
    x,y,a,b=s
    fx,fy=-k*x,-y
    vr=math.hypot(a,b)
    D=math.atan2(a*fy-b*fx,a*fx+b*fy) if vr>0 else 0.0
    turn=-D*(-math.expm1(-om*vr))
    P=1/(1+2*g*vr); F=math.hypot(fx,fy); ex,ey=fx/F,fy/F
    cs,sn=math.cos(turn),math.sin(turn)
    return [a+V[0],b+V[1],fx-P*(ex*cs-ey*sn),fy-P*(ex*sn+ey*cs)]
def f8(t,s):
    x,y,a,b,c,sn,delta,e=s
    fx,fy=-k*x,-y
    q=a*a+b*b; vr=math.sqrt(q)
    phi=1/(1+2*g*vr)
    ax,ay=fx+phi*c,fy+phi*sn
    xd,yd=a+V[0],b+V[1]
    dfx,dfy=-k*xd,-yd
    dphi_el=(fx*dfy-fy*dfx)/(fx*fx+fy*fy)
    dphi_v=(a*ay-b*ax)/q
    dvr=(a*ax+b*ay)/vr
    dd=dphi_el-dphi_v
    de=-om*e*dvr
    dpf=dphi_el-dd*(1-e)+delta*de
    return [xd,yd,ax,ay,-sn*dpf,c*dpf,dd,de]
def aux(s):
    x,y,a,b=s
    fx,fy=-k*x,-y
    vr=math.hypot(a,b)
    D=math.atan2(a*fy-b*fx,a*fx+b*fy)
    e=math.exp(-om*vr)
    pf=math.pi+math.atan2(fy,fx)-D*(1-e)
    return [x,y,a,b,math.cos(pf),math.sin(pf),D,e]
def growth4(t,s):
    d=f4(t,s); return s[2]*d[2]+s[3]*d[3]
def growth8(t,s):
    d=f8(t,s); return s[2]*d[2]+s[3]*d[3]
def run(theta,tol):
    s0=[math.cos(theta)/k,math.sin(theta),0.0,0.0]
    ev4=lambda t,s: growth4(t,s) if t>1e-3 else 1.0
    ev4.terminal=True; ev4.direction=-1
    ref=solve_ivp(f4,(0,5),s0,method='DOP853',rtol=1e-13,atol=1e-13,events=ev4,dense_output=True)
    tend=ref.t_events[0][0]; yend=ref.y_events[0][0]
    out={}
    atol4=np.array([tol/k,tol,tol/math.sqrt(k),tol])
    r4=solve_ivp(f4,(0,5),s0,method='DOP853',rtol=tol,atol=atol4,events=ev4,first_step=0.01/math.sqrt(k))
    e4=np.max(np.abs((r4.y_events[0][0]-yend)*np.array([k,1,math.sqrt(k),1])))
    out['alg']=(r4.nfev,len(r4.t)-1,e4)
    # 8-dim from t1: take the algebraic solution at t1 from the reference dense output (exact start)
    for t1 in (0.01,0.05):
        s1=ref.sol(t1)
        ev8=lambda t,s: growth8(t,s)
        ev8.terminal=True; ev8.direction=-1
        for aux_w in ('excl','incl'):
            at=np.concatenate([atol4,[1e10]*4 if aux_w=='excl' else [tol]*4])
            # the part before t1 with the 4-dim system at tol, to count its cost too
            r0=solve_ivp(f4,(0,t1),s0,method='DOP853',rtol=tol,atol=atol4,first_step=0.01/math.sqrt(k))
            r8=solve_ivp(f8,(t1,5),aux(r0.y[:,-1]),method='DOP853',rtol=tol if aux_w=='incl' else tol,atol=at,events=ev8)
            e8=np.max(np.abs((r8.y_events[0][0][:4]-yend)*np.array([k,1,math.sqrt(k),1])))
            out[f'aug t1={t1} aux {aux_w}']=(r0.nfev+r8.nfev,len(r0.t)-1+len(r8.t)-1,e8)
    return tend,out
for tol in (1e-8,1e-10):
    for theta in (0.45,0.40):
        tend,out=run(theta,tol)
        print(f"tol {tol:g} theta {theta} accel end {tend:.4f}")
        for kk,v in out.items(): print(f"   {kk:24s} nfev {v[0]:5d} steps {v[1]:4d} err(end state, kx-weighted) {v[2]:.1e}")
