"""The 3D FE confirmation of the reach study's best designs (issue 47, item 3): the Gaussian bump
and the two-wave surface on the refined 5 x 5 grid with a drive per strip
(:mod:`lcefem.validation.studies.design.gridshell_reach_study`), run with the FE gridshell.

    python benchmarks/gridshell_reach_fe.py --design DIR            # 1. the BH designs -> DIR
    python benchmarks/gridshell_reach_fe.py --fe two-wave DIR [--symmetrize]  # 2. one FE run
    python benchmarks/gridshell_reach_fe.py --bh-check DIR          # 2b. the BH from as built
    python benchmarks/gridshell_reach_fe.py --collect DIR [--data FILE]  # 3. -> the data file
    python benchmarks/gridshell_reach_fe.py --space-map two-wave DIR --iterations 3  # 4.
    python benchmarks/gridshell_reach_fe.py --collect-space-map DIR  # 5. -> its data file

1. ``gridshell_reach_study.best_surface(target, "5x5", "per strip", max_evaluations=40)`` (the case
   gridshell_reach_study_bh's full level): the design's lambda per bar-and-hinge strip id, its BH
   RMS distance [mm], written to ``DIR/design_<target>.json``.
2. The design's lambdas mapped to the FE strip tags of the 5 x 5 gmsh mesh
   (:func:`lcefem.meshes.gridshell_fe.fe_lambdas_of_strips`), symmetrized over the grid's two mirror
   planes (mean of each strip and its mirror images) when they differ from it by no more than
   :data:`SYMMETRIZE_TOL` (the design loop's round-off; the quarter model then applies, 4 times
   cheaper than the whole surface), or always with ``--symmetrize`` (the designs of 2026-12-07
   depart from their mirror means by 0.029 and 0.011, which move the BH's RMS by 0.016 and
   0.001 mm: ``--bh-check``), ramped from the as-built state (level 0, rollers). The FE
   surface's RMS distance from the target uses the study's rigid fit
   (``gridshell_reach_study.rigid_residual``) at the same material points as the BH's: the
   as-built centres of the BH's Kapton panels, evaluated on the FE ribbon's mid-surface.
   Written to ``DIR/fe_<target>.json``.
3. Both targets' records -> ``validation/data/gridshell_fe_reach_designs_level0.json``.
4. The FE-corrected design (output space mapping,
   :mod:`lcefem.validation.studies.design.space_mapping`): from the design of step 1 (or, without
   ``DIR/design_<target>.json``, the one stored in ``--data``), at most ``--iterations`` FE runs as
   in step 2 (``--symmetrize``); after each, the gap D = r_FE - r_BH between the rigid residuals at
   the panel centres of the same mirror-mean drives (the BH from as built,
   ``gridshell_reach_study.surface_at``) corrects the BH target to T - D, and
   ``best_surface(..., p0=the FE-run drives, offset=D)`` redesigns; stops when the FE's RMS from T
   stops falling. Residuals rather than raw heights: the FE and BH points also move in plane and
   each fit removes its own plane; with the residuals the corrected BH equals the FE at the design.
   Written to ``DIR/space_map_<target>.json`` (per run: ``design_<target>_sm<k>.json``,
   ``fe_<target>_sm<k>.json``).
5. Both targets' space maps -> ``validation/data/gridshell_fe_reach_space_map_level0.json``.

Not a test: it prints figures. CPU time is the process's; wall times on a shared machine are upper
bounds.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import pathlib
import resource
import sys
import time

import numpy as np

DATA = (
    pathlib.Path(__file__).parents[1]
    / "validation"
    / "data"
    / "gridshell_fe_reach_designs_level0.json"
)
#: The FE-corrected designs (--space-map, --collect-space-map).
SPACE_MAP_DATA = DATA.with_name("gridshell_fe_reach_space_map_level0.json")
TARGETS = ("gaussian bump", "two-wave")
GRID, WIRING, SUPPORT = "5x5", "per strip", "rollers"
#: Largest |lambda - its mirror images' mean| [-] that is symmetrized (the design's round-off;
#: above it the design is taken as asymmetric and run on the whole surface).
SYMMETRIZE_TOL = 1e-6


def _slug(target: str) -> str:
    return target.replace(" ", "_")


def _write(path: pathlib.Path, data: dict) -> None:
    tmp = path.with_suffix(path.suffix + ".part")
    tmp.write_text(json.dumps(data, indent=1) + "\n")
    tmp.replace(path)


def reach_structure():
    """The study's refined 5 x 5 (FE-calibrated set): its layout and bar-and-hinge structure."""
    from lcefem.validation.studies.design import gridshell_reach_study as rs
    from lcefem.validation.studies.gridshell import calibrate

    layout = dataclasses.replace(rs.GRIDS[GRID], wiring=rs.WIRINGS[WIRING][1])
    return layout, calibrate.model_set(calibrate.DEFAULT_MODEL_SET).structure(layout)


