"""The rolling twisted ribbon meeting a rigid wall on the hot plate, head-on and at an angle (seed
000, Fig. 1: the robot turns away from an obstacle).

    OMP_NUM_THREADS=1 python -m lcefem.validation.studies.ribbon.ribbon_obstacle \
        [--angles 0 30] [--distance 5]
        [--nodes 31] [--duration 60] [--ground-temperature 100] [--csv out.csv]

For each wall angle (and a run without a wall) it prints, every ``--every`` simulated seconds, the
centroid [mm], its speed [mm/s] and heading [deg from +x], the spin of both ends [rad] and the
smallest gap of the ribbon to the wall [mm] (the contact's smoothing width is 0.05 mm: a gap below
minus that would be a pass-through). Not a test (tests/solvers/test_der_obstacle.py checks the
no-pass-through bound): what the model does, for the README.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import os

from lcefem.models.contact import Wall
from lcefem.models.ribbon import RibbonGeometry
from lcefem.solvers.der.ribbon import RibbonNumerics, RibbonSetup, RibbonSimulation


def run(
    angle: float | None,
    distance: float,
    nodes: int,
    duration: float,
    ground_temperature: float,
    every: float,
) -> list[dict]:
    walls = () if angle is None else (Wall(distance=distance, angle=angle),)
    setup = RibbonSetup(
        geometry=RibbonGeometry(),
        ground_temperature=ground_temperature,
        numerics=dataclasses.replace(RibbonNumerics(), nodes=nodes),
        walls=walls,
    )
    sim = RibbonSimulation(setup)
    dt = setup.numerics.dt
    per = max(1, int(round(every / dt)))
    rows = []
    label = "no wall" if angle is None else f"wall {angle:g} deg"
    for i in range(1, int(round(duration / dt)) + 1):
        sim.step(dt)
        if i % per == 0:
            obs = sim.observe()
            v = sim.state.v.mean(axis=0)
            gaps = sim.wall_gaps()
            rows.append(
                {
                    "case": label,
                    "time [s]": obs["time [s]"],
                    "centroid_x [mm]": obs["centroid_x [mm]"],
                    "centroid_y [mm]": obs["centroid_y [mm]"],
                    "speed [mm/s]": obs["speed [mm/s]"],
                    "heading [deg]": math.degrees(math.atan2(v[1], v[0])),
                    "spin_start [rad]": obs["spin_start [rad]"],
                    "spin_end [rad]": obs["spin_end [rad]"],
                    "wall_gap [mm]": float(gaps.min()) if len(gaps) else float("nan"),
                }
            )
            r = rows[-1]
            print(
                f"  {label:12s} t {r['time [s]']:6.1f} s  centroid ({r['centroid_x [mm]']:7.3f}, "
                f"{r['centroid_y [mm]']:7.3f}) mm  speed {r['speed [mm/s]']:6.3f} mm/s  heading "
                f"{r['heading [deg]']:7.1f} deg  spins {r['spin_start [rad]']:7.2f} "
                f"{r['spin_end [rad]']:7.2f} rad "
                " "
                f"wall gap {r['wall_gap [mm]']:7.3f} mm",
                flush=True,
            )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--angles", type=float, nargs="+", default=[0.0, 30.0], help="wall angles [deg]"
    )
    parser.add_argument(
        "--distance", type=float, default=5.0, help="wall distance from the centre line [mm]"
    )
    parser.add_argument("--nodes", type=int, default=31)
    parser.add_argument(
        "--duration", type=float, default=60.0, help="simulated time on the plate [s]"
    )
    parser.add_argument(
        "--ground-temperature", type=float, default=100.0, help="plate temperature [C]"
    )
    parser.add_argument("--every", type=float, default=5.0, help="report interval [s]")
    parser.add_argument("--no-reference", action="store_true", help="skip the run without a wall")
    parser.add_argument("--csv", help="write all rows to this CSV file")
    args = parser.parse_args(argv)
    if args.duration <= 0 or args.distance <= 0 or args.every <= 0:
        parser.error("--duration, --distance and --every must be > 0")
    rows = []
    for angle in ([] if args.no_reference else [None]) + list(args.angles):
        rows += run(
            angle, args.distance, args.nodes, args.duration, args.ground_temperature, args.every
        )
    if args.csv and rows:
        tmp = args.csv + ".part"
        with open(tmp, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        os.replace(tmp, args.csv)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
