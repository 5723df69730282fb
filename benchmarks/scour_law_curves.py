"""Equilibrium burial and time scale of each scour burial law against theta and KC (issue 33:
"curves of equilibrium burial and time scale against theta and KC for each law").

Evaluates the stage's own kernels (kernels/mine/scour.py) for the 0.53 m Oahu cylinder on 0.2 mm
quartz sand in sea water (theta_cr = 0.0553, Soulsby & Whitehouse 1997) at the laws' default
coefficients, draws four panels and writes the numbers beside them:

- B_eq/D (rennie: D a theta^b from theta_cr, capped at D) and S_eq/D (scour_settle: pure waves at
  KC 4, 8, 16; a pure current; combined U_cw = 0.5 at KC 8) against theta;
- S_eq/D of scour_settle's wave pit against KC at theta 0.1, 0.3, 1;
- the time scale T [h] of each T* law against theta (KC 8 for the KC law);
- T of the pile-in-waves KC law against KC at theta 0.1, 0.3.

    python benchmarks/scour_law_curves.py [--png docs/figures/scour_law_curves.png]
        [--txt benchmarks/results/scour_law_curves.txt]
"""

import argparse
import math
import pathlib

import numpy as np

from mineburial.kernels.mine import scour as S

ROOT = pathlib.Path(__file__).resolve().parents[1]
D = 0.53
P = S.default_parameters(diameter=D, d50=2.0e-4)
SG = P[S.S_RHO_GRAIN] / P[S.S_RHO_WATER]
THETA_CR = S.shields_threshold(S.grain_size_number(P[S.S_D50], SG, P[S.S_G], P[S.S_NU]))
A, B, AW, MW = P[S.S_BEQ_A], P[S.S_BEQ_B], P[S.S_WAVE_A], P[S.S_WAVE_KC_EXP]


def rennie(theta):
    """The first version's B_eq/D: a theta^b above the threshold (a jump there), capped at 1."""
    return min(A * theta**B, 1.0) if theta > THETA_CR else 0.0


def settle(theta, kc, ucw):
    """scour_settle's S_eq/D (before the caps of the coarse-sand exposure and mobile layer)."""
    return min(S.pit_equilibrium(theta, THETA_CR, kc, ucw, D, A, B, AW, MW) / D, 1.0)


def time_scale_h(law, theta, kc):
    c, m, p, kc_min = S.TSTAR_LAWS[law]
    t = S.scour_time_scale(theta, kc, D, P[S.S_D50], SG, P[S.S_G], c, m, p, kc_min)
    return t / 3600.0


def curves():
    thetas = np.geomspace(0.02, 3.0, 400)
    kcs = np.linspace(0.5, 30.0, 300)
    eq_theta = {"rennie (Rennie et al. 2017)": [rennie(t) for t in thetas]}
    for kc in (4.0, 8.0, 16.0):
        eq_theta[f"scour_settle, waves, KC {kc:g}"] = [settle(t, kc, 0.0) for t in thetas]
    eq_theta["scour_settle, current"] = [settle(t, 0.0, 1.0) for t in thetas]
    eq_theta["scour_settle, U_cw 0.5, KC 8"] = [settle(t, 8.0, 0.5) for t in thetas]
    eq_kc = {f"waves, theta {th:g}": [settle(th, kc, 0.0) for kc in kcs] for th in (0.1, 0.3, 1.0)}
    ts_theta = {
        law: [time_scale_h(law, t, 8.0) for t in thetas] for law in ("whitehouse", "pipeline", "pile_waves")
    }
    ts_kc = {
        f"pile_waves, theta {th:g}": [time_scale_h("pile_waves", th, kc) for kc in kcs] for th in (0.1, 0.3)
    }
    return thetas, kcs, eq_theta, eq_kc, ts_theta, ts_kc


