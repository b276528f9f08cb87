"""The FE gridshell's hexahedral mesh made by gmsh (the project's mesher) from the same plan as the
structured builder (:mod:`lcefem.meshes.gridshell_fe`): every in-plane piece of the plan (tab,
flank, crown, junction part; :func:`~lcefem.meshes.gridshell_fe.axis_pieces`) times every layer
(bottom strip, ribbon, top strip) is one block of gmsh's built-in kernel, meshed transfinite and
recombined into hexahedra with the plan's element counts (``divisions``), so the cells are the hex8
cells of the structured builder (Q2 fields on top, as there).

Why gmsh's built-in kernel with hand-made topology, not OCC boxes and ``fragment``: fragment merges
every pair of coincident faces, whereas a strip's unbonded face must keep its own nodes (only the
contact term keeps it off the ribbon). Here each point, curve and surface is made once per *owner*:
an entity on the ribbon/strip interface belongs to the ribbon (shared, bonded) when it lies on a
bonded block (a bottom pad under a tab or junction, a crown pad), else each body makes its own copy
at the same place (apart). Inside one layer neighbouring blocks share their faces (one body).

The blocks are flat boxes; the arch is put on afterwards, node by node, with the structured
builder's rule: ribbon nodes and the crown pads' column are lifted by the arch
z = gap sin^2(pi s/L) of both axes (zero on junctions and tabs); the other top nodes sit at the
crown-edge height z_c; the bottom layer stays flat. In-plane, each node is put on the plan's station
it lies on (gmsh places it there to round-off, ~1e-14 mm), so the mesh has exactly the structured
builder's vertices, cells and tags (tests/meshes/test_gridshell_fe_gmsh.py) and the same results.

:func:`build_gridshell_fe_gmsh` has :func:`~lcefem.meshes.gridshell_fe.build_gridshell_fe`'s
arguments and returns the same :class:`~lcefem.meshes._gmsh.TaggedMesh`; ``shear_angle`` maps the
mesh onto a rhombic layout (:mod:`lcefem.meshes.gridshell_layout`): (x, y) -> x e1 + y e2.
"""

from __future__ import annotations

import math

import numpy as np

from lcefem.meshes._hexgrid import divisions
from lcefem.meshes.communicator import resolve_comm
from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell_fe import (
    FE_FACETS,
    MATERIAL_CELLS,
    SYMMETRIES,
    GridshellFEMesh,
    arch_at,
    axis_pieces,
    axis_stations,
    cell_groups_of,
    checked_inputs,
    facet_names_of,
    mesh_info,
    plan_regions,
    strip_catalogue,
)

#: Layer index of each body: bottom strips (0), ribbon (1), top strips (2); z levels 0..3 bound
#: them.
_LAYER = {"b": 0, "r": 1, "t": 2}


def _bonded(blocks: set, kind: str, i: int, j: int) -> bool:
    """Whether an interface entity touches a bonded block of ``blocks`` ((i, j) in-plane blocks):
    a point (i, j) any of its four blocks, an x-edge (i..i+1, j) either of its two, a y-edge
    (i, j..j+1) either of its two, a face (i, j) itself."""
    if kind == "p":
        return any((i - a, j - b) in blocks for a in (0, 1) for b in (0, 1))
    if kind == "ex":
        return (i, j) in blocks or (i, j - 1) in blocks
    if kind == "ey":
        return (i, j) in blocks or (i - 1, j) in blocks
    return (i, j) in blocks