def _header(target: str) -> dict:
    """The entries every record of ``target`` starts with: the target, its source, grid, wiring
    and support."""
    from lcefem.validation.studies.design import gridshell_reach_study as rs

    return {
        "target": target,
        "target source": rs.TARGETS[target][1],
        "grid": GRID,
        "wiring": WIRING,
        "support": SUPPORT,
    }


def design(target: str, out: pathlib.Path) -> dict:
    """Step 1: the BH design of ``target`` (module docstring)."""
    from lcefem.validation.studies.design import gridshell_reach_study as rs

    r = rs.best_surface(target, GRID, WIRING, max_evaluations=40)
    _, structure = reach_structure()
    rec = {
        **_header(target),
        "BH RMS [mm]": r.rms,
        "drives [-]": r.variables,
        "evaluations [-]": r.evaluations,
        "BH CPU [s]": r.cpu,
        # the design variables are the strip ids in order (gridshell_design.channel_selections)
        "lambda per BH strip id [-]": {
            str(s.id): float(v) for s, v in zip(structure.info["strips"], r.lambdas)
        },
        "BH panel centres [mm]": (
            r.x[structure.panel_centres].tolist() if r.x is not None else None
        ),
        "date": datetime.date.today().isoformat(),
    }
    out.mkdir(parents=True, exist_ok=True)
    _write(out / f"design_{_slug(target)}.json", rec)
    print(f"{target}: BH RMS {r.rms:.4f} mm, {r.evaluations} evaluations, {r.cpu:.1f} s CPU")
    return rec


def mirror_orbits(catalogue: dict, centre: float) -> list[set]:
    """The FE strip tags grouped by the grid's two mirror planes x = c and y = c (each strip with
    its mirror images)."""
    from lcefem.solvers.problems.gridshell_fe_run import mirror_image

    orbits, seen = [], set()
    for tag in catalogue:
        if tag in seen:
            continue
        mx = mirror_image(catalogue, tag, 0, centre)
        orbit = {tag, mx, mirror_image(catalogue, tag, 1, centre)}
        orbit.add(mirror_image(catalogue, mx, 1, centre))
        seen |= orbit
        orbits.append(orbit)
    return orbits


def symmetrized(values: dict, catalogue: dict, centre: float) -> tuple[dict, float]:
    """``values`` ({FE strip tag: lambda}) with each strip at the mean of its mirror orbit, and the
    largest |lambda - that mean| [-] removed."""
    out, dev = dict(values), 0.0
    for orbit in mirror_orbits(catalogue, centre):
        mean = float(np.mean([values[t] for t in orbit]))
        dev = max(dev, max(abs(values[t] - mean) for t in orbit))
        out.update(dict.fromkeys(orbit, mean))
    return out, dev


