"""Cost and centre curvatures of the 3D FE gridshell (prescribed-lambda route) for the Fig. 4
shapes: DOFs, path steps, Newton iterations, cut steps, wall time, peak memory, and the two
curvature measures against the paper's simulation and experiment (seed 001).

    python benchmarks/gridshell_fe_benchmark.py [--shapes dome saddle] [--level 0]
        [--symmetry quarter] [--kapton datasheet|buckling_fit] [--support table] [--json out.json]
    python benchmarks/gridshell_fe_benchmark.py --heated dome --duration 60
        [--dt 1] [--csv curvature_vs_time.csv]

``--heated dome``: the heated route (HeatedGridshellFE) with the paper's dome protocol
(DOME_PROTOCOL: 0.1 A top / 0.2 A bottom for 20 s, then 0.04 / 0.07 A held) on the published
rollers; one CSV row per time step (time, channel temperatures, currents and stretches, centre
curvatures, Newton iterations, wall time; units in the headers), rewritten after every step.

Not a test: it prints figures for the developers' guide and the report. Peak memory is the
process's high-water mark (ru_maxrss) after each shape: run one shape per call for per-shape
figures. The machine load matters: run it alone.
"""

from __future__ import annotations

import argparse
import platform
import resource
import time


def run_shape(
    shape: str, level: int, symmetry: str, kapton: str = "datasheet", support: str | None = None
) -> dict:
    """Build the shape's model, ramp it from the as-built state; returns the figures (units in
    keys). ``kapton``: a name of models.hyperelastic.KAPTON_MODULI (issue 16: "datasheet" is the
    choice); ``support``: a GridshellSupports kind (None: the shape's published one)."""
    from lcefem.models.hyperelastic import KAPTON_MODULI, NeoHookeanSolid
    from lcefem.solvers.problems.gridshell import GridshellMaterials, GridshellSupports
    from lcefem.validation.cases.programs import FIG4_SHAPES, fig4_shape

    t0 = time.perf_counter()
    materials = GridshellMaterials(kapton=NeoHookeanSolid(youngs_modulus=KAPTON_MODULI[kapton]))
    kw = {"supports": GridshellSupports(kind=support)} if support else {}
    model = fig4_shape(shape, mesh_level=level, symmetry=symmetry, materials=materials, **kw)
    build = time.perf_counter() - t0
    states = model.ramp(FIG4_SHAPES[shape])
    f = model.last_follower
    obs = model.observables()
    return {
        "shape": shape,
        "level": level,
        "symmetry": symmetry,
        "dofs": model.ndofs,
        "support": model.config.supports.kind,
        "kapton": kapton,
        "kapton youngs_modulus [MPa]": KAPTON_MODULI[kapton],
        "build [s]": build,
        "ramp [s]": model.wall_time,
        "steps": len(states),
        "newton iterations": f.iterations,
        "cut steps": f.cuts,
        "folds": f.snaps,
        "peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        **{k: v for k, v in obs.items() if not k.startswith("junction_")},
    }