def build_gridshell_fe_gmsh(
    geometry: CompositeBeamGeometry,
    lambda_N: float,
    mesh: GridshellFEMesh = GridshellFEMesh(),
    comm=None,
    cells: int = 3,
    symmetry: str = "quarter",
    shear_angle: float | None = None,
):
    """Hexahedral mesh of the as-built n x n gridshell made by gmsh (module docstring); arguments,
    tags and ``info`` as :func:`lcefem.meshes.gridshell_fe.build_gridshell_fe`.

    ``shear_angle`` [deg] (default ``mesh.shear_angle``): the angle between the two ribbon
    families (90: the orthogonal grid); at
    another angle the built mesh is mapped (x, y) -> x e1 + y e2, e1 = (1, 0), e2 = (cos a, sin a)
    (the rhombic layout; ``geometry`` in the oblique coordinates, :meth:`Layout.geometry`), a full
    model only (the mirror planes x = c, y = c are not mirror planes of a rhombic grid);
    ``info["shear_angle"]`` then records it and ``info["directions"]`` the two unit vectors.
    """
    from lcefem.meshes._gmsh import TaggedMesh, gmsh_session, to_dolfinx
    from lcefem.models.errors import InputError

    comm = resolve_comm(comm)
    g, n, m, tp, W, ws, H = checked_inputs(geometry, lambda_N, mesh, cells, symmetry)
    shear_angle = m.shear_angle if shear_angle is None else shear_angle
    if not (isinstance(shear_angle, (int, float)) and 30.0 <= shear_angle <= 150.0):
        raise InputError(f"shear_angle = {shear_angle!r}: must be from 30 to 150 deg")
    if shear_angle != 90.0 and symmetry != "full":
        raise InputError(
            f"symmetry = {symmetry!r}: a rhombic grid ({shear_angle} deg) has no mirror "
            "plane x = c or y = c; allowed 'full'"
        )
    cut_x, cut_y = SYMMETRIES[symmetry]
    mult = m.level + 1
    length = (n + 1) * g.segment_length + n * g.junction_length
    centre = 0.5 * length
    pieces = [axis_pieces(g, n, m.end_tab, ws, cut) for cut in (cut_x, cut_y)]
    # the plan's stations (the structured builder's nodes) and each piece's element count
    stations = [axis_stations(p, m.size, mult)[0] for p in pieces]
    coarse = [np.array([p[0] for p in ps] + [ps[-1][1]]) for ps in pieces]
    counts = [[divisions(p[1] - p[0], m.size, mult) for p in ps] for ps in pieces]
    z_levels = (-0.5 * tp - H, -0.5 * tp, 0.5 * tp, 0.5 * tp + H)
    layers = (m.strip_layers, m.ribbon_layers, m.strip_layers)

    catalogue = strip_catalogue(g, n, ws)
    names = list(MATERIAL_CELLS) + list(catalogue)
    tag = {name: k for k, name in enumerate(names, start=1)}
    blocks = []  # (i, j, body, name)
    bonded = {"b": set(), "t": set()}
    for i, pxi in enumerate(pieces[0]):
        for j, pyj in enumerate(pieces[1]):
            ribbon, bottom, top = plan_regions(pxi, pyj, n)
            if not ribbon:
                continue
            blocks.append((i, j, "r", "kapton"))
            if bottom is not None:
                blocks.append((i, j, "b", bottom))
                if bottom == "bottom_pads":
                    bonded["b"].add((i, j))
            if top is not None:
                blocks.append((i, j, "t", top))
                if top == "top_pads":
                    bonded["t"].add((i, j))
    crown = sorted(bonded["t"])
    ftag = {name: k for k, name in enumerate(FE_FACETS, start=1)}
    strips = {k: v for k, v in catalogue.items() if k in {b[3] for b in blocks}}
    present_names = sorted({b[3] for b in blocks}, key=tag.get)
    info = mesh_info(
        g,
        n,
        m,
        symmetry,
        float(lambda_N),
        ws,
        H,
        strips,
        cell_groups_of(present_names, tag, strips),
    )
    info["mesher"] = "gmsh"
    if shear_angle != 90.0:
        a = math.radians(shear_angle)
        info["shear_angle"] = float(shear_angle)
        info["directions"] = ((1.0, 0.0), (math.cos(a), math.sin(a)))

    with gmsh_session("gridshell_fe") as model:
        if comm.rank == 0:
            geo = model.geo
            points, curves, surfaces = {}, {}, {}
            curve_ends, curve_count = {}, {}

            def owner(body: str, k: int, kind: str, i: int, j: int) -> str:
                # an interface entity on a bonded block is the ribbon's (shared); else the body's
                # own
                if body == "b" and k == 1 and _bonded(bonded["b"], kind, i, j):
                    return "r"
                if body == "t" and k == 2 and _bonded(bonded["t"], kind, i, j):
                    return "r"
                return body

            def point(i, j, k, body):
                key = (i, j, k, owner(body, k, "p", i, j))
                if key not in points:
                    points[key] = geo.addPoint(coarse[0][i], coarse[1][j], z_levels[k])
                return points[key]

            def curve(kind, i, j, k, body):
                """x-edge (i..i+1, j, k), y-edge (i, j..j+1, k) or z-edge (i, j, k..k+1)."""
                if kind == "ez":
                    key = (kind, i, j, k, body)
                    ends = (point(i, j, k, body), point(i, j, k + 1, body))
                    count = layers[_LAYER[body]]
                else:
                    key = (kind, i, j, k, owner(body, k, kind, i, j))
                    a, b = (i + 1, j) if kind == "ex" else (i, j + 1)
                    ends = (point(i, j, k, body), point(a, b, k, body))
                    count = counts[0][i] if kind == "ex" else counts[1][j]
                if key not in curves:
                    curves[key] = geo.addLine(*ends)
                    curve_ends[curves[key]] = ends
                    curve_count[curves[key]] = count
                return curves[key]

            def surface(key, loop_points, loop_curves):
                if key not in surfaces:
                    signed = []
                    for c, (p, q) in zip(
                        loop_curves, zip(loop_points, loop_points[1:] + loop_points[:1])
                    ):
                        signed.append(c if curve_ends[c] == (p, q) else -c)
                    surfaces[key] = geo.addPlaneSurface([geo.addCurveLoop(signed)])
                return surfaces[key]

            def h_face(i, j, k, body):
                key = ("h", i, j, k, owner(body, k, "f", i, j))
                ps = [
                    point(i, j, k, body),
                    point(i + 1, j, k, body),
                    point(i + 1, j + 1, k, body),
                    point(i, j + 1, k, body),
                ]
                cs = [
                    curve("ex", i, j, k, body),
                    curve("ey", i + 1, j, k, body),
                    curve("ex", i, j + 1, k, body),
                    curve("ey", i, j, k, body),
                ]
                return surface(key, ps, cs)

            def x_face(i, j, k, body):  # the plane x = X_i, y in block j, z in layer k..k+1
                ps = [
                    point(i, j, k, body),
                    point(i, j + 1, k, body),
                    point(i, j + 1, k + 1, body),
                    point(i, j, k + 1, body),
                ]
                cs = [
                    curve("ey", i, j, k, body),
                    curve("ez", i, j + 1, k, body),
                    curve("ey", i, j, k + 1, body),
                    curve("ez", i, j, k, body),
                ]
                return surface(("vx", i, j, k, body), ps, cs)

            def y_face(i, j, k, body):
                ps = [
                    point(i, j, k, body),
                    point(i + 1, j, k, body),
                    point(i + 1, j, k + 1, body),
                    point(i, j, k + 1, body),
                ]
                cs = [
                    curve("ex", i, j, k, body),
                    curve("ez", i + 1, j, k, body),
                    curve("ex", i, j, k + 1, body),
                    curve("ez", i, j, k, body),
                ]
                return surface(("vy", i, j, k, body), ps, cs)

            volumes, uses = {}, {}  # name -> volume tags; surface -> [(side, body, corners)]
            for i, j, body, name in blocks:
                k = _LAYER[body]
                faces = {
                    "-z": h_face(i, j, k, body),
                    "+z": h_face(i, j, k + 1, body),
                    "-x": x_face(i, j, k, body),
                    "+x": x_face(i + 1, j, k, body),
                    "-y": y_face(i, j, k, body),
                    "+y": y_face(i, j + 1, k, body),
                }
                vol = geo.addVolume([geo.addSurfaceLoop(list(faces.values()))])
                volumes.setdefault(name, []).append(vol)
                x0, x1 = coarse[0][i], coarse[0][i + 1]
                y0, y1 = coarse[1][j], coarse[1][j + 1]
                for side, s in faces.items():
                    xs = (x0, x0) if side == "-x" else (x1, x1) if side == "+x" else (x0, x1)
                    ys = (y0, y0) if side == "-y" else (y1, y1) if side == "+y" else (y0, y1)
                    corners = [(xx, yy, 0.0) for xx in xs for yy in ys]
                    uses.setdefault(s, []).append((side, body, corners))
            geo.synchronize()
            for c, count in curve_count.items():
                model.mesh.setTransfiniteCurve(c, count + 1)
            for s in surfaces.values():
                model.mesh.setTransfiniteSurface(s)
                model.mesh.setRecombine(2, s)
            for vols in volumes.values():
                for v in vols:
                    model.mesh.setTransfiniteVolume(v)
                    model.mesh.setRecombine(3, v)

            # exterior faces (one volume) named by the structured builder's rules
            outer = [(s, u[0]) for s, u in uses.items() if len(u) == 1]
            pts = np.array([c for _, (_, _, c) in outer], dtype=float).reshape(-1, 4, 3)
            sides = np.array([u[0] for _, u in outer])
            bodies = np.array([u[1] for _, u in outer])
            facet_names = facet_names_of(
                pts,
                sides,
                bodies,
                cut_x,
                cut_y,
                centre,
                (-m.end_tab, length + m.end_tab),
                0.5 * g.junction_length,
                n % 2 == 1,
                1e-9 * length,
            )
            for name in sorted(volumes, key=tag.get):
                model.addPhysicalGroup(3, volumes[name], tag[name], name)
            for name in FE_FACETS:
                chosen = [s for (s, _), f in zip(outer, facet_names) if f == name]
                if chosen:
                    model.addPhysicalGroup(2, chosen, ftag[name], name)
            model.mesh.generate(3)
            _place_nodes(
                model,
                volumes,
                stations,
                g,
                n,
                z_levels,
                (tp, H),
                layers,
                coarse,
                crown,
                shear_angle,
                1e-9 * length,
            )
        data, cell_names, facet_names_map = to_dolfinx(model, comm)
    num = data.mesh.topology.index_map(3).size_global
    info.update(cells=int(num), nodes=int(data.mesh.geometry.index_map().size_global))
    return TaggedMesh(data.mesh, data.cell_tags, data.facet_tags, cell_names, facet_names_map, info)


