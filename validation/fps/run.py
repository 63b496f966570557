"""A 1:25-scale floating power system on three chain catenaries (Srinivas, Yu, Hall & Bosma, OMAE 2016,
section 1 of issue 16), reproduced with moorline's coupled floating system.

    python validation/fps/run.py [--quick]

A vertical cylinder (200 mm diameter, 766.4 g) with Capytaine coefficients at its free-floating
draft, moored by three 3 m chains of 24 segments in a 1 m deep fresh-water basin. Runs:

- decays: heave from the free-floating position (the body sinks to its moored equilibrium), surge
  from 100 mm, pitch from 0.1 rad, and pitch without moorings (for the pitch drag);
- regular wave H 40 mm, T 0.8 s, 28 s with an 8 s ramp: fairlead tension statistics against the
  paper's WEC-Sim+MoorDyn and OrcaFlex numbers;
- irregular sea, JONSWAP Hs 20 mm, Tp 1.2 s, 370 s with a 10 s ramp: tension statistics and spectra.

Writes ``results.json`` and ``fps_*.png`` beside this script; exits 1 when a check fails.
``--quick``: the decays and the regular wave as in full, the irregular sea shortened to 70 s.
See README.md for every assumption.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE  # where results.json and the figures go (--out)
sys.path.insert(0, str(HERE.parent))

import common  # noqa: E402

import moorline  # noqa: E402
from moorline import hydro  # noqa: E402
from moorline.model import Model  # noqa: E402
from moorline.model.water import Waves  # noqa: E402

RHO, G = 1000.0, 9.81  # fresh-water basin
DEPTH = 1.0  # [m] not given by the paper: see README (it gives the published 5.3 mm sink)
RADIUS, HEIGHT, MASS = 0.100, 0.090, 0.7664  # [m, m, kg]
DRAFT_FREE = MASS / (RHO * np.pi * RADIUS**2)  # 24.4 mm
ZG = 0.029  # [m] centre of gravity above the waterline
#: inertia about the CG: a uniform solid cylinder of the body's mass and overall size (not given)
INERTIA = (MASS * (3 * RADIUS**2 + HEIGHT**2) / 12,) * 2 + (MASS * RADIUS**2 / 2,)
# chains: 3 m, 45.5 g/m, 24 segments; anchors 2.6 m out in plan
CHAIN_L, CHAIN_W, CHAIN_N, ANCHOR_R = 3.0, 0.0455, 24, 2.6
STEEL = 7850.0
CHAIN_D_VOL = np.sqrt(4 * CHAIN_W / (np.pi * STEEL))  # volume-equivalent diameter [m] (2.72 mm)
CHAIN_D_NOM = CHAIN_D_VOL / 1.8  # nominal (bar) diameter, MoorDyn's chain convention d_vol = 1.8 d_nom
#: axial stiffness [N]: not given. The studless-chain formula 0.854e11 d_nom^2 gives 195 kN, at which
#: moorline's Newton statics stalls (residual 5e-4 m/s^2, README "gaps"); 50 kN keeps the chain
#: inextensible all the same (strain 1.2e-5 at 0.6 N: the static tension changes by 1e-4 N)
CHAIN_EA = 5.0e4
#: lines M1, M2, M3: anchors at these bearings from +x (the waves travel toward +x); M2 down-wave
LINE_BEARINGS = (120.0, 0.0, 240.0)
# viscous drag: the paper's coefficients per DOF on the projected areas; pitch from the heave
# coefficient on the bottom disc (see drag())
CD_SURGE, CD_HEAVE = 0.75, 1.1
# published fairlead tension statistics [N], lines M1 / M2 / M3 (regular wave H 40 mm, T 0.8 s)
PUBLISHED = {"WEC-Sim+MoorDyn": {"mean": [0.446, 0.448, 0.446], "std": [0.052, 0.046, 0.052]},
             "OrcaFlex": {"mean": [0.450, 0.446, 0.450], "std": [0.051, 0.051, 0.051]}}
H_REG, T_REG, DUR_REG, RAMP_REG = 0.040, 0.8, 28.0, 8.0
HS, TP, GAMMA, SEED, DUR_IRR, RAMP_IRR = 0.020, 1.2, 3.3, 1, 370.0, 10.0
DTM = 0.005  # [s] generalized-alpha step: T/160 of the regular wave, T/70 of the heave period


def coefficients():
    """Capytaine coefficients of the cylinder at its free-floating draft, about the waterline centre
    (cached by moorline after the first run)."""
    mesh = hydro.mesh_cylinder(RADIUS, DRAFT_FREE, n_theta=32, n_radial=8, n_vertical=4)
    return hydro.compute_coefficients(mesh, omega=np.linspace(0.5, 30.0, 60), rho=RHO, g=G, water_depth=DEPTH,
                                      rotation_center=[0.0, 0.0, 0.0], lid=True)


def drag() -> np.ndarray:
    """Quadratic damping about the waterline centre [N s^2/m^2, N m s^2]: 0.5 rho Cd A on the
    projected areas (surge: diameter x draft; heave: the bottom disc), and in pitch the heave
    coefficient acting on the local vertical velocity of the bottom disc, 0.5 rho Cd int |x|^3 dA =
    0.5 rho Cd (8/15) R^5."""
    bq = np.zeros(6)
    bq[0] = bq[1] = 0.5 * RHO * CD_SURGE * 2 * RADIUS * DRAFT_FREE
    bq[2] = 0.5 * RHO * CD_HEAVE * np.pi * RADIUS**2
    bq[3] = bq[4] = 0.5 * RHO * CD_HEAVE * 8.0 / 15.0 * RADIUS**5
    return bq


def build(ds, *, moored: bool = True, waves: Waves | None = None, waves_on_lines: bool = False,
          hold: dict | None = None) -> Model:
    """The cylinder (on its chains when ``moored``). ``hold`` ({dof: displacement}) puts the body
    there in the deck (the hydrostatics stay linearised about the free-floating pose) so that
    statics starts near the held equilibrium (see :func:`run`)."""
    m = Model()
    m.env.rho, m.env.g, m.env.depth = RHO, G, DEPTH
    m.env.kBot, m.env.cBot = 3.0e6, 3.0e5
    m.options.tScheme = "GenAlpha"
    m.options.dtM = DTM
    x0 = np.zeros(6)
    for dof, x in (hold or {}).items():
        x0[dof] = x
    b = m.add_body("free", x0[:3], np.degrees(x0[3:]), m=MASS, rCG=(0.0, 0.0, ZG), I=INERTIA)
    if moored:
        m.add_line_type("chain", d=CHAIN_D_VOL, w=CHAIN_W, EA=CHAIN_EA, BA=-0.8, Cd=2.4, Ca=1.0, CdAx=1.15,
                        CaAx=0.5)
        for bearing in LINE_BEARINGS:
            c, s = np.cos(np.radians(bearing)), np.sin(np.radians(bearing))
            fair = m.add_point("body", (RADIUS * c, RADIUS * s, -DRAFT_FREE), body=b)
            anchor = m.add_point("fixed", (ANCHOR_R * c, ANCHOR_R * s, -DEPTH))
            m.add_line("chain", anchor, fair, L=CHAIN_L, N=CHAIN_N)
    m.add_hydro([b], ds, mean_poses=[np.zeros(6)])
    m.add_floating(b, quadratic_damping=drag())
    m.env.waves = waves
    m.env.waves_on_lines = waves_on_lines
    return m


def heave_period_fd(ds) -> float:
    """Undamped heave natural period [s] of the unmoored body, 2 pi sqrt((m + A33(w)) / C33) with
    A33 at its own frequency (fixed point)."""
    C33 = float(ds["hydrostatic_stiffness"].sel(influenced_dof="Heave", radiating_dof="Heave"))
    a33 = ds["added_mass"].sel(influenced_dof="Heave", radiating_dof="Heave")
    w = np.sqrt(C33 / MASS)
    for _ in range(50):
        w = np.sqrt(C33 / (MASS + float(a33.interp(omega=w))))
    return float(2 * np.pi / w)


#: stiffness of the temporary spring that holds a body at its initial displacement while the lines
#: find their equilibrium [N/m, N m/rad]: 200 to 2000 times the hydrostatic and mooring stiffnesses
#: (the held pose is within 0.5 % of the target); stiffer springs make Newton statics stall
HOLD_STIFFNESS = np.array([1.0e3, 1.0e3, 1.0e5, 1.0e2, 1.0e2, 1.0e2])


def run(m: Model, duration: float, dt_out: float, *, hold: dict | None = None) -> dict:
    """Simulate. ``hold`` ({dof index: displacement from the mean pose}) makes a decay: Newton
    statics finds the equilibrium of the lines with the body held there by a stiff spring (an extra
    stiffness and constant load, see :class:`moorline.model.FloatingBody`), and the spring is
    released at t = 0. (Moving the body alone with ``set_body_state`` would stretch the end segments
    of the stiff chains by the displacement: a kilonewton kick to a 0.77 kg body.)"""
    if hold:
        K = np.zeros(6)
        F = np.zeros(6)
        for dof, x in hold.items():
            K[dof] = HOLD_STIFFNESS[dof]
            F[dof] = HOLD_STIFFNESS[dof] * x
        fb = m.floating_body(0)
        m.add_floating(0, linear_damping=fb.linear_damping, quadratic_damping=fb.quadratic_damping,
                       stiffness=np.diag(K), force=F, morison=fb.morison)
    s = moorline.System(m)
    s.init()
    eq = s.bodies[0].pose().copy()
    if hold:
        f = s.layout.fl.body.tolist().index(0)
        s.layout.fl.Kext[f] = 0.0
        s.layout.fl.Fc[f] = 0.0
        s.set_state()  # loads re-evaluated, the scheme's history cleared
    t0 = time.perf_counter()
    r = moorline.simulate(s, duration, dt_out=dt_out, progress=False, record_nodes=False)
    out = {"t": r.time.values, "pose": r.body_pose.values[:, 0, :], "start": eq, "wall": time.perf_counter() - t0}
    out["eq"] = eq if not hold else None
    if m.lines:
        out["tension"] = r.line_tension_b.values  # end B is the fairlead
    return out


def decay_measures(t, x):
    """Damped period [s] (zero crossings) and mean logarithmic decrement of successive same-sign
    peaks, over the first cycles that stay above 5 % of the first peak."""
    i = np.where(np.sign(x[:-1]) != np.sign(x[1:]))[0]
    if len(i) < 4:
        return float("nan"), float("nan")
    zc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    peaks = np.array([np.max(np.abs(x[(t >= zc[k]) & (t < zc[k + 1])])) for k in range(len(zc) - 1)])
    keep = np.where(peaks > 0.05 * np.max(np.abs(x)))[0]
    n = max(3, min(len(keep), 8))
    Td = 2.0 * float(np.mean(np.diff(zc[: n + 1])))
    p = peaks[:n]
    dec = float(np.mean(np.log(p[:-2] / p[2:]))) if len(p) > 2 else float("nan")
    return Td, dec


def main(argv=None) -> int:
    global OUT
    a, OUT = common.study_command(__doc__, "shortened irregular sea (CI)", HERE, argv)
    started = time.perf_counter()
    ds = coefficients()
    chk = common.Checks()
    res: dict = {"assumed": {"depth_m": DEPTH, "chain_ea_n": CHAIN_EA, "chain_d_volume_m": CHAIN_D_VOL,
                             "inertia_kg_m2": INERTIA, "quadratic_damping": drag(),
                             "line_bearings_deg": LINE_BEARINGS, "free_draft_m": DRAFT_FREE}}

    # ------------------------------------------------------------ decays
    dec = {}
    static = run(build(ds), 0.1, 0.1)  # the moored equilibrium
    sink = -float(static["eq"][2])
    heave = run(build(ds, hold={2: 0.0}), 6.0, 0.002, hold={2: 0.0})  # held at the free-floating draft, then released
    dec["heave"] = decay_measures(heave["t"], heave["pose"][:, 2] + sink)
    hs = {0: static["eq"][0] + 0.1}
    surge = run(build(ds, hold=hs), 40.0, 0.01, hold=hs)
    dec["surge"] = decay_measures(surge["t"], surge["pose"][:, 0] - static["eq"][0])
    pitch = run(build(ds, hold={4: 0.1}), 6.0, 0.002, hold={4: 0.1})
    dec["pitch"] = decay_measures(pitch["t"], pitch["pose"][:, 4] - static["eq"][4])
    pitch_free = run(build(ds, moored=False, hold={4: 0.1}), 6.0, 0.002, hold={4: 0.1})
    dec["pitch_unmoored"] = decay_measures(pitch_free["t"], pitch_free["pose"][:, 4])
    res["heave_equilibrium_sink_m"] = sink
    chk.add("moored equilibrium sink vs the paper's 5.3 mm", sink, 0.0053, 0.10,
            why="depth chosen for it in quasi-static catenary terms (README); the dynamic lines, seabed contact "
                "and the elastic chain move it by a few per cent")

    # ------------------------------------------------------------ regular wave
    reg = {}
    for key, wol in (("regular", False), ("regular_waves_on_lines", True)):
        w = Waves.regular(H_REG, T_REG, ramp_time=RAMP_REG)
        reg[key] = run(build(ds, waves=w, waves_on_lines=wol), DUR_REG, 0.01)
    for key, c in reg.items():
        sel = c["t"] >= RAMP_REG
        res[key] = {"fairlead_tension_mean_n": c["tension"][sel].mean(axis=0),
                    "fairlead_tension_std_n": c["tension"][sel].std(axis=0), "window_s": [RAMP_REG, DUR_REG],
                    "heave_amplitude_m": abs(common.steady_amplitude(c["t"], c["pose"][:, 2], 2 * np.pi / T_REG, 10)),
                    "surge_amplitude_m": abs(common.steady_amplitude(c["t"], c["pose"][:, 0], 2 * np.pi / T_REG, 10)),
                    "pitch_amplitude_rad": abs(common.steady_amplitude(c["t"], c["pose"][:, 4], 2 * np.pi / T_REG,
                                                                       10))}
    ours = res["regular"]
    for name, pub in PUBLISHED.items():
        for k in range(3):
            chk.compare(f"regular: mean fairlead tension M{k + 1}", ours["fairlead_tension_mean_n"][k], pub["mean"][k],
                        name, note="set by the unstated depth; README")
            chk.compare(f"regular: fairlead tension std M{k + 1}", ours["fairlead_tension_std_n"][k], pub["std"][k],
                        name, note="fairlead position, chain stiffness and line orientation unstated; README")
    # the heave decay against the frequency-domain natural period of the unmoored body
    heave_free = run(build(ds, moored=False, hold={2: 0.01}), 6.0, 0.002, hold={2: 0.01})
    dec["heave_unmoored"] = decay_measures(heave_free["t"], heave_free["pose"][:, 2])
    t_fd = heave_period_fd(ds)
    res["heave_natural_period_fd_s"] = t_fd
    chk.add("unmoored heave decay: damped period vs the frequency-domain natural period", dec["heave_unmoored"][0],
            t_fd, 0.05, why="a damping ratio of 0.2 (the measured decrement) lengthens the damped period by 2 %; the "
            "radiation memory spreads A(w), B(w) over the band (tests/floating/test_decay.py: 1 %)")
    res["decay"] = {k: {"damped_period_s": v[0], "log_decrement": v[1]} for k, v in dec.items()}

    # ------------------------------------------------------------ irregular sea
    dur = 70.0 if a.quick else DUR_IRR
    w = Waves.jonswap(HS, TP, GAMMA, seed=SEED, ramp_time=RAMP_IRR)
    irr = run(build(ds, waves=w), dur, 0.02)
    sel = irr["t"] >= RAMP_IRR
    res["irregular"] = {"fairlead_tension_mean_n": irr["tension"][sel].mean(axis=0),
                        "fairlead_tension_std_n": irr["tension"][sel].std(axis=0),
                        "fairlead_tension_max_n": irr["tension"][sel].max(axis=0),
                        "surge_std_m": np.std(irr["pose"][sel, 0]), "heave_std_m": np.std(irr["pose"][sel, 2]),
                        "pitch_std_rad": np.std(irr["pose"][sel, 4]), "duration_s": dur, "ramp_s": RAMP_IRR,
                        "surge_peak_period_s": common.peak_period(irr["t"][sel], irr["pose"][sel, 0], segment=60.0)
                        if not a.quick else None}
    static = reg["regular"]["tension"][0]  # t = 0: the moored equilibrium in still water
    res["static_fairlead_tension_n"] = static
    for k in range(3):
        chk.add(f"irregular: mean fairlead tension M{k + 1} vs the still-water tension",
                res["irregular"]["fairlead_tension_mean_n"][k], static[k], 0.05,
                why="a small sea moves the mean tension only through second-order effects (drift, drag)")
    res["case_wall_time_s"] = {"heave_decay": heave["wall"], "surge_decay": surge["wall"], "pitch_decay": pitch["wall"],
                               "regular": reg["regular"]["wall"], "irregular": irr["wall"]}
    res["published"] = PUBLISHED
    res["checks"] = chk.items
    res["comparisons"] = chk.comparisons
    res["passed"] = chk.passed
    out = common.write_results(OUT / "results.json", res, quick=a.quick, started=started)
    paths = figures(heave, surge, pitch, pitch_free, reg, irr, a.quick)
    print(f"FPS ({out['mode']}, {out['wall_time_s']} s): moored sink {1e3 * sink:.2f} mm (paper 5.3 mm)")
    for k, v in dec.items():
        print(f"  {k} decay: damped period {v[0]:.3f} s, log decrement {v[1]:.3f}")
    for key in ("regular", "regular_waves_on_lines", "irregular"):
        r = res[key]
        print(f"  {key}: fairlead tension mean {np.round(r['fairlead_tension_mean_n'], 3)} N, std "
              f"{np.round(r['fairlead_tension_std_n'], 3)} N")
    for name, p in PUBLISHED.items():
        print(f"  published regular ({name}): mean {p['mean']} N, std {p['std']} N")
    print(chk.report())
    for p in paths:
        print(f"  wrote {p}")
    return 0 if chk.passed else 1


def figures(heave, surge, pitch, pitch_free, reg, irr, quick) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    axes[0].plot(heave["t"], 1e3 * heave["pose"][:, 2])
    axes[0].axhline(-5.3, color="k", ls="--", lw=0.8, label="paper: 5.3 mm sink")
    axes[0].set_ylabel("heave [mm]")
    axes[0].legend(fontsize=8)
    axes[1].plot(surge["t"], 1e3 * (surge["pose"][:, 0]))
    axes[1].set_ylabel("surge [mm]")
    axes[2].plot(pitch["t"], np.degrees(pitch["pose"][:, 4]), label="moored")
    axes[2].plot(pitch_free["t"], np.degrees(pitch_free["pose"][:, 4]), "--", label="no moorings")
    axes[2].set_ylabel("pitch [deg]")
    axes[2].legend(fontsize=8)
    for ax, title in zip(axes, ("heave: released at the free-floating draft", "surge decay from 100 mm",
                                "pitch decay from 0.1 rad"), strict=True):
        ax.set_xlabel("time [s]")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    paths.append(OUT / "fps_decays.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 3.8), gridspec_kw={"width_ratios": [2, 1]})
    c = reg["regular"]
    for k in range(3):
        ax1.plot(c["t"], c["tension"][:, k], lw=0.9, label=f"M{k + 1}")
    ax1.axvspan(0, RAMP_REG, color="0.9")
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("fairlead tension [N]")
    ax1.legend(fontsize=8)
    ax1.set_title(f"regular wave H {1e3 * H_REG:g} mm, T {T_REG} s (grey: ramp)", fontsize=9)
    x = np.arange(3)
    sel = c["t"] >= RAMP_REG
    mean, std = c["tension"][sel].mean(axis=0), c["tension"][sel].std(axis=0)
    ax2.errorbar(x - 0.15, mean, std, fmt="o", capsize=4, label="moorline")
    for k, (name, p) in enumerate(PUBLISHED.items()):
        ax2.errorbar(x + 0.05 + 0.1 * k, p["mean"], p["std"], fmt="s", capsize=4, label=name)
    ax2.set_xticks(x, ["M1", "M2", "M3"])
    ax2.set_ylabel("mean ± std [N]")
    ax2.legend(fontsize=7)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    paths.append(OUT / "fps_regular.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, axes = plt.subplots(1, 4, figsize=(14, 3.4))
    sel = irr["t"] >= RAMP_IRR
    seg = 30.0 if quick else 60.0
    for ax, (y, lab) in zip(axes, ((irr["pose"][sel, 0], "surge [m²/Hz]"), (irr["pose"][sel, 2], "heave [m²/Hz]"),
                                   (irr["pose"][sel, 4], "pitch [rad²/Hz]")), strict=False):
        f, S = common.spectrum(irr["t"][sel], y, segment=seg)
        ax.semilogy(f, S)
        ax.set_ylabel(lab)
    for k in range(3):
        f, S = common.spectrum(irr["t"][sel], irr["tension"][sel, k], segment=seg)
        axes[3].semilogy(f, S, label=f"M{k + 1}")
    axes[3].set_ylabel("fairlead tension [N²/Hz]")
    axes[3].legend(fontsize=8)
    for ax in axes:
        ax.set_xlim(0, 3)
        ax.set_xlabel("frequency [Hz]")
        ax.grid(alpha=0.3)
    fig.suptitle(f"JONSWAP Hs {1e3 * HS:g} mm, Tp {TP} s: spectra after the ramp ({irr['t'][-1]:.0f} s record)",
                 fontsize=10)
    fig.tight_layout()
    paths.append(OUT / "fps_irregular_spectra.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)
    return paths


if __name__ == "__main__":
    sys.exit(main())
