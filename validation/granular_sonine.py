"""The first Sonine a_2 of granular gases, derived from the collision integrals (docs/validation/granular.md).

The a_2 formulas that validation/granular.py compares with (van Noije and
Ernst, Granular Matter 1, 57 (1998)),

    HCS:          a_2 = 16 (1 - e)(1 - 2 e^2) / (9 + 24 d - e (41 - 8 d) + 30 e^2 (1 - e)),
    white noise:  a_2 = 16 (1 - e)(1 - 2 e^2) / (73 + 56 d - 3 e (35 + 8 d) + 30 e^2 (1 - e)),

and the Sonine factors of the collision rate and of the energy lost,
``1 - a_2/16`` and ``1 + 3 a_2/16``, are derived here exactly (sympy) in
d = 2 and 3, in the first Sonine approximation:
``phi(c) ~ exp(-c^2) (1 + a_2 S_2(c^2))``, ``S_2(x) = x^2/2 - (d + 2) x/2 +
d (d + 2)/8``, linear in ``a_2``.  With the collision moments ``C_p = <<
Theta(g.s) (g.s) (c_1'^p + c_2'^p - c_1^p - c_2^p) >>`` (``g = c_1 - c_2``,
``s`` the unit vector between the centres, ``g' = g - (1 + e)(g.s) s``):

* the HCS is a scaling solution, ``<c^p>`` constant while ``T`` falls, so
  ``C_4 / <c^4> = 2 C_2 / <c^2>``: ``C_4 = (d + 2)(1 + a_2) C_2``;
* white noise adds ``(xi_0^2 / 2) nabla_v^2 f``, which gives ``d xi_0^2``
  to ``d<v^2>/dt`` and ``2 (d + 2) xi_0^2 <v^2>`` to ``d<v^4>/dt``, so the
  steady state has ``C_4 = (d + 2) C_2``.

The Gaussian average over the centre of mass ``G = (c_1 + c_2)/2`` is done
from its moments, then ``|g|`` (density ``r^(d-1) exp(-r^2/2)``) and the
angle between ``g`` and ``s``: no numerical integration.

    python3 validation/granular_sonine.py     # validation/results/granular_sonine.txt (about 10 s)

It needs sympy (``pip install sympy``), which the package does not.
"""

import os
import sys

from hardspheres.fileio import atomic_write


def _gauss_moment(k: int) -> object:
    """``<x^k>`` of a normal of variance 1/4 (each component of G), exact."""
    import sympy as sp

    return 0 if k % 2 else sp.factorial2(k - 1) * sp.Rational(1, 4) ** (k // 2)


def derive(d: int) -> dict:
    """The a_2 of both states and the Sonine factors, exact rational functions of the restitution ``e``."""
    import sympy as sp

    e = sp.Symbol("e")
    r, th = sp.symbols("r theta", positive=True)
    comps = sp.symbols(f"G0:{d}")
    G = sp.Matrix(comps)
    ez = sp.Matrix([0] * (d - 1) + [1])  # g along the last axis
    s = sp.Matrix([sp.sin(th)] + [0] * (d - 2) + [sp.cos(th)])  # s at angle theta to it
    g, gs = r * ez, r * sp.cos(th)
    g_after = g - (1 + e) * gs * s

    def sq(v: sp.Matrix) -> sp.Expr:
        return (v.T * v)[0]

    def s2(x: sp.Expr) -> sp.Expr:
        return x**2 / 2 - sp.Rational(d + 2, 2) * x + sp.Rational(d * (d + 2), 8)

    c1, c2 = G + g / 2, G - g / 2
    w1 = s2(sq(c1)) + s2(sq(c2))  # the a_2 term of phi(c_1) phi(c_2), to first order

    def average(expr: sp.Expr, angular: bool) -> sp.Expr:
        """Over G (moments), |g| (radial Gaussian) and, if ``angular``, the collision angle."""
        over_g = 0
        for powers, coef in sp.Poly(sp.expand(expr), *comps).terms():
            m = 1
            for k in powers:
                m *= _gauss_moment(k)
            over_g += coef * m
        radial = 0
        for (k,), coef in sp.Poly(sp.expand(over_g), r).terms():
            radial += coef * 2 ** sp.Rational(k + d - 2, 2) * sp.gamma(sp.Rational(k + d, 2))
        if not angular:
            return sp.simplify(radial)
        if d == 3:
            return sp.simplify(sp.integrate(sp.expand(radial) * sp.sin(th), (th, 0, sp.pi / 2)))
        return sp.simplify(sp.integrate(sp.expand(radial), (th, -sp.pi / 2, sp.pi / 2)))

    moments = {}
    for p in (2, 4):
        half = p // 2
        delta = sq(G + g_after / 2) ** half + sq(G - g_after / 2) ** half - sq(c1) ** half - sq(c2) ** half
        moments[p] = (average(gs * delta, True), average(gs * delta * w1, True))
    (c20, c21), (c40, c41) = moments[2], moments[4]
    hcs = sp.factor(sp.simplify(((d + 2) * c20 - c40) / (c41 - (d + 2) * (c20 + c21))))
    noise = sp.factor(sp.simplify(((d + 2) * c20 - c40) / (c41 - (d + 2) * c21)))
    num = 16 * (1 - e) * (1 - 2 * e**2)
    quoted_hcs = num / (9 + 24 * d - e * (41 - 8 * d) + 30 * e**2 * (1 - e))
    quoted_noise = num / (73 + 56 * d - 3 * e * (35 + 8 * d) + 30 * e**2 * (1 - e))
    rate = sp.simplify(average(r * w1, False) / average(r, False))  # <g> (the collision rate)
    return {
        "hcs": hcs,
        "noise": noise,
        "hcs_minus_quoted": sp.simplify(hcs - quoted_hcs),
        "noise_minus_quoted": sp.simplify(noise - quoted_noise),
        "energy_factor": sp.simplify(c21 / c20),  # 3/16: (1 + 3 a_2/16)
        "rate_factor": rate,  # -1/16: (1 - a_2/16)
        "e": e,
    }


def main() -> int:
    """Derive in d = 2 and 3, print and write the comparison; 1 without sympy."""
    try:
        import sympy  # noqa: F401
    except ModuleNotFoundError:
        print("validation/granular_sonine.py needs sympy: pip install sympy", file=sys.stderr)
        return 1
    lines = []
    for d in (2, 3):
        out = derive(d)
        e = out["e"]
        lines.append(f"d = {d}: the energy lost per unit time changes by 1 + ({out['energy_factor']}) a_2, "
                     f"the collision rate by 1 + ({out['rate_factor']}) a_2")  # fmt: skip
        for state in ("hcs", "noise"):
            name = "HCS" if state == "hcs" else "white noise"
            values = ", ".join(f"{float(out[state].subs(e, x)):+.4f} at e = {x}" for x in (0.9, 0.8, 0.6))
            lines.append(f"  {name}: a_2 = {out[state]}; less the quoted formula: "
                         f"{out[state + '_minus_quoted']}; {values}")  # fmt: skip
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "granular_sonine.txt")
    with atomic_write(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