def table(thetas, kcs, eq_theta, eq_kc, ts_theta, ts_kc) -> str:
    lines = [
        "Equilibrium burial and time scale of the scour laws (python benchmarks/scour_law_curves.py)",
        f"D = {D} m, d50 = 0.2 mm quartz in sea water, theta_cr = {THETA_CR:.4f}; "
        f"defaults a = {A:g}, b = {B:g}, a_w = {AW:g}, m_w = {MW:g}",
        "",
        "B_eq/D or S_eq/D against theta:",
    ]
    picks = [0.05, 0.06, 0.08, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0]
    lines.append("  theta " + " ".join(f"{t:7g}" for t in picks))
    for name in eq_theta:
        law = name
        vals = [rennie(t) if law.startswith("rennie") else None for t in picks]
        if not law.startswith("rennie"):
            if "current" in law:
                vals = [settle(t, 0.0, 1.0) for t in picks]
            elif "U_cw" in law:
                vals = [settle(t, 8.0, 0.5) for t in picks]
            else:
                kc = float(law.rsplit(" ", 1)[1])
                vals = [settle(t, kc, 0.0) for t in picks]
        lines.append(f"  {name}: " + " ".join(f"{v:7.3f}" for v in vals))
    lines.append("")
    lines.append("S_eq/D of the wave pit against KC:")
    kpicks = [2.0, 4.0, 8.0, 16.0, 30.0]
    lines.append("  KC " + " ".join(f"{k:7g}" for k in kpicks))
    for th in (0.1, 0.3, 1.0):
        lines.append(f"  theta {th:g}: " + " ".join(f"{settle(th, k, 0.0):7.3f}" for k in kpicks))
    lines.append("")
    lines.append("time scale T [h] against theta (KC 8 for pile_waves):")
    lines.append("  theta " + " ".join(f"{t:7g}" for t in picks))
    for law in ts_theta:
        lines.append(f"  {law}: " + " ".join(f"{time_scale_h(law, t, 8.0):7.3g}" for t in picks))
    lines.append("")
    return "\n".join(lines) + "\n"


def draw(png, thetas, kcs, eq_theta, eq_kc, ts_theta, ts_kc):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 8), dpi=100)
    for name, v in eq_theta.items():
        ax[0, 0].plot(thetas, v, label=name, ls="--" if name.startswith("rennie") else "-")
    ax[0, 0].axvline(THETA_CR, color="grey", lw=0.8)
    ax[0, 0].text(THETA_CR * 1.05, 0.95, "θ_cr", color="grey")
    ax[0, 0].set(xscale="log", xlabel="Shields parameter θ", ylabel="equilibrium B/D or S/D", ylim=(0, 1.05))
    ax[0, 0].set_title("equilibrium against θ")
    ax[0, 0].legend(fontsize=7)
    for name, v in eq_kc.items():
        ax[0, 1].plot(kcs, v, label=name)
    ax[0, 1].set(xlabel="Keulegan-Carpenter number KC", ylabel="S_eq/D (waves)", ylim=(0, 1.05))
    ax[0, 1].set_title("scour_settle wave pit against KC (Sumer & Fredsøe 1990)")
    ax[0, 1].legend(fontsize=7)
    for name, v in ts_theta.items():
        ax[1, 0].plot(thetas, v, label=name + (" (KC 8)" if name == "pile_waves" else ""))
    ax[1, 0].axvline(THETA_CR, color="grey", lw=0.8)
    ax[1, 0].set(xscale="log", yscale="log", xlabel="Shields parameter θ", ylabel="time scale T [h]")
    ax[1, 0].set_title("time scale against θ (D 0.53 m, d50 0.2 mm)")
    ax[1, 0].legend(fontsize=7)
    for name, v in ts_kc.items():
        ax[1, 1].plot(kcs, v, label=name)
    ax[1, 1].set(yscale="log", xlabel="KC", ylabel="time scale T [h]")
    ax[1, 1].set_title("KC time-scale law (piles in waves; none below KC 7)")
    ax[1, 1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--png", default=str(ROOT / "docs" / "figures" / "scour_law_curves.png"))
    ap.add_argument("--txt", default=str(ROOT / "benchmarks" / "results" / "scour_law_curves.txt"))
    args = ap.parse_args()
    data = curves()
    text = table(*data)
    pathlib.Path(args.txt).write_text(text, encoding="utf-8")
    draw(args.png, *data)
    print(text)
    assert math.isclose(THETA_CR, 0.0553, rel_tol=5e-3)


if __name__ == "__main__":
    main()
