#!/usr/bin/env python3
"""PASIBOT geometry for models/pasibot.yaml (plain python3, no third-party modules).

Solves the mechanism of ../shared/pasibot.md (a path from the repository root) directly, point by
point, by circle and line intersections (lengths in units of the crank length l8, hip frame:
origin A, x axis A->B, y up):

  Chebyshev   P = (cos th8, sin th8); M: |PM| = |BM| = 2.5, below the line P-B; C = 2M - P
  pantograph  K: |CK| = 3, |DK| = 6 (branch: the seed's eq. 7); J = C + 3(K - C);
              E = 3D - 2C; L = J + (E - J)/3
  stabiliser  S on y = -4 with |CS| = 4.2, ahead of C; R = S + (J - C); F = R + (E - J)

The flying leg is the same mechanism at th8 + pi (seed eq. 10); its points carry a suffix p.

It prints
  1. the hip-frame positions of all points at the model's t0 (th8 = pi/2),
  2. the body angles in the hip frame and in the support-foot (ground) frame at t0, which are
     the `assembly:` hints of models/pasibot.yaml (seed eq. 11: th_ground = th_hip - th1_hip),
and checks, over the support phase th8 in [pi/2, 3pi/2] (and the whole turn where it says so),
  - the loop equations (3)-(5) of the seed (with eq. 4's missing factor 2.5 restored),
  - the closed forms (6) and (8) and a corrected (7) against the direct solution,
  - the parallelisms (9), the rigid link lengths and the parallelograms,
  - the claims of pasibot.md (straight line of C, stride, hip tilt, flying-foot lift).
With a path argument (default models/pasibot.yaml, when PyYAML is importable) it also checks
that every body of the model carries its points where this geometry puts them, with the body
angle equal to the hint, and that the joints and drivers count up to the mobility of one.

Exit status 1 when a check fails.
"""

import cmath
import math
import os
import re
import sys

TOL = 1e-12
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


# ---------------------------------------------------------------------------------------------
# Geometry (complex numbers: x + j y, hip frame, units of l8)

A = 0j
B = 2 + 0j
D = 2 - 12j
SLOT_Y = -4.0


def cross(u, v):
    return u.real * v.imag - u.imag * v.real


def circles(p0, r0, p1, r1):
    """Both intersections of the circles (p0, r0) and (p1, r1)."""
    d = abs(p1 - p0)
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h2 = r0 * r0 - a * a
    if h2 < 0:
        raise ValueError("circles do not meet")
    h = math.sqrt(h2)
    u = (p1 - p0) / d
    base = p0 + a * u
    return base + h * 1j * u, base - h * 1j * u


def solve_leg(th8):
    """All points of one leg for the crank angle th8 (hip frame)."""
    P = cmath.exp(1j * th8)
    m1, m2 = circles(P, 2.5, B, 2.5)
    # below the line P-B: on the right of the direction P->B (which points to +x)
    M = m1 if cross(B - P, m1 - P) < 0 else m2
    C = 2 * M - P
    k1, k2 = circles(C, 3.0, D, 6.0)
    # branch of the seed's eq. (7): K on the left of the direction C->D (toward +x), so the knee
    # J = C + 3(K - C) is ahead of the leg (+x, the walking direction)
    K = k1 if cross(D - C, k1 - C) > 0 else k2
    J = C + 3 * (K - C)
    E = 3 * D - 2 * C
    L = J + (E - J) / 3
    dy = SLOT_Y - C.imag
    S = complex(C.real + math.sqrt(4.2 ** 2 - dy * dy), SLOT_Y)
    R = S + (J - C)
    F = R + (E - J)
    return dict(P=P, M=M, C=C, K=K, J=J, E=E, L=L, S=S, R=R, F=F)