def _station_index(values: np.ndarray, stations: np.ndarray, tol: float) -> np.ndarray:
    """Index of the station each value lies on (within ``tol`` [mm])."""
    k = np.clip(np.searchsorted(stations, values), 1, stations.size - 1)
    nearest = np.where(np.abs(stations[k - 1] - values) <= np.abs(stations[k] - values), k - 1, k)
    if np.any(np.abs(stations[nearest] - values) > tol):
        raise RuntimeError("gridshell gmsh mesh: a node is off the plan's stations")
    return nearest


def _place_nodes(
    model,
    volumes: dict,
    stations,
    g,
    n: int,
    z_levels,
    thickness,
    layers,
    coarse,
    crown,
    shear_angle: float,
    tol: float,
) -> None:
    """Move gmsh's nodes from the flat blocks to the as-built surface (module docstring)."""
    body_nodes = {"r": set(), "t": set()}
    for name, vols in volumes.items():
        body = (
            "r" if name == "kapton" else "t" if (name.startswith("top_") or name == "glue") else "b"
        )
        if body == "b":
            continue
        for v in vols:
            nodes = model.mesh.getNodes(3, v, includeBoundary=True)[0]
            body_nodes[body].update(int(t) for t in nodes)
    node_tags, xyz, _ = model.mesh.getNodes()
    x = np.asarray(xyz, dtype=float).reshape(-1, 3)
    ix = _station_index(x[:, 0], stations[0], tol)
    iy = _station_index(x[:, 1], stations[1], tol)
    x[:, 0], x[:, 1] = stations[0][ix], stations[1][iy]
    # the arch at the stations, as the structured builder evaluates it (bit for bit)
    mid = arch_at(g, n, stations[0])[ix] + arch_at(g, n, stations[1])[iy]
    is_r = np.fromiter((int(t) in body_nodes["r"] for t in node_tags), bool, len(node_tags))
    is_t = np.fromiter((int(t) in body_nodes["t"] for t in node_tags), bool, len(node_tags)) & ~is_r
    on_crown = np.zeros(len(node_tags), dtype=bool)
    for i, j in crown:
        on_crown |= (
            (x[:, 0] >= coarse[0][i] - tol)
            & (x[:, 0] <= coarse[0][i + 1] + tol)
            & (x[:, 1] >= coarse[1][j] - tol)
            & (x[:, 1] <= coarse[1][j + 1] + tol)
        )
    # z by the structured builder's formulas, the layer index k from gmsh's (linear) flat z
    tp, H = thickness
    nb, nr, nt = layers
    is_b = ~(is_r | is_t)
    zf = x[:, 2]
    z = np.empty_like(zf)
    kb = np.rint((zf[is_b] - z_levels[0]) / H * nb)
    z[is_b] = -0.5 * tp - H * (nb - kb) / nb
    kr = np.rint((zf[is_r] - z_levels[1]) / tp * nr)
    z[is_r] = mid[is_r] + tp * (-0.5 + kr / nr)
    kt = np.rint((zf[is_t] - z_levels[2]) / H * nt)
    z[is_t] = np.where(on_crown[is_t], mid[is_t], g.top_strip_height) + 0.5 * tp + H * kt / nt
    x[:, 2] = z
    if shear_angle != 90.0:
        a = math.radians(shear_angle)
        x[:, 0], x[:, 1] = x[:, 0] + x[:, 1] * math.cos(a), x[:, 1] * math.sin(a)
    for t, p in zip(node_tags, x):
        model.mesh.setNode(int(t), p.tolist(), [])


