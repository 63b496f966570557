"""RM3 two-body point absorber on its three-point catenary mooring (Srinivas, Yu, Hall & Bosma, OMAE
2016, section 2 of issue 16), reproduced with moorline's coupled floating system.

    python validation/rm3/run.py [--quick]

Float and spar/plate on the public RM3 WAMIT run (two bodies, 12 x 12 coupling), the float sliding
on the spar with a 1200 kN s/m PTO damper; the spar moored by the public RM3 MoorDyn deck (three
240 m + 40 m chains with a submerged buoy at each junction, 70 m depth), or free. Runs:

- irregular sea (JONSWAP Hs 2.5 m, Tp 8 s, gamma 3.3, 400 s, 40 s ramp), moored and free;
- regular wave H 2.5 m, T 8 s (400 s, 40 s ramp), moored and free, against the frequency-domain
  solve of the same constrained pair (:func:`moorline.hydro.rao`).

Writes ``results.json`` and ``rm3_*.png`` beside this script and prints the checks; exits 1 when a
check fails. ``--quick`` runs 200 s records (the frequency-domain checks keep their tolerance, the
irregular-sea statistic a looser one). See README.md for every assumption.
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
from moorline.io.deck import read_deck  # noqa: E402
from moorline.model import BodyKind, Model  # noqa: E402
from moorline.model.water import Waves  # noqa: E402

RHO, G = 1000.0, 9.81  # WEC-Sim's RM3 water
FLOAT_CG = (0.0, 0.0, -0.72)  # [m] the WAMIT reference points are the centres of gravity
SPAR_CG = (0.0, 0.0, -21.29)
FLOAT_I = (20907301.0, 21306090.66, 37085481.11)  # [kg m^2] about the CG
SPAR_I = (94419614.57, 94407091.24, 28542224.82)
PTO_DAMPING = 1.2e6  # [N s/m]
HS, TP, GAMMA, SEED = 2.5, 8.0, 3.3, 1
H_REG, T_REG = 2.5, 8.0
RAMP = 40.0
DT_OUT = 0.1


def rm3_data():
    """The WAMIT stem and the MoorDyn deck of ../shared/data/rm3."""
    stem = common.shared_file("rm3", "rm3.1").with_suffix("")
    return stem, common.shared_file("rm3", "rm3_moorings_moordyn.txt")


def build(ds, deck: Path, *, moored: bool, waves: Waves, dtM: float = 0.05) -> Model:
    """The RM3 model: float (body index 1) sliding on the spar (body index 0) with the PTO.

    Moored: the public MoorDyn deck, whose Coupled body (at z = -21.5 m, where WEC-Sim puts the
    spar after its 0.21 m initial sink) becomes the free spar; the hydrostatics are linearised about
    the WAMIT pose (z = -21.29 m) and Newton statics finds the moored equilibrium. Free: the same
    two bodies without lines, at the WAMIT pose.
    """
    V = ds["displaced_volume"].values
    if moored:
        m = read_deck(deck)
        spar = 0
        b = m.bodies[spar]
        b.kind = BodyKind.FREE
        b.m = RHO * float(V[1])
        b.rCG = np.array(SPAR_CG) - b.r  # body axes, from the deck reference point
        b.I = np.array(SPAR_I)
    else:
        m = Model()
        m.env.depth = 70.0
        spar = m.add_body("free", SPAR_CG, m=RHO * float(V[1]), I=SPAR_I)
    m.env.rho, m.env.g = RHO, G
    fl = m.add_body("free", FLOAT_CG, m=RHO * float(V[0]), I=FLOAT_I)
    m.add_hydro([fl, spar], ds, mean_poses=[[*FLOAT_CG, 0, 0, 0], [*SPAR_CG, 0, 0, 0]])
    m.add_joint(fl, spar, axis=(0.0, 0.0, 1.0), pto_damping=PTO_DAMPING)
    m.options.tScheme = "GenAlpha"
    m.options.dtM = dtM
    m.env.waves = waves
    m.env.waves_on_lines = False  # WEC-Sim's MoorDyn coupling: WaveKin 0
    return m


def run_case(ds, deck, *, moored: bool, waves: Waves, duration: float) -> dict:
    """Simulate one case and return its time series (float = body 2, spar = body 1 of the output)."""
    m = build(ds, deck, moored=moored, waves=waves)
    t0 = time.perf_counter()
    r = moorline.simulate(moorline.System(m), duration, dt_out=DT_OUT, progress=False, record_nodes=False)
    pose = r.body_pose.values  # (time, body, pose)
    sp, fl = (0, 1)
    out = {"t": r.time.values, "surge": pose[:, sp, 0], "heave": pose[:, sp, 2] - pose[0, sp, 2],
           "pitch": pose[:, sp, 4], "float_heave": pose[:, fl, 2] - pose[0, fl, 2],
           "relative": r.joint_slide.values[:, 0], "power": r.pto_power.values[:, 0],
           "wall": time.perf_counter() - t0,
           "z0_spar_cg": float(pose[0, sp, 2] + m.bodies[sp].rCG[2])}  # no rotation at rest
    if moored:
        out["fairlead_tension"] = r.line_tension_b.values[:, 3:6]  # lines 4-6 end at the spar
    return out


def frequency_domain(ds, omega):
    """The constrained frequency-domain solve of the free pair (no moorings)."""
    V = ds["displaced_volume"].values
    M = hydro.mass_matrix([RHO * V[0], RHO * V[1]], [FLOAT_CG, SPAR_CG], [FLOAT_I, SPAR_I], [FLOAT_CG, SPAR_CG])
    pto = hydro.LinearPTO(0, 1, (0.0, 0.0, 1.0), 0.0, PTO_DAMPING)
    return hydro.rao(ds, M, wave_direction=0.0, omega=np.atleast_1d(omega), pto=pto)


def frequency_domain_series(ds, waves: Waves, t) -> dict:
    """The frequency-domain prediction of the free pair for the same wave components (amplitudes
    and phases) as the time-domain run: the relative motion, its velocity and the PTO power as time
    series, and their spectral (expected) statistics.

    The waves are cosine-phased, ``zeta = Re(a exp(i w t))``, and the RAOs are in Capytaine's
    convention, ``x = Re(RAO A exp(-i w t))`` for ``zeta = Re(A exp(-i w t))``, so
    ``x = Re(conj(RAO) a exp(i w t))``. Components outside the WAMIT band are left out (they carry
    less than 0.1 % of the sea's variance here).
    """
    w = np.asarray(waves.omega)
    a = np.asarray(waves.amplitude)
    band = (w >= float(ds.omega.min())) & (w <= float(ds.omega.max()))
    fd = frequency_domain(ds, w[band])
    H = np.conj(fd.pto_displacement.values) * a[band]
    ph = np.exp(1j * np.outer(np.asarray(t), w[band]))
    rel = (ph @ H).real
    vel = (ph @ (1j * w[band] * H)).real
    return {"relative": rel, "power": PTO_DAMPING * vel**2, "std": float(np.sqrt(np.sum(0.5 * np.abs(H) ** 2))),
            "mean_power": float(np.sum(0.5 * PTO_DAMPING * np.abs(w[band] * H) ** 2)),
            "variance_in_band": float(np.sum(np.abs(a[band]) ** 2) / np.sum(np.abs(a) ** 2))}


def figures(irr: dict, reg: dict, fd: dict, fds: dict, quick: bool) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    fig, axes = plt.subplots(4, 1, figsize=(10, 9), sharex=True)
    for key, ls, label in (("moored", "-", "moored (public RM3 MoorDyn deck)"), ("free", "--", "no moorings")):
        c = irr[key]
        axes[0].plot(c["t"], c["surge"], ls, lw=0.9, label=label)
        axes[1].plot(c["t"], np.degrees(c["pitch"]), ls, lw=0.9)
        axes[2].plot(c["t"], c["relative"], ls, lw=0.9)
        axes[3].plot(c["t"], c["power"] / 1e3, ls, lw=0.9)
    axes[2].plot(irr["free"]["t"], fds["relative"], ":", color="k", lw=0.8, label="frequency domain, same components")
    axes[2].legend(fontsize=8, loc="upper right")
    for ax, lab in zip(axes, ("spar surge [m]", "spar pitch [deg]", "float - spar [m]", "PTO power [kW]"),
                       strict=True):
        ax.set_ylabel(lab)
        ax.axvspan(0, RAMP, color="0.9")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(f"RM3 in a JONSWAP sea Hs {HS} m, Tp {TP} s (grey: ramp)")
    fig.tight_layout()
    paths.append(OUT / "rm3_irregular.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
    for ax, key, lab in zip(axes, ("surge", "pitch", "relative"),
                            ("spar surge [m²/Hz]", "spar pitch [rad²/Hz]", "relative motion [m²/Hz]"), strict=True):
        for case, ls in (("moored", "-"), ("free", "--")):
            c = irr[case]
            sel = c["t"] >= RAMP
            f, S = common.spectrum(c["t"][sel], c[key][sel], segment=100.0 if quick else 120.0)
            ax.semilogy(f, S, ls, label=case)
        ax.set_xlim(0, 0.4)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.suptitle("spectra after the ramp (Welch, Hann)")
    fig.tight_layout()
    paths.append(OUT / "rm3_spectra.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4))
    names = ["float heave", "spar heave", "spar surge", "spar pitch [deg]", "relative", "power [100 kW]"]
    vals = {k: [reg[k]["amp"][n] for n in ("float_heave", "heave", "surge", "pitch", "relative", "power")]
            for k in ("moored", "free")}
    vals["fd"] = [fd[n] for n in ("float_heave", "heave", "surge", "pitch", "relative", "power")]
    scale = np.array([1, 1, 1, 180 / np.pi, 1, 1e-5])
    x = np.arange(len(names))
    for k, (key, label) in enumerate((("fd", "frequency domain (free)"), ("free", "time domain, free"),
                                      ("moored", "time domain, moored"))):
        ax.bar(x + (k - 1) * 0.27, np.array(vals[key]) * scale, 0.27, label=label)
    ax.set_xticks(x, names, fontsize=8)
    ax.set_ylabel("amplitude [m] (pitch [deg], power [100 kW])")
    ax.set_title(f"RM3 in a regular wave H {H_REG} m, T {T_REG} s: steady amplitudes")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    paths.append(OUT / "rm3_regular.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)
    return paths


def main(argv=None) -> int:
    global OUT
    a, OUT = common.study_command(__doc__, "200 s records (CI)", HERE, argv)
    started = time.perf_counter()
    stem, deck = rm3_data()
    ds = hydro.read_wamit(stem, rho=RHO, g=G)
    duration = 200.0 if a.quick else 400.0
    irr_waves = Waves.jonswap(HS, TP, GAMMA, seed=SEED, ramp_time=RAMP)
    reg_waves = Waves.regular(H_REG, T_REG, ramp_time=RAMP)
    irr = {k: run_case(ds, deck, moored=k == "moored", waves=irr_waves, duration=duration) for k in ("moored", "free")}
    reg = {k: run_case(ds, deck, moored=k == "moored", waves=reg_waves, duration=duration) for k in ("moored", "free")}

    # ------------------------------------------------------------ regular wave: steady amplitudes
    w = 2 * np.pi / T_REG
    amp = H_REG / 2
    n_per = 10
    for c in reg.values():
        c["amp"] = {k: abs(common.steady_amplitude(c["t"], c[k], w, n_per))
                    for k in ("surge", "heave", "pitch", "float_heave", "relative")}
        sel = c["t"] >= c["t"][-1] - n_per * T_REG - 1e-9
        c["amp"]["power"] = float(np.mean(c["power"][sel]))
    fdr = frequency_domain(ds, w)
    rao = fdr.rao.values[0]
    fd = {"float_heave": abs(rao[2]) * amp, "heave": abs(rao[8]) * amp, "surge": abs(rao[6]) * amp,
          "pitch": abs(rao[10]) * amp, "relative": abs(fdr.pto_displacement.values[0]) * amp,
          "power": float(fdr.pto_power.values[0]) * amp**2}

    # ------------------------------------------------------------ irregular sea: statistics
    stats = {}
    for k, c in irr.items():
        sel = c["t"] >= RAMP
        stats[k] = {"relative_std": float(np.std(c["relative"][sel])), "power": float(np.mean(c["power"][sel])),
                    "surge_std": float(np.std(c["surge"][sel])), "surge_range": float(np.ptp(c["surge"][sel])),
                    "pitch_std": float(np.std(c["pitch"][sel])), "heave_std": float(np.std(c["heave"][sel]))}
        if "fairlead_tension" in c:
            stats[k]["fairlead_tension_mean"] = c["fairlead_tension"][sel].mean(axis=0)
            stats[k]["fairlead_tension_std"] = c["fairlead_tension"][sel].std(axis=0)
    fds = frequency_domain_series(ds, irr_waves, irr["free"]["t"])
    sel = irr["free"]["t"] >= 2 * RAMP  # the ramp and the transient it leaves behind
    fd_std = float(np.std(fds["relative"][sel]))
    td_std_window = float(np.std(irr["free"]["relative"][sel]))
    fd_power = float(np.mean(fds["power"][sel]))
    td_power_window = float(np.mean(irr["free"]["power"][sel]))

    chk = common.Checks()
    why_fd = ("raw WAMIT A(w), B(w) vs the passive fitted kernel the time loop integrates (0.5 %), generalized-alpha "
              "at T/160 (0.7 %), tests/floating/test_rm3.py")
    for n in ("relative", "float_heave", "heave", "surge", "pitch"):
        chk.add(f"regular, free: {n} amplitude, time vs frequency domain", reg["free"]["amp"][n], fd[n], 0.03,
                why=why_fd)
    chk.add("regular, free: mean PTO power, time vs frequency domain", reg["free"]["amp"]["power"], fd["power"], 0.06,
            why="power goes as the square of the relative velocity: twice the amplitude tolerance")
    chk.add("regular: relative motion moored vs free", reg["moored"]["amp"]["relative"], reg["free"]["amp"]["relative"],
            0.05, why="the paper: the moorings barely change the relative motion (their stiffness acts on surge)")
    chk.add("regular: PTO power moored vs free", reg["moored"]["amp"]["power"], reg["free"]["amp"]["power"], 0.10,
            why="twice the relative-motion tolerance")
    tol_irr = 0.05 if a.quick else 0.03
    chk.add("irregular, free: relative-motion std vs the frequency-domain series of the same components",
            td_std_window, fd_std, tol_irr,
            why="as in the regular wave, plus the transient of the ramp and the surge-pitch mode of the free pair "
                "(lightly damped), which the linear steady-state prediction does not hold")
    chk.add("irregular, free: mean PTO power vs the frequency-domain series", td_power_window, fd_power,
            2 * tol_irr, why="twice the relative-motion tolerance")
    chk.add("irregular: relative-motion std moored vs free", stats["moored"]["relative_std"],
            stats["free"]["relative_std"], 0.05, why="as for the regular wave")
    chk.bound("irregular: moorings restore surge (moored / free surge std)",
              stats["moored"]["surge_std"] / stats["free"]["surge_std"], hi=1.0,
              why="the paper: the moorings restore surge; without them the spar's surge has no restoring force")

    sink = float(SPAR_CG[2] - irr["moored"]["z0_spar_cg"])  # below the WAMIT (free-floating) pose
    results = {
        "relative_motion_std_m": {k: stats[k]["relative_std"] for k in ("moored", "free")},
        "mean_pto_power_w": {k: stats[k]["power"] for k in ("moored", "free")},
        "regular_relative_motion_amplitude_m": reg["moored"]["amp"]["relative"],
        "regular_mean_pto_power_w": reg["moored"]["amp"]["power"],
        "regular_free": {k: v for k, v in reg["free"]["amp"].items()},
        "regular_moored": {k: v for k, v in reg["moored"]["amp"].items()},
        "regular_frequency_domain": fd,
        "irregular_frequency_domain": {"window_start_s": 2 * RAMP, "relative_motion_std_m": fd_std,
                                       "mean_pto_power_w": fd_power, "time_domain_relative_motion_std_m": td_std_window,
                                       "time_domain_mean_pto_power_w": td_power_window,
                                       "spectral_relative_motion_std_m": fds["std"],
                                       "spectral_mean_pto_power_w": fds["mean_power"],
                                       "wave_variance_in_band": fds["variance_in_band"]},
        "irregular": stats,
        "spar_equilibrium_sink_m": sink,
        "sea": {"irregular": {"Hs_m": HS, "Tp_s": TP, "gamma": GAMMA, "seed": SEED, "duration_s": duration,
                              "ramp_s": RAMP, "components": int(irr_waves.n_components)},
                "regular": {"H_m": H_REG, "T_s": T_REG, "duration_s": duration, "ramp_s": RAMP}},
        "case_wall_time_s": {f"{kind}_{k}": c["wall"] for kind, d in (("irregular", irr), ("regular", reg))
                             for k, c in d.items()},
        "checks": chk.items, "comparisons": chk.comparisons, "passed": chk.passed,
    }
    out = common.write_results(OUT / "results.json", results, quick=a.quick, started=started)
    paths = figures(irr, reg, fd, fds, a.quick)
    print(f"RM3 ({out['mode']}, {out['wall_time_s']} s): spar sinks {sink:.3f} m under the moorings")
    for k in ("moored", "free"):
        print(f"  irregular {k}: relative motion std {stats[k]['relative_std']:.3f} m, mean PTO power "
              f"{stats[k]['power'] / 1e3:.1f} kW, surge std {stats[k]['surge_std']:.3f} m, pitch std "
              f"{np.degrees(stats[k]['pitch_std']):.2f} deg")
    print(f"  irregular, free, t >= {2 * RAMP:g} s: relative std {td_std_window:.3f} m (frequency-domain series "
          f"{fd_std:.3f} m, spectral {fds['std']:.3f} m), power {td_power_window / 1e3:.1f} kW (frequency domain "
          f"{fd_power / 1e3:.1f} kW, spectral {fds['mean_power'] / 1e3:.1f} kW)")
    for k in ("moored", "free"):
        print(f"  regular {k}: relative amplitude {reg[k]['amp']['relative']:.3f} m, power "
              f"{reg[k]['amp']['power'] / 1e3:.1f} kW")
    print(f"  regular, frequency domain: relative amplitude {fd['relative']:.3f} m, power {fd['power'] / 1e3:.1f} kW")
    print(chk.report())
    for p in paths:
        print(f"  wrote {p}")
    return 0 if chk.passed else 1


if __name__ == "__main__":
    sys.exit(main())