def ang(z):
    return math.atan2(z.imag, z.real)


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def leg_angles(th8, pt):
    """Seed angles (hip frame) of one leg; each is the body angle of the model's link frame."""
    return {
        "8": th8,                       # crank, A->P
        "7": ang(pt["P"] - pt["M"]),    # coupler, M->P (pasibot.md)
        "9": ang(B - pt["M"]),          # rocker, M->B (pasibot.md)
        "6": ang(pt["K"] - D),          # upper tendon, D->K (pasibot.md)
        "3": ang(pt["C"] - pt["K"]),    # femur, K->C (pasibot.md)
        "10": ang(pt["S"] - pt["C"]),   # stabiliser, C->S (pasibot.md)
        "1": ang(pt["F"] - pt["E"]),    # foot, E->F (= th10 by eq. 9)
        "5": ang(pt["R"] - pt["J"]),    # knee link, J->R (= th10)
        "12": ang(pt["S"] - pt["R"]),   # stabiliser upright, R->S (= th3)
        "4": ang(D - pt["L"]),          # lower tendon, L->D (= th3)
        "2": ang(pt["J"] - pt["E"]),    # tibia, E->J (= th6)
        "11": ang(pt["R"] - pt["F"]),   # rear leg bar, F->R (= th6)
    }


# ---------------------------------------------------------------------------------------------
# The seed's closed forms

def seed_eq6(th8):
    c, s = math.cos(th8), math.sin(th8)
    root = math.sqrt(-16 * c * c - 60 * c + 100)
    th7 = math.acos((-4 * c * c + 13 * c - 10 + s * root) / (25 - 20 * c))
    th9 = math.acos((-4 * c * c + 13 * c - 10 - s * root) / (-25 + 20 * c))
    return th7, th9


def seed_eq7(th7, th9, as_printed=False):
    """Eq. (7). The printed version misplaces a parenthesis twice: in A it reads
    (2.5 sin th7 + sin th9 - 12)^2 and in th6 it multiplies the root by 2.5 (sin th7 + sin th9
    - 12); the corrected version uses v = 2.5 (sin th7 + sin th9) - 12 in both places."""
    u = 2.5 * (math.cos(th7) + math.cos(th9))
    v = 2.5 * (math.sin(th7) + math.sin(th9)) - 12
    if as_printed:
        Ap = u * u + (2.5 * math.sin(th7) + math.sin(th9) - 12) ** 2
        vp = 2.5 * (math.sin(th7) + math.sin(th9) - 12)
        th6 = math.acos((u * (-27 - Ap) - vp * math.sqrt(max(0.0, 144 * Ap - (-27 - Ap) ** 2)))
                        / (12 * Ap))
        th3 = math.acos((u * (27 - Ap) + v * math.sqrt(max(0.0, 36 * Ap - (27 - Ap) ** 2)))
                        / (6 * Ap))
        return th6, th3
    A_ = u * u + v * v
    th6 = math.acos((u * (-27 - A_) - v * math.sqrt(144 * A_ - (27 + A_) ** 2)) / (12 * A_))
    th3 = math.acos((u * (27 - A_) + v * math.sqrt(36 * A_ - (27 - A_) ** 2)) / (6 * A_))
    return th6, th3


def seed_eq8(th7, th8):
    return math.asin((5 * math.sin(th7) - math.sin(th8) - 4) / 4.2)


# ---------------------------------------------------------------------------------------------
# Checks over the support phase

RIGID = [  # (leg points or hip points, length): every link's rigid distances
    ("P", "M", 2.5), ("M", "C", 2.5), ("P", "C", 5.0), ("B", "M", 2.5), ("A", "P", 1.0),
    ("C", "K", 3.0), ("K", "J", 6.0), ("C", "J", 9.0), ("D", "K", 6.0),
    ("J", "L", 6.0), ("L", "E", 12.0), ("J", "E", 18.0), ("D", "L", 6.0),
    ("C", "S", 4.2), ("S", "R", 9.0), ("J", "R", 4.2), ("R", "F", 18.0), ("E", "F", 4.2),
]


def pos(pt, name):
    return {"A": A, "B": B, "D": D}.get(name, pt.get(name))


