"""examples/wheeled_pendulum.toml against an independent model: the same robot written with SymPy's
KanesMethod (frames, points, rigid bodies, the rolling conditions as velocity constraints, the
motor torques as equal and opposite torques on body and wheel), integrated with SciPy's solve_ivp.

A driven, turning run (constant unequal torques from a forward tilt) must agree with `nhc simulate`
to integration error, and the upright linearization's eigenvalues must agree with the SymPy
model's (Kane's equations linearized about the upright by finite differences of its state
derivative: the pitch mode +-sqrt(a) and zeros).

Usage: wheeled_pendulum_sympy.py NHC SCENE WORKDIR
"""
import csv
import json
import os
import subprocess
import sys

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp

nhc, scene, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)

P = dict(mb=2.0, l=0.3, Ib1=0.06, Ib2=0.05, Ib3=0.03, mw=0.5, r=0.1, d=0.15, g=9.81)
P["Ja"] = P["mw"] * P["r"] ** 2 / 2
P["Jd"] = P["mw"] * P["r"] ** 2 / 4

# --- the SymPy model ------------------------------------------------------------------------------
q = me.dynamicsymbols("x y psi th phL phR")
u = me.dynamicsymbols("uth uL uR")
x, y, psi, th, phL, phR = q
uth, uL, uR = u
mb, l, Ib1, Ib2, Ib3, mw, r, d, Ja, Jd, g, TL, TR = sp.symbols("mb l Ib1 Ib2 Ib3 mw r d Ja Jd g TL TR")
# The rolling conditions solved by hand for the minimal speeds (th', phL', phR'): forward speed
# r (phL' + phR')/2, yaw rate r (phR' - phL')/(2 d); checked below against the contact velocities.
v = r * (uL + uR) / 2
w = r * (uR - uL) / (2 * d)

N = me.ReferenceFrame("N")
H = N.orientnew("H", "Axis", (psi, N.z))
B = H.orientnew("B", "Axis", (th, H.y))
WL = H.orientnew("WL", "Axis", (phL, H.y))
WR = H.orientnew("WR", "Axis", (phR, H.y))
H.set_ang_vel(N, w * N.z)
B.set_ang_vel(H, uth * H.y)
WL.set_ang_vel(H, uL * H.y)
WR.set_ang_vel(H, uR * H.y)

O = me.Point("O")
O.set_vel(N, 0)
C = O.locatenew("C", x * N.x + y * N.y + r * N.z)
C.set_vel(N, v * H.x)
Bo = C.locatenew("Bo", l * B.z)
Bo.v2pt_theory(C, N, B)
CL = C.locatenew("CL", d * H.y)
CL.v2pt_theory(C, N, H)
CR = C.locatenew("CR", -d * H.y)
CR.v2pt_theory(C, N, H)
PL = CL.locatenew("PL", -r * N.z)
PL.v2pt_theory(CL, N, WL)
PR = CR.locatenew("PR", -r * N.z)
PR.v2pt_theory(CR, N, WR)
for contact in (PL, PR):  # the contact material points do not move: rolling without slipping
    assert all(sp.simplify(contact.vel(N).dot(e)) == 0 for e in (N.x, N.y, N.z))

body = me.RigidBody("body", Bo, B, mb, (me.inertia(B, Ib1, Ib2, Ib3), Bo))
left = me.RigidBody("left", CL, WL, mw, (me.inertia(WL, Jd, Ja, Jd), CL))
right = me.RigidBody("right", CR, WR, mw, (me.inertia(WR, Jd, Ja, Jd), CR))
loads = [(Bo, -mb * g * N.z), (CL, -mw * g * N.z), (CR, -mw * g * N.z),
         (WL, TL * H.y), (WR, TR * H.y), (B, -(TL + TR) * H.y)]
kinematics = [x.diff() - v * sp.cos(psi), y.diff() - v * sp.sin(psi), psi.diff() - w,
              th.diff() - uth, phL.diff() - uL, phR.diff() - uR]
kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kinematics)
kane.kanes_equations([body, left, right], loads)
symbols = [mb, l, Ib1, Ib2, Ib3, mw, r, d, Ja, Jd, g]
values = dict(zip(symbols, [P[str(s)] for s in symbols]))
M = kane.mass_matrix_full.subs(values)
F = kane.forcing_full.subs(values)
state = list(q) + list(u)
Mf = sp.lambdify([state, [TL, TR]], M, "numpy")
Ff = sp.lambdify([state, [TL, TR]], F, "numpy")


def rhs(_t, z, torques):
    return np.linalg.solve(np.asarray(Mf(z, torques), float), np.asarray(Ff(z, torques), float).ravel())


# --- a driven turning run -------------------------------------------------------------------------
torques = [0.2, -0.1]
t_end = 0.3
z0 = np.zeros(9)
z0[3] = 0.05  # th, as in the scene's [initial]; at rest, so every speed is 0 and the constraints hold
ref = solve_ivp(rhs, (0, t_end), z0, args=(torques,), rtol=1e-12, atol=1e-13, method="DOP853",
                dense_output=True)
assert ref.success, ref.message

out = os.path.join(work, "driven.csv")
subprocess.run([nhc, "simulate", scene, "--input", f"TL={torques[0]}", "--input", f"TR={torques[1]}",
                "--t-end", str(t_end), "--outputs", "50", "-o", out], check=True)
with open(out) as f:
    rows = list(csv.DictReader(f))