def build_layout_fe(
    layout,
    geometry: CompositeBeamGeometry,
    lambda_N: float,
    mesh: GridshellFEMesh = GridshellFEMesh(),
    comm=None,
    symmetry: str | None = None,
):
    """The FE mesh of a :class:`~lcefem.meshes.gridshell_layout.Layout` made by gmsh: its ribbons
    per direction, its lengths (:meth:`Layout.geometry` on ``geometry``, the ``[geometry]``
    section) and, for a rhombic layout, its angle (the mesh mapped (x, y) -> x e1 + y e2).

    On a rhombic layout the strips keep their width across themselves (W_s, as built): in the
    oblique coordinates the builder works in, their cast width is ``strip_width / sin a`` as the
    ribbon's is ``ribbon_width / sin a`` (:meth:`Layout.geometry`).

    ``symmetry``: default the quarter model on an orthogonal layout (its mirror planes x = c and
    y = c), the full model on a rhombic one (none of those planes is a mirror plane). Refused with
    one line: the triangular and hexagonal kinds (three ribbons at a junction: not this plan's two
    layers of strips), and unbonded junctions (``glued`` other than 'all': the FE plan bonds every
    crossing).
    """
    from lcefem.meshes.gridshell_layout import FE_KINDS
    from lcefem.models.errors import InputError

    layout = layout.checked()
    if layout.kind not in FE_KINDS:
        raise InputError(
            f"layout.kind = {layout.kind!r}: the FE mesh is built for "
            f"{', '.join(FE_KINDS)} (two families of ribbons, two strips a junction)"
        )
    if layout.glued != "all":
        raise InputError(
            f"layout.glued = {layout.glued!r}: the FE mesh bonds every junction; allowed 'all'"
        )
    g = layout_fe_geometry(layout, geometry)
    if symmetry is None:
        symmetry = "full" if layout.oblique else "quarter"
    tm = build_gridshell_fe_gmsh(
        g, lambda_N, mesh, comm, layout.ribbons, symmetry, shear_angle=float(layout.angle)
    )
    tm.info["layout"] = {
        "kind": layout.kind,
        "ribbons": layout.ribbons,
        "angle": float(layout.angle),
    }
    return tm


def layout_fe_geometry(layout, geometry: CompositeBeamGeometry) -> CompositeBeamGeometry:
    """The FE mesh's geometry of a layout in the builder's (oblique) coordinates:
    :meth:`Layout.geometry`, and on a rhombic layout the cast strip width / sin a, so that a strip
    keeps its width across itself after the map (x, y) -> x e1 + y e2 (as the ribbon does)."""
    import dataclasses

    g = layout.checked().geometry(geometry)
    if layout.oblique:
        g = dataclasses.replace(g, strip_width=g.strip_width / math.sin(math.radians(layout.angle)))
    return g