def check_leg(th8, label):
    pt = solve_leg(th8)
    th = leg_angles(th8, pt)
    e = cmath.exp
    j = 1j
    # loop equations (3)-(5); x = horizontal distance from A to S
    r3 = 2.5 * e(j * th["7"]) - 2.5 * e(j * th["9"]) - e(j * th8) + 2
    r4 = (6 * e(j * th["6"]) + 3 * e(j * th["3"]) + 2.5 * e(j * th["7"]) + 2.5 * e(j * th["9"])
          - 12j)
    x = pt["S"].real
    r5 = 4.2 * e(j * th["10"]) - 5 * e(j * th["7"]) + e(j * th8) - x + 4j
    worst = max(abs(r3), abs(r4), abs(r5))
    check(worst < TOL, f"{label}: loop equations (3)-(5) residual {worst:.2e}")
    # closed forms
    th7, th9 = seed_eq6(th8)
    d6 = max(abs(wrap(th7 - th["7"])), abs(wrap(th9 - th["9"])))
    th6, th3 = seed_eq7(th7, th9)
    d7 = max(abs(wrap(th6 - th["6"])), abs(wrap(th3 - th["3"])))
    d8 = abs(wrap(seed_eq8(th7, th8) - th["10"]))
    # parallelisms (9)
    d9 = max(abs(wrap(th["1"] - th["10"])), abs(wrap(th["5"] - th["10"])),
             abs(wrap(th["12"] - th["3"])), abs(wrap(th["4"] - th["3"])),
             abs(wrap(th["2"] - th["6"])), abs(wrap(th["11"] - th["6"])))
    check(d9 < TOL, f"{label}: parallelisms (9) off by {d9:.2e}")
    # rigid distances
    dl = max(abs(abs(pos(pt, a) - pos(pt, b)) - l) for a, b, l in RIGID)
    check(dl < TOL, f"{label}: rigid distances off by {dl:.2e}")
    # collinear points on a link: M, C on P's line; K, J on the femur; L on the tibia
    col = max(abs(cross(pt["C"] - pt["P"], pt["M"] - pt["P"])),
              abs(cross(pt["J"] - pt["C"], pt["K"] - pt["C"])),
              abs(cross(pt["E"] - pt["J"], pt["L"] - pt["J"])))
    check(col < TOL, f"{label}: collinearity off by {col:.2e}")
    return pt, th, d6, d7, d8


def frange(a, b, n):
    return [a + (b - a) * i / n for i in range(n + 1)]


def to_ground(z, pt):
    """Hip-frame point -> support-foot frame (origin E, x axis E->F)."""
    return (z - pt["E"]) * cmath.exp(-1j * ang(pt["F"] - pt["E"]))


