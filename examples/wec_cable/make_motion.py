"""Write buoy_motion.csv: the motion of the cable's hang-off point under the buoy of wec_cable.dat
(one coupled point: x, y, z). Heave 1.2 m at 8 s and surge 0.8 m at 8 s with a quarter-period
lag (an orbital, wave-following motion), ramped in over 8 s with a quintic smoothstep; 0.05 s
samples for 96 s."""

from pathlib import Path

import numpy as np

OUT = Path(__file__).with_name("buoy_motion.csv")


def main(path=OUT, duration=96.0, dt=0.05, period=8.0):
    t = np.round(np.arange(0.0, duration + 0.5 * dt, dt), 10)
    u = np.clip(t / period, 0.0, 1.0)
    ramp = u**3 * (6 * u**2 - 15 * u + 10)
    w = 2 * np.pi / period
    x = 0.8 * ramp * np.cos(w * t)  # surge leads heave by a quarter period
    z = -2.0 + 1.2 * ramp * np.sin(w * t)
    np.savetxt(path, np.column_stack([t, x, np.zeros_like(t), z]), delimiter=",", header="t,P1_x,P1_y,P1_z",
               comments="", fmt="%.6f")
    return path


if __name__ == "__main__":
    print(main())