def run_heated(
    level: int, symmetry: str, duration: float, dt: float, csv: str | None
) -> list[dict]:
    """The dome protocol on the heated route; prints and (``csv``) writes a row per step."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.solvers.problems.gridshell import GridshellConfig
    from lcefem.solvers.problems.gridshell_heated import HeatedGridshellFE
    from lcefem.solvers.runtime.files import write_text
    from lcefem.validation.cases.programs import DOME_PROTOCOL

    t0 = time.perf_counter()
    model = HeatedGridshellFE(
        GridshellConfig(mesh=GridshellFEMesh(level=level), symmetry=symmetry), dt=dt
    )
    print(
        f"heated dome: {model.ndofs} displacement DOFs, {model.heat.V.dofmap.index_map.size_global}"
        f" temperature DOFs, build {time.perf_counter() - t0:.1f} s",
        flush=True,
    )
    rows: list[dict] = []

    def on_step(row: dict) -> None:
        row = {k: v for k, v in row.items() if not k.startswith("junction_")}
        row["wall time [s]"] = time.perf_counter() - t0
        row["peak memory [MiB]"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        rows.append(row)
        print(
            f"t = {row['time [s]']:5.1f} s  T_mean Tx/Bx {row['T_mean Tx [C]']:6.1f} "
            f"{row['T_mean Bx [C]']:6.1f} C  lambda Tx/Bx {row['lambda Tx [-]']:.3f} "
            f"{row['lambda Bx [-]']:.3f}  kappa circle x/y {row['kappa_circle_x [1/mm]']:+.5f} "
            f"{row['kappa_circle_y [1/mm]']:+.5f}  quad x {row['kappa_quad_x [1/mm]']:+.5f} 1/mm"
            f"  {row['newton iterations [-]']} its  {row['wall time [s]']:.0f} s",
            flush=True,
        )
        if csv:
            head = list(rows[0])
            lines = [",".join(head)] + [",".join(f"{r.get(k, '')}" for k in head) for r in rows]
            write_text(csv, "\n".join(lines) + "\n")  # .part then rename

    model.run_protocol(DOME_PROTOCOL, duration=duration, dt=dt, on_step=on_step)
    return rows


def main(argv: list[str] | None = None) -> int:
    from lcefem.solvers.problems.gridshell import SUPPORT_KINDS
    from lcefem.validation.cases.programs import FIG4_SHAPES
    from lcefem.validation.studies.gridshell.gridshell_bh import SHAPES

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--shapes",
        nargs="+",
        default=["dome", "table", "saddle", "cylinder"],
        choices=list(FIG4_SHAPES),
    )
    parser.add_argument("--level", type=int, default=0, help="FE mesh level")
    parser.add_argument("--symmetry", default="quarter", help="reduced model")
    parser.add_argument(
        "--kapton",
        default="datasheet",
        choices=["datasheet", "buckling_fit"],
        help="Kapton modulus (models.hyperelastic.KAPTON_MODULI; issue 16)",
    )
    parser.add_argument(
        "--support",
        default=None,
        choices=list(SUPPORT_KINDS),
        help="support of every shape (default: each shape's published one)",
    )
    parser.add_argument(
        "--heated",
        choices=["dome"],
        default=None,
        help="run the heated route with the paper's protocol of this shape",
    )
    parser.add_argument("--duration", type=float, default=60.0, help="heated route: simulated s")
    parser.add_argument("--dt", type=float, default=1.0, help="heated route: time step [s]")
    parser.add_argument("--csv", default=None, help="heated route: curvature against time")
    parser.add_argument("--json", default=None, help="also write the figures to this file")
    args = parser.parse_args(argv)
    if args.heated:
        run_heated(args.level, args.symmetry, args.duration, args.dt, args.csv)
        return 0
    print(
        f"python {platform.python_version()}, {platform.processor() or platform.machine()}; "
        f"FE gridshell, {args.symmetry} model, level {args.level}, Kapton {args.kapton}, "
        f"supports {args.support or 'published'}"
    )
    rows = []
    for shape in args.shapes:
        r = run_shape(shape, args.level, args.symmetry, args.kapton, args.support)
        rows.append(r)
        sim, exp = SHAPES[shape]["paper_sim"], SHAPES[shape]["paper_exp"]
        print(
            f"{shape}: {r['dofs']} DOFs, {r['steps']} steps, {r['newton iterations']} Newton "
            f"iterations ({r['cut steps']} cuts, {r['folds']} folds), build {r['build [s]']:.1f} "
            "s, "
            f"ramp {r['ramp [s]']:.0f} s, peak {r['peak memory [MiB]']:.0f} MiB"
        )
        print(
            f"  kappa_x, kappa_y [1/mm]: circle {r['kappa_circle_x [1/mm]']:+.4f} "
            f"{r['kappa_circle_y [1/mm]']:+.4f}, quadratic {r['kappa_quad_x [1/mm]']:+.4f} "
            f"{r['kappa_quad_y [1/mm]']:+.4f}; paper simulation {sim}, experiment {exp}; "
            f"z range {r['z_range [mm]']:.2f} mm"
        )
        if "table_force [N]" in r:
            print(
                f"  on the table: reaction {r['table_force [N]']:.4f} N, apex "
                f"{r['apex_height_above_table [mm]']:.3f} mm above it, "
                f"{r['table_contact_nodes [-]']} nodes in contact"
            )
    if args.json:
        from lcefem.solvers.runtime.files import write_json

        write_json(args.json, rows)  # .part then rename, strict JSON
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