names = ["x", "y", "psi", "th", "phL", "phR"]
rates = ["x'", "y'", "psi'", "th'", "phL'", "phR'"]
worst = 0.0
for row in rows:
    t = float(row["t"])
    zr = ref.sol(t)
    mine = np.array([float(row[n]) for n in names + ["th'", "phL'", "phR'"]])
    worst = max(worst, float(np.max(np.abs(mine - zr))))
    speed = P["r"] * (zr[7] + zr[8]) / 2  # x' from the rolling conditions
    worst = max(worst, abs(float(row["x'"]) - speed * np.cos(zr[2])))
moved = ref.sol(t_end)
print(f"driven run: x={moved[0]:.4f} y={moved[1]:.4f} psi={moved[2]:.4f} th={moved[3]:.4f}; "
      f"largest difference to SymPy+solve_ivp {worst:.2e}")
assert abs(moved[2]) > 0.1 and abs(moved[1]) > 1e-3, "the test run does not turn"
assert worst < 1e-7, worst

# --- the upright linearization: A and B over nhc's own state names ------------------------------
# Central differences of the SymPy model's state derivative in (q, th', phL', phR').
index = {"x": 0, "y": 1, "psi": 2, "th": 3, "phL": 4, "phR": 5, "th'": 6, "phL'": 7, "phR'": 8}
lin = subprocess.run([nhc, "linearize", scene, "--at", "th=0", "--format", "json"], check=True,
                     capture_output=True, text=True)
data = json.loads(lin.stdout)
keep = [index[n] for n in data["states"]]
A = np.array(data["A"], float)
Bm = np.array(data["B"], float)
h = 1e-6
As = np.zeros((9, 9))
Bs = np.zeros((9, 2))
for k in range(9):
    e = np.zeros(9)
    e[k] = h
    As[:, k] = (rhs(0, e, [0, 0]) - rhs(0, -e, [0, 0])) / (2 * h)
for k in range(2):
    e = np.zeros(2)
    e[k] = h
    Bs[:, k] = (rhs(0, np.zeros(9), e) - rhs(0, np.zeros(9), -e)) / (2 * h)
As = As[np.ix_(keep, keep)]
Bs = Bs[keep, :]
print("states", data["states"])
print("A difference", np.max(np.abs(A - As)), "B difference", np.max(np.abs(Bm - Bs)))
assert np.max(np.abs(A - As)) < 1e-6 * (1 + np.max(np.abs(As))), (A, As)
assert np.max(np.abs(Bm - Bs)) < 1e-6 * (1 + np.max(np.abs(Bs))), (Bm, Bs)

# --- a feedback law in [inputs], compiled into the equations -------------------------------------
# An LQR state feedback (gains rounded from scipy's continuous ARE on the A, B above) written as the
# scene's [inputs] laws; the same law closed around the SymPy model. From a 0.3 rad tilt, 2 s.
law_L = "0.7*psi + 11*th + 2.4*th' - 0.01*phL' + 0.33*phR'"
law_R = "-0.7*psi + 11*th + 2.4*th' + 0.33*phL' - 0.01*phR'"
text = open(scene).read()
text = text.replace('TL = "0"', f'TL = "{law_L}"').replace('TR = "0"', f'TR = "{law_R}"')
text = text.replace("th = [0.05, 0.0]", "th = [0.3, 0.0]")
closed_scene = os.path.join(work, "wheeled_pendulum_lqr.toml")
with open(closed_scene, "w") as f:
    f.write(text)


def law(z):
    psi_, th_, dth, dL, dR = z[2], z[3], z[6], z[7], z[8]
    return [0.7 * psi_ + 11 * th_ + 2.4 * dth - 0.01 * dL + 0.33 * dR,
            -0.7 * psi_ + 11 * th_ + 2.4 * dth + 0.33 * dL - 0.01 * dR]


z0 = np.zeros(9)
z0[3] = 0.3
t_end = 2.0
ref = solve_ivp(lambda t, z: rhs(t, z, law(z)), (0, t_end), z0, rtol=1e-12, atol=1e-13, method="DOP853",
                dense_output=True)
assert ref.success, ref.message
out = os.path.join(work, "closed.csv")
subprocess.run([nhc, "simulate", closed_scene, "--t-end", str(t_end), "--outputs", "40", "-o", out], check=True)
with open(out) as f:
    rows = list(csv.DictReader(f))
worst = 0.0
for row in rows:
    zr = ref.sol(float(row["t"]))
    mine = np.array([float(row[n]) for n in names + ["th'", "phL'", "phR'"]])
    worst = max(worst, float(np.max(np.abs(mine - zr))))
final = ref.sol(t_end)
print(f"closed loop from th = 0.3: th({t_end}) = {final[3]:.2e}; largest difference to SymPy+solve_ivp {worst:.2e}")
assert abs(final[3]) < 0.01, "the law does not hold the pendulum up"
assert worst < 1e-7, worst

# A law of an acceleration is an algebraic loop: refused, exit 2, at the input.
looped = os.path.join(work, "algebraic_loop.toml")
with open(looped, "w") as f:
    f.write(text.replace(f'TL = "{law_L}"', 'TL = "3*th' + "''" + '"'))
bad = subprocess.run([nhc, "simulate", looped], capture_output=True, text=True)
print(bad.stderr.strip())
assert bad.returncode == 2 and "algebraic loop" in bad.stderr and "algebraic_loop.toml:" in bad.stderr
# --input on an input the scene closes by a law would drive nothing: refused, exit 2, naming the flag.
bad = subprocess.run([nhc, "simulate", closed_scene, "--input", "TL=0"], capture_output=True, text=True)
assert bad.returncode == 2 and "--input" in bad.stderr and "feedback law" in bad.stderr, bad.stderr
print("ok")
