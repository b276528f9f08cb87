"""Strip temperatures and lambdas over time of a gridshell current sequence (issue 31,
docs/gridshell_thermal.md): ``python -m lcefem.validation.studies.gridshell.gridshell_thermal_plots
HISTORY.csv OUT.png`` reads the history.csv of ``lcefem run gridshell --schedule`` (time [s], per
channel temperature [C] and lambda [-]) and draws both over time, with T_NI of the calibrated
transition."""

from __future__ import annotations

import csv
import pathlib
import sys

from lcefem.models.lce import NematicTransition

CHANNELS = ("Tx", "Ty", "Bx", "By")


def plot_strip_temperatures(history: pathlib.Path, png: pathlib.Path) -> pathlib.Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = list(csv.DictReader(open(history)))
    t = [float(r["time [s]"]) for r in rows]
    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ch in CHANNELS:
        key = f"{ch} temperature [C]"
        if key in rows[0]:
            a.plot(t, [float(r[key]) for r in rows], label=ch)
            b.plot(t, [float(r[f"{ch} lambda [-]"]) for r in rows], label=ch)
    a.axhline(NematicTransition().T_NI, color="k", lw=0.6, ls=":", label="T_NI (calibrated)")
    a.set_ylabel("strip temperature [C]")
    b.set_ylabel("strip lambda [-]")
    b.set_xlabel("time [s]")
    a.legend(fontsize=8)
    a.set_title("lumped grid strips (thermal model 'strip', calibrated grid exchange)", fontsize=9)
    png = pathlib.Path(png)
    part = png.with_name(png.stem + ".part.png")
    fig.tight_layout()
    fig.savefig(part, dpi=110)
    plt.close(fig)
    part.replace(png)
    return png


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(
            "usage: python -m lcefem.validation.studies.gridshell.gridshell_thermal_plots "
            "HISTORY.csv OUT.png",
            file=sys.stderr,
        )
        raise SystemExit(2)
    print(plot_strip_temperatures(pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])))
