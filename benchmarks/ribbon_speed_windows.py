"""Speed of the rolling ribbon in 15 s windows over 180 s on the plate (issue 32, the 180 C stall).

    nice python benchmarks/ribbon_speed_windows.py T NODES [NODES ...]

The default ribbon with contact sections 0.25 mm apart (``RibbonNumerics.contact_spacing``), 0.01 s
steps, on a plate at T [C]: prints one JSON line per node count with, per window, its start [s], the
centroid displacement over the window divided by its length [mm/s], the mean ribbon temperature [C]
and the contact points at its end, and the CPU seconds. Rows of
validation/data/ribbon_180C_speed_windows.csv.
"""

import dataclasses
import json
import sys
import time

import numpy as np

from lcefem.solvers.der.ribbon import RibbonNumerics
from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RibbonRun, run_ribbon


def main(argv: list[str]) -> None:
    """Run the windows for plate temperature argv[0] [C] and node counts argv[1:]."""
    T = float(argv[0])
    for n in [int(a) for a in argv[1:]]:
        cfg = RibbonConfig(
            run=RibbonRun(ground_temperature=T, duration=180.0, output_interval=0.0),
            numerics=dataclasses.replace(RibbonNumerics(), nodes=n, dt=0.01, contact_spacing=0.25),
        )
        t0 = time.process_time()
        r = run_ribbon(cfg, None, progress=False, fields=False)
        h = r.history
        t = np.asarray(h["time [s]"])
        x = np.asarray(h["centroid_x [mm]"])
        y = np.asarray(h["centroid_y [mm]"])
        Tm = np.asarray(h["T_mean [C]"])
        cp = np.asarray(h["contact_points [-]"])
        t_end = t[-1]
        edges = np.arange(t_end - 180.0, t_end + 1e-6, 15.0)
        out = []
        for a, b in zip(edges[:-1], edges[1:]):
            i, j = np.searchsorted(t, a), min(np.searchsorted(t, b), len(t) - 1)
            out.append(
                (
                    round(a - edges[0]),
                    round(float(np.hypot(x[j] - x[i], y[j] - y[i]) / (t[j] - t[i])), 3),
                    round(float(Tm[j]), 1),
                    int(cp[j]),
                )
            )
        print(
            json.dumps(
                {
                    "T": T,
                    "nodes": n,
                    "cpu": time.process_time() - t0,
                    "windows (t0 [s], speed [mm/s], T_mean [C], contact points)": out,
                }
            ),
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:])