def main():
    n = 720
    worst6 = worst7 = worst8 = 0.0
    worst7_printed = 0.0
    cy_min, cy_max = 1e9, -1e9
    cx = []
    tilt = 0.0
    lift = 0.0
    ex = []
    for th8 in frange(math.pi / 2, 3 * math.pi / 2, n):
        pt, th, d6, d7, d8 = check_leg(th8, f"support th8={th8:.4f}")
        ptf, thf, f6, f7, f8 = check_leg(th8 + math.pi, f"flying th8={th8:.4f}")
        worst6 = max(worst6, d6)
        worst7 = max(worst7, d7)
        worst8 = max(worst8, d8)
        p6, p3 = seed_eq7(*seed_eq6(th8), as_printed=True)
        worst7_printed = max(worst7_printed, abs(wrap(p6 - th["6"])), abs(wrap(p3 - th["3"])))
        cy_min = min(cy_min, pt["C"].imag)
        cy_max = max(cy_max, pt["C"].imag)
        cx.append(pt["C"].real)
        ex.append(pt["E"].real)
        tilt = max(tilt, abs(th["10"]))
        lift = max(lift, to_ground(ptf["E"], pt).imag, to_ground(ptf["F"], pt).imag)
    # the closed forms are branch-exact on the support phase only where acos/asin cover it;
    # report them over the whole turn as well (the flying leg uses them at th8 + pi)
    worst6_turn = worst7_turn = worst8_turn = 0.0
    slot_x = []
    for th8 in frange(0, 2 * math.pi, 4 * n):
        pt, th, d6, d7, d8 = check_leg(th8, f"turn th8={th8:.4f}")
        worst6_turn = max(worst6_turn, d6)
        worst7_turn = max(worst7_turn, d7)
        worst8_turn = max(worst8_turn, d8)
        slot_x.append(pt["S"].real)

    print("PASIBOT geometry, hip frame (origin A, x axis A->B), units of l8")
    print()
    print("Checks over the support phase th8 in [pi/2, 3pi/2] (%d intervals):" % n)
    print("  loop equations (3)-(5), parallelisms (9), rigid lengths: residual < %.0e" % TOL)
    print("  closed form (6) vs direct solution:            %.2e" % worst6)
    print("  closed form (7), parentheses corrected:         %.2e" % worst7)
    print("  closed form (7), as printed in the seed:        %.2e" % worst7_printed)
    print("  closed form (8) vs direct solution:             %.2e" % worst8)
    print("Same over a whole crank turn (the flying leg's range too):")
    print("  (6) %.2e   (7 corrected) %.2e   (8) %.2e" % (worst6_turn, worst7_turn, worst8_turn))
    check(worst6 < 1e-9 and worst6_turn < 1e-9, "closed form (6)")
    check(worst7 < 1e-9 and worst7_turn < 1e-9, "closed form (7) corrected")
    check(worst8 < 1e-9 and worst8_turn < 1e-9, "closed form (8)")
    print()
    print("Support phase, as pasibot.md states it:")
    print("  C.y in [%.5f, %.5f] (straight within %.4f)" % (cy_min, cy_max, cy_max - cy_min))
    print("  C.x from %.4f to %.4f; foot E.x from %.4f to %.4f (stride %.4f)"
          % (cx[0], cx[-1], ex[0], ex[-1], ex[0] - ex[-1]))
    print("  hip tilt max |th10| = %.5f rad" % tilt)
    print("  flying foot max height above the floor = %.4f" % lift)
    print("  slot: S.x in [%.4f, %.4f] over a whole turn" % (min(slot_x), max(slot_x)))
    print("  hip height (A above the support foot) at t0 = %.4f"
          % to_ground(A, solve_leg(math.pi / 2)).imag)

    th8 = math.pi / 2
    sup = solve_leg(th8)
    fly = solve_leg(th8 + math.pi)
    tsup = leg_angles(th8, sup)
    tfly = leg_angles(th8 + math.pi, fly)
    th1 = tsup["1"]
    print()
    print("Points at t0 (th8 = pi/2), hip frame, units of l8:")
    print("  %-3s (%9.5f, %9.5f)" % ("A", A.real, A.imag))
    print("  %-3s (%9.5f, %9.5f)" % ("B", B.real, B.imag))
    print("  %-3s (%9.5f, %9.5f)" % ("D", D.real, D.imag))
    for k in "PMCKJLESRF":
        z, zp = sup[k], fly[k]
        print("  %-3s (%9.5f, %9.5f)    %-3s (%9.5f, %9.5f)"
              % (k, z.real, z.imag, k + "p", zp.real, zp.imag))
    print()
    print("Body angles at t0: hip frame, and foot (ground) frame = hip - th1_hip (th1_hip = %.6f)"
          % th1)
    hints = {"l13": wrap(0.0 - th1)}
    print("  %-5s hip %9.5f   ground %9.5f" % ("l13", 0.0, hints["l13"]))
    for i in ["8", "7", "9", "6", "3", "10", "1", "5", "12", "4", "2", "11"]:
        hints["l" + i] = wrap(tsup[i] - th1)
        line = "  %-5s hip %9.5f   ground %9.5f" % ("l" + i, tsup[i], hints["l" + i])
        if i != "8":
            hints["l" + i + "p"] = wrap(tfly[i] - th1)
            line += "    %-5s hip %9.5f   ground %9.5f" % ("l" + i + "p", tfly[i],
                                                         hints["l" + i + "p"])
        print(line)

    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "models", "pasibot.yaml")
    if os.path.exists(path):
        check_model(path, sup, fly, hints)
    if failures:
        print("\n%d check(s) failed" % len(failures))
        return 1
    print("\nall checks passed")
    return 0