def fe_config(layout, lambdas: dict, level: int = 0):
    """The FE run of ``lambdas`` ({FE strip tag: lambda}) on ``layout`` (the gmsh mesh, as
    ``lcefem run gridshell --model fe --layout``), rollers, mesh ``level``."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.meshes.gridshell_fe_gmsh import layout_fe_geometry
    from lcefem.solvers.problems.gridshell import GridshellConfig
    from lcefem.solvers.problems.gridshell_fe_run import (
        GridshellFERun,
        GridshellFERunConfig,
        supports_of,
    )

    model = GridshellConfig(
        mesh=GridshellFEMesh(level=level, mesher="gmsh", shear_angle=float(layout.angle)),
        supports=supports_of(SUPPORT),
        cells=layout.ribbons,
    )
    model = dataclasses.replace(model, geometry=layout_fe_geometry(layout, model.geometry))
    run = GridshellFERun(drive="lambda", label=f"{len(lambdas)} FE strip lambdas")
    return GridshellFERunConfig(model=model, run=run, lambdas=lambdas).validated()


def ribbon_points(model, cfg, xy: np.ndarray) -> np.ndarray:
    """Deformed positions (m, 3) [mm] of the FE ribbon's mid-surface at the as-built plan points
    ``xy`` (m, 2) [mm] of the full surface: u evaluated at (x, y, arch(x) + arch(y)) (the ribbon's
    as-built mid-surface, meshes.gridshell_fe.arch_at), mirror images for points outside a reduced
    model."""
    import dolfinx

    from lcefem.meshes.gridshell_fe import arch_at

    c = model.info["centre"]
    cut_x, cut_y = "sym_x" in model.tmesh.facets, "sym_y" in model.tmesh.facets
    fx = cut_x & (xy[:, 0] < c - 1e-9)
    fy = cut_y & (xy[:, 1] < c - 1e-9)
    p = xy.copy()
    p[fx, 0] = 2 * c - p[fx, 0]
    p[fy, 1] = 2 * c - p[fy, 1]
    g = dataclasses.replace(cfg.model.geometry, segments=cfg.model.cells + 1)
    n = cfg.model.cells
    pts = np.column_stack([p, arch_at(g, n, p[:, 0]) + arch_at(g, n, p[:, 1])])
    mesh = model.tmesh.mesh
    tree = dolfinx.geometry.bb_tree(mesh, mesh.topology.dim)
    cand = dolfinx.geometry.compute_collisions_points(tree, pts)
    hit = dolfinx.geometry.compute_colliding_cells(mesh, cand, pts)
    cells = []
    for i in range(len(pts)):
        links = hit.links(i)
        if len(links) == 0:
            raise RuntimeError(f"no FE cell at the ribbon point {pts[i]} mm")
        cells.append(links[0])
    x = pts + model.u.eval(pts, np.asarray(cells, dtype=np.int32))
    x[fx, 0] = 2 * c - x[fx, 0]
    x[fy, 1] = 2 * c - x[fy, 1]
    return x


def fe_run(
    target: str, folder: pathlib.Path, level: int = 0, force: bool = False, stem: str | None = None
) -> dict:
    """Step 2: the FE run of the design of ``target`` (module docstring); ``force``: symmetrize
    whatever the design's departure from its mirror images (the quarter model; the departure is
    recorded). ``stem``: the design ``DIR/design_<stem>.json`` -> ``DIR/fe_<stem>.json`` (default
    the target's name)."""
    from lcefem.meshes.gridshell_fe import fe_lambdas_of_strips
    from lcefem.solvers.problems.gridshell_fe_run import run_gridshell_fe
    from lcefem.validation.studies.design import gridshell_reach_study as rs

    stem = stem or _slug(target)
    rec = json.loads((folder / f"design_{stem}.json").read_text())
    layout, structure = reach_structure()
    per_id = {int(k): v for k, v in rec["lambda per BH strip id [-]"].items()}
    mapped = fe_lambdas_of_strips(structure.info["strips"], per_id)
    cfg = fe_config(layout, mapped, level)
    centre = float(np.mean(_centres(cfg)))
    sym, dev = symmetrized(mapped, cfg.catalogue(), centre)
    if dev <= SYMMETRIZE_TOL or force:
        cfg = fe_config(layout, sym, level)
    z = rs.TARGETS[target][0]
    xy0 = structure.nodes[structure.panel_centres][:, :2]
    found = {}

    def report(out, cfg_, model):
        x = ribbon_points(model, cfg_, xy0)
        r = rs.rigid_residual(x, z)
        found["rms"] = float(np.sqrt(np.mean(r * r)))
        found["x"] = x
        return {"RMS distance from the target [mm]": found["rms"]}

    out = folder / f"fe_{stem}"
    c0 = time.process_time()
    s = run_gridshell_fe(cfg, out, progress=False, report=report)
    cpu = time.process_time() - c0
    fe = {
        "FE RMS [mm]": found["rms"],
        "FE symmetry": cfg.symmetry,
        "largest |lambda - mirror mean| [-]": dev,
        "symmetrized": dev <= SYMMETRIZE_TOL or force,
        "dofs [-]": s["dofs [-]"],
        "newton iterations [-]": s["newton iterations [-]"],
        "path steps [-]": s["path steps [-]"],
        "FE CPU [s]": cpu,
        "FE wall [s]": s["wall time [s]"],
        "peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "circle kappa_x [1/mm]": s["results"]["kappa_circle_x [1/mm]"],
        "circle kappa_y [1/mm]": s["results"]["kappa_circle_y [1/mm]"],
        "z range [mm]": s["results"]["z_range [mm]"],
        "FE panel centres [mm]": found["x"].tolist(),
        "mesh level": level,
        "date": datetime.date.today().isoformat(),
    }
    if rec.get("BH panel centres [mm]") is not None:
        xb = np.asarray(rec["BH panel centres [mm]"])
        d = rs.rigid_residual(found["x"], z) - rs.rigid_residual(xb, z)
        fe["RMS of FE - BH residuals [mm]"] = float(np.sqrt(np.mean(d * d)))
    _write(folder / f"fe_{stem}.json", fe)
    print(
        f"{target}: FE RMS {found['rms']:.4f} mm (BH {rec['BH RMS [mm]']:.4f} mm), "
        f"{cfg.symmetry}, {s['dofs [-]']} DOFs, {cpu:.1f} s CPU"
    )
    return fe


def _centres(cfg) -> np.ndarray:
    from lcefem.meshes.gridshell_fe import junction_centres

    return junction_centres(cfg.model.geometry, cfg.model.cells)


def bh_check(target: str, folder: pathlib.Path) -> dict:
    """The BH of the design's drives and of their mirror means, each ramped from the as-built state
    (the design loop's equilibrium is warm-started, not checked from flat): RMS distances [mm]."""
    from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
    from lcefem.validation.studies.design import gridshell_reach_study as rs
    from lcefem.validation.studies.gridshell import calibrate

    rec = json.loads((folder / f"design_{_slug(target)}.json").read_text())
    layout, structure = reach_structure()
    per_id = {int(k): v for k, v in rec["lambda per BH strip id [-]"].items()}
    ms = calibrate.model_set(calibrate.DEFAULT_MODEL_SET)
    out = {}
    for label, drive in (("design", per_id), ("symmetrized", mirror_mean_drives(per_id)[0])):
        c0 = time.process_time()
        p = GridshellBH(
            ms.structure(layout),
            GridshellBHConfig(materials=ms.materials_for(layout), support=SUPPORT),
        )
        p.set_drives(drive)
        p.advance()
        r = rs.rigid_residual(p.x.reshape(-1, 3)[structure.panel_centres], rs.TARGETS[target][0])
        out[f"BH RMS from as built, {label} drives [mm]"] = float(np.sqrt(np.mean(r * r)))
        out[f"BH CPU from as built, {label} drives [s]"] = time.process_time() - c0
    _write(folder / f"bh_check_{_slug(target)}.json", out)
    print(target, out)
    return out


def collect(folder: pathlib.Path, data: pathlib.Path) -> dict:
    """Step 3: the designs and FE runs of both targets -> ``data`` (rows without the positions)."""
    rows = []
    for t in TARGETS:
        d = json.loads((folder / f"design_{_slug(t)}.json").read_text())
        fe = json.loads((folder / f"fe_{_slug(t)}.json").read_text())
        check = folder / f"bh_check_{_slug(t)}.json"
        fe.update(json.loads(check.read_text()) if check.exists() else {})
        rows.append(
            {
                **{k: v for k, v in d.items() if "panel centres" not in k and k != "date"},
                **{k: v for k, v in fe.items() if "panel centres" not in k and k != "date"},
            }
        )
    costs = "; ".join(
        f"{r['target']}: BH {r['BH CPU [s]']:.0f} s CPU ({r['evaluations [-]']} evaluations), FE "
        f"{r['FE symmetry']}, {r['dofs [-]']:,} DOFs, {r['FE CPU [s]']:.0f} s CPU "
        f"({r['FE wall [s]']:.0f} s wall)"
        for r in rows
    )
    record = {
        "source": (
            "the reach study's best designs (validation.studies.design.gridshell_reach_study."
            "best_surface(target, '5x5', 'per strip', max_evaluations=40): FE-calibrated "
            "bar-and-hinge, rollers) mapped to the FE strip tags "
            "(meshes.gridshell_fe.fe_lambdas_of_strips) and ramped from the as-built state with "
            "lcefem.solvers.problems.gridshell.GridshellFE on the gmsh mesh of the same layout "
            "(pitch 24.67 mm, 141 mm side), mesh level 0, rollers, datasheet Kapton; where "
            "'symmetrized', the FE drives are the mirror means of the design's lambdas (quarter "
            "model; the row gives the design's largest departure from them and the BH RMS of both "
            "drives from the as-built state); RMS distance "
            "from the target after the study's rigid fit (rigid_residual) at the BH's Kapton panel "
            "centres (FE: the ribbon's mid-surface at their as-built plan points); "
            f"python benchmarks/gridshell_reach_fe.py, {datetime.date.today()} (issue 47); "
            f"{costs}; serial, shared 2-core machine"
        ),
        "units": {
            "BH RMS [mm]": "mm",
            "FE RMS [mm]": "mm",
            "lambda per BH strip id [-]": "-",
            "circle kappa_x [1/mm]": "1/mm",
        },
        "rows": rows,
    }
    _write(data, record)
    for r in rows:
        print(f"{r['target']}: BH {r['BH RMS [mm]']:.3f} mm, FE {r['FE RMS [mm]']:.3f} mm")
    return record


def mirror_mean_drives(per_id: dict) -> tuple[dict, float]:
    """The BH drives ({BH strip id: lambda}) at the mirror means of their FE strips (the drives
    the quarter FE model runs) and the largest |lambda - mirror mean| [-]."""
    from lcefem.meshes.gridshell_fe import fe_lambdas_of_strips, fe_strip_tags

    layout, structure = reach_structure()
    strips = structure.info["strips"]
    mapped = fe_lambdas_of_strips(strips, per_id)
    cfg = fe_config(layout, mapped)
    sym, dev = symmetrized(mapped, cfg.catalogue(), float(np.mean(_centres(cfg))))
    return {s.id: sym[fe_strip_tags(s)[0]] for s in strips}, dev


def _initial_design(target: str, folder: pathlib.Path, data: pathlib.Path) -> dict:
    """d0: ``DIR/design_<target>.json`` (step 1) if present, else the stored design of ``data``
    (the same best_surface run, kept there with its lambdas)."""
    own = folder / f"design_{_slug(target)}.json"
    if own.exists():
        return json.loads(own.read_text())
    rows = json.loads(data.read_text())["rows"]
    row = next((r for r in rows if r["target"] == target), None)
    if row is None:
        raise FileNotFoundError(2, "no design of this target", str(own))
    keep = ("target", "target source", "grid", "wiring", "support", "BH RMS [mm]", "drives [-]")
    rec = {k: row[k] for k in keep} | {
        "lambda per BH strip id [-]": row["lambda per BH strip id [-]"]
    }
    rec["design source"] = f"{data.name} (stored best_surface design)"
    return rec


def space_map(target: str, folder: pathlib.Path, iterations: int, data: pathlib.Path) -> dict:
    """Output space mapping of ``target``'s design (validation.studies.design.space_mapping): at
    most ``iterations`` FE runs; each FE run's gap D = r_FE - r_BH (the rigid residuals at the
    panel centres of the same mirror-mean drives, the BH from as built) corrects the BH target to
    T - D, and the BH redesign starts from the FE-run drives. -> ``DIR/space_map_<target>.json``."""
    from lcefem.validation.studies.design import gridshell_reach_study as rs
    from lcefem.validation.studies.design.space_mapping import output_space_map, rms

    d0_rec = _initial_design(target, folder, data)
    folder.mkdir(parents=True, exist_ok=True)
    z = rs.TARGETS[target][0]
    _, structure = reach_structure()
    ids = [s.id for s in structure.info["strips"]]  # the design variables' order
    d0 = np.array([d0_rec["lambda per BH strip id [-]"][str(i)] for i in ids])
    rows: list[dict] = []
    pending: dict = {}

    def sym_vector(d):
        drives, dev = mirror_mean_drives(dict(zip(ids, map(float, d))))
        return np.array([drives[i] for i in ids]), dev

    def fine(d):
        k = len(rows)
        stem = f"{_slug(target)}_sm{k}"
        rec = {**d0_rec, "lambda per BH strip id [-]": {str(i): float(v) for i, v in zip(ids, d)}}
        rec.pop("BH panel centres [mm]", None)
        rec["BH RMS [mm]"] = pending.get("bh_rms_corrected", d0_rec["BH RMS [mm]"])
        _write(folder / f"design_{stem}.json", rec)
        fe = fe_run(target, folder, force=True, stem=stem)
        pending["fe"] = fe
        return rs.rigid_residual(np.asarray(fe["FE panel centres [mm]"]), z)

    def coarse(d):
        c0 = time.process_time()
        ds, dev = sym_vector(d)
        x = rs.surface_at(target, GRID, WIRING, ds)
        r = rs.rigid_residual(x[structure.panel_centres], z)
        pending["bh_at"] = (rms(r), time.process_time() - c0, dev)
        return r

    def redesign(d, gap):
        ds, _ = sym_vector(d)
        r = rs.best_surface(target, GRID, WIRING, max_evaluations=40, p0=ds, offset=gap)
        pending["redesign"] = (r.evaluations, r.cpu)
        pending["bh_rms_corrected"] = r.rms
        print(
            f"{target}: redesign for T - D: BH RMS {r.rms:.4f} mm, {r.evaluations} evaluations, "
            f"{r.cpu:.1f} s CPU",
            flush=True,
        )
        return r.lambdas, r.rms

    def on_step(k, step):
        fe = pending.pop("fe")
        bh_rms, bh_cpu, dev = pending.pop("bh_at")
        evaluations, design_cpu = pending.pop("redesign", (None, None))
        rows.append(
            {
                "iteration": k,
                "BH RMS to T - D of the previous gap, design loop [mm]": step.coarse_rms,
                "BH evaluations [-]": evaluations,
                "BH design CPU [s]": design_cpu,
                "BH RMS to T from as built, mirror-mean drives [mm]": bh_rms,
                "BH from as built CPU [s]": bh_cpu,
                "largest |lambda - mirror mean| [-]": dev,
                "FE RMS to T [mm]": step.fine_rms,
                "FE CPU [s]": fe["FE CPU [s]"],
                "FE wall [s]": fe["FE wall [s]"],
                "FE symmetry": fe["FE symmetry"],
                "dofs [-]": fe["dofs [-]"],
                "RMS of the gap D [mm]": rms(step.gap),
                "lambda per BH strip id [-]": {str(i): float(v) for i, v in zip(ids, step.design)},
            }
        )
        print(
            f"{target}: space map {k}: FE RMS to T {step.fine_rms:.4f} mm "
            f"({fe['FE CPU [s]']:.0f} s CPU), BH from as built {bh_rms:.4f} mm, "
            f"|D| {rms(step.gap):.4f} mm",
            flush=True,
        )
        _write(folder / f"space_map_{_slug(target)}.json", _space_map_record(target, rows, None))

    _, best = output_space_map(d0, fine, coarse, redesign, max_fine=iterations, on_step=on_step)
    rec = _space_map_record(target, rows, best)
    _write(folder / f"space_map_{_slug(target)}.json", rec)
    return rec


def _space_map_record(target: str, rows: list[dict], best: int | None) -> dict:
    out = {
        **_header(target),
        "iterations": rows,
        "date": datetime.date.today().isoformat(),
    }
    if best is not None:
        out |= {
            "best iteration": best,
            "FE RMS [mm]": rows[best]["FE RMS to T [mm]"],
            "start FE RMS [mm]": rows[0]["FE RMS to T [mm]"],
            "total CPU [s]": sum(
                r["FE CPU [s]"] + (r["BH design CPU [s]"] or 0) + r["BH from as built CPU [s]"]
                for r in rows
            ),
        }
    return out


def collect_space_map(folder: pathlib.Path, data: pathlib.Path) -> dict:
    """The space-mapping records of both targets -> ``data``."""
    rows = []
    for t in TARGETS:
        rec = json.loads((folder / f"space_map_{_slug(t)}.json").read_text())
        if "best iteration" not in rec:
            raise FileNotFoundError(2, "space mapping not finished", str(folder))
        rows.append({k: v for k, v in rec.items() if k != "date"})
    costs = "; ".join(
        f"{r['target']}: {len(r['iterations'])} FE runs, {r['total CPU [s]']:.0f} s CPU"
        for r in rows
    )
    record = {
        "source": (
            "output space mapping (Bandler et al., IEEE Trans. Microwave Theory Tech. 52 (2004) "
            "337; validation.studies.design.space_mapping) of the reach study's best designs "
            "(gridshell_fe_reach_designs_level0.json, iteration 0) on the refined 5 x 5, a drive "
            "per strip, rollers: the gap D = r_FE - r_BH between the rigid residuals "
            "(gridshell_reach_study.rigid_residual) at the BH's Kapton panel centres of the same "
            "mirror-mean drives (FE: quarter model, mesh level 0, datasheet Kapton, the ribbon's "
            "mid-surface at their as-built plan points; BH: FE-calibrated set from as built) "
            "corrects the BH target to T - D; best_surface(..., max_evaluations=40, p0=the "
            "FE-run drives, offset=D) redesigns; the FE runs the new design's mirror means; stop "
            "when the FE RMS from T stops falling; no model parameter changed; "
            f"python benchmarks/gridshell_reach_fe.py --space-map, {datetime.date.today()} "
            f"(issue 47); {costs}; serial, shared 2-core machine"
        ),
        "units": {"RMS": "mm", "CPU": "s", "lambda": "-"},
        "rows": rows,
    }
    _write(data, record)
    for r in rows:
        print(
            f"{r['target']}: FE RMS {r['start FE RMS [mm]']:.3f} -> {r['FE RMS [mm]']:.3f} mm "
            f"(iteration {r['best iteration']})"
        )
    return record


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", metavar="DIR")
    ap.add_argument("--target", action="append", choices=TARGETS)
    ap.add_argument("--fe", nargs=2, metavar=("TARGET", "DIR"))
    ap.add_argument("--collect", metavar="DIR")
    ap.add_argument("--bh-check", metavar="DIR", help="the BH of the designs from as built")
    ap.add_argument(
        "--symmetrize",
        action="store_true",
        help="with --fe: average each strip's lambda over its mirror images whatever its "
        "departure (the quarter model; the departure is recorded)",
    )
    ap.add_argument("--data", default=str(DATA))
    ap.add_argument(
        "--space-map",
        nargs=2,
        metavar=("TARGET", "DIR"),
        help="the FE-corrected design loop (output space mapping) from the design of TARGET",
    )
    ap.add_argument(
        "--iterations", type=int, default=3, help="with --space-map: most FE runs (>= 1)"
    )
    ap.add_argument("--collect-space-map", metavar="DIR")
    ap.add_argument("--space-map-data", default=str(SPACE_MAP_DATA))
    a = ap.parse_args(argv)
    try:
        return _main(a)
    except FileNotFoundError as exc:  # a step run before the one that writes its input
        print(f"{exc.filename}: missing (run the step that writes it first)", file=sys.stderr)
        return 2


def _main(a) -> int:
    if a.design:
        for t in a.target or TARGETS:
            design(t, pathlib.Path(a.design))
    if a.fe:
        if a.fe[0] not in TARGETS:
            print(f"--fe: target {a.fe[0]!r}: allowed {', '.join(TARGETS)}", file=sys.stderr)
            return 2
        fe_run(a.fe[0], pathlib.Path(a.fe[1]), force=a.symmetrize)
    if a.bh_check:
        for t in a.target or TARGETS:
            bh_check(t, pathlib.Path(a.bh_check))
    if a.space_map:
        if a.space_map[0] not in TARGETS:
            print(
                f"--space-map: target {a.space_map[0]!r}: allowed {', '.join(TARGETS)}",
                file=sys.stderr,
            )
            return 2
        if a.iterations < 1:
            print(f"--iterations: {a.iterations}: allowed an integer >= 1", file=sys.stderr)
            return 2
        space_map(a.space_map[0], pathlib.Path(a.space_map[1]), a.iterations, pathlib.Path(a.data))
    if a.collect:
        collect(pathlib.Path(a.collect), pathlib.Path(a.data))
    if a.collect_space_map:
        collect_space_map(pathlib.Path(a.collect_space_map), pathlib.Path(a.space_map_data))
    return 0


if __name__ == "__main__":
    sys.exit(main())