# ---------------------------------------------------------------------------------------------
# Cross-check of models/pasibot.yaml against this geometry

def evaluate(text, params):
    expr = str(text).replace("^", "**")
    if not re.fullmatch(r"[A-Za-z0-9_+\-*/(). ]*", expr):
        raise ValueError("unexpected expression " + expr)
    env = {"pi": math.pi, "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos,
           "__builtins__": {}}
    env.update(params)
    return float(eval(expr, env))  # only arithmetic on the model's own parameters


def check_model(path, sup, fly, hints):
    try:
        import yaml
    except ImportError:
        print("\n(PyYAML not available: %s not cross-checked)" % path)
        return
    with open(path) as f:
        model = yaml.safe_load(f)
    params = {}
    for name, p in model["parameters"].items():
        params[name] = float(p["value"] if isinstance(p, dict) else p)
    l8 = params["l8"]
    where = {"A": A, "B": B, "D": D}
    for k, z in sup.items():
        where[k] = z
    for k, z in fly.items():
        where[k + "p"] = z
    worst = 0.0
    worst_hint = 0.0
    carriers = {}
    for body in model["bodies"]:
        name = body["name"]
        hint = 0.0 if body.get("ground") else evaluate(body["assembly"], params)
        if not body.get("ground"):
            worst_hint = max(worst_hint, abs(wrap(hint - hints[name])))
        # exact body angle and origin (ground frame) from the first two points
        pts = {k: complex(evaluate(v[0], params), evaluate(v[1], params)) / l8
               for k, v in body["points"].items()}
        names = list(pts)
        g = {k: to_ground(where[k], sup) for k in names}
        a, b = names[0], names[1]
        th = ang(g[b] - g[a]) - ang(pts[b] - pts[a])
        origin = g[a] - pts[a] * cmath.exp(1j * th)
        if body.get("ground"):
            check(abs(th) < 1e-9 and abs(origin) < 1e-9, "ground frame is the foot frame")
        else:
            check(abs(wrap(th - hints[name])) < 1e-9, f"model body {name}: angle != seed angle")
        for k in names:
            d = abs(origin + pts[k] * cmath.exp(1j * th) - g[k])
            worst = max(worst, d)
            check(d < 1e-9, f"model body {name}: point {k} misplaced by {d:.2e}")
            carriers.setdefault(k, []).append(name)
    # joints: revolute points carried by both bodies, slots on the hip line y = -4
    cons = 0
    bodies = {b["name"]: b for b in model["bodies"]}
    for jt in model["joints"]:
        first, second, p = bodies[jt["first"]], bodies[jt["second"]], jt["point"]
        if jt["type"] == "revolute":
            cons += 2
            check(p in first["points"] and p in second["points"], f"joint {jt['name']}: point")
        elif jt["type"] == "pin_in_slot":
            cons += 1
            thr = jt["line"]["through"]
            check(p in second["points"], f"joint {jt['name']}: point")
            check(abs(evaluate(thr[1], params) / l8 - SLOT_Y) < 1e-12
                  and evaluate(jt["line"]["direction"][1], params) == 0,
                  f"joint {jt['name']}: slot line")
            check(abs(where[p].imag - SLOT_Y) < 1e-12, f"joint {jt['name']}: S off the slot")
        else:
            cons += 2
    moving = len(model["bodies"]) - 1
    mobility = 3 * moving - cons
    check(mobility == len(model["drivers"]) == 1, "mobility")
    print()
    print("Model %s: %d moving bodies, %d joints (%d constraints), %d driver(s): mobility %d"
          % (os.path.relpath(path), moving, len(model["joints"]), cons, len(model["drivers"]),
             mobility))
    print("  body frames reproduce this geometry within %.1e l8; hints within %.4f rad"
          % (worst, worst_hint))


if __name__ == "__main__":
    sys.exit(main())
