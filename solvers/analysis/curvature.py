"""Curvature measures of solved shapes (units: mm, 1/mm).

* :func:`circle_fit`, :func:`signed_circle_curvature`: Pratt's circle through 3-D points, and its
  sign relative to an "up" vector.
* :func:`beam_curvature`: the composite beam's curvature through its middle stations, positive when
  the beam bends towards its bottom strips (the sign of Eq. 2, seed 001).
* :func:`quadratic_surface_curvatures`: principal curvatures and directions at a point of the
  quadratic surface w = a + b u + c v + (A u^2 + 2 B u v + C v^2)/2 fitted by least squares through
  points given in a local frame (u, v, w) (seed 001, Materials and Methods: "These nine points were
  then used to fit a quadratic surface to calculate the principal curvatures").
* :func:`gridshell_curvatures`: both of the paper's measures at the gridshell's centre junction:
  (1) the circle through the apex (centre junction) and the two ends of the middle composite beam,
  in x and in y (the paper's method for the gridshell without cover scales); (2) the quadratic
  surface through the junction centres (the paper's method with cover scales, nine points for 3 x
  3).

Sign of surface curvatures (seed 001, Fig. 4: "the principal curvatures [of the dome] are both
negative"): kappa = d^2 w/ds^2 with w along the centre junction's normal on the top strips' side
(+z as built), i.e. positive for a bowl (concave up), negative for a dome (cap). This is the
opposite of the beam's Eq. 2 sign: a beam bending towards its bottom strips (positive in Eq. 2) is a
cap (negative here).
"""

from __future__ import annotations

import math

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import beam_stations, beam_up_vector, middle_station_indices
from lcefem.models.errors import InputError


def circle_fit(points) -> tuple[float, np.ndarray, np.ndarray]:
    """Pratt's algebraic circle fit in the best-fit plane of 3-D points.

    Returns (curvature [1/mm] >= 0, centre (3,) [mm] (nan for a straight line), plane normal (3,)).
    Exact for three points (the circumcircle); zero curvature for collinear points.
    (V. Pratt, "Direct least-squares fitting of algebraic surfaces", Computer Graphics 21, 1987;
    the SVD implementation of N. Chernov, "Circular and linear regression", CRC 2010, Sec. 5.5.)
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[0] < 3 or pts.shape[1] != 3:
        raise InputError("points: need an array (n >= 3, 3) for a circle fit")
    centroid = pts.mean(axis=0)
    q = pts - centroid
    _, _, vt = np.linalg.svd(q)
    e1, e2, normal = vt[0], vt[1], vt[2]
    u, v = q @ e1, q @ e2
    scale = max(np.sqrt(np.mean(u**2 + v**2)), 1e-300)
    u, v = u / scale, v / scale
    z = u**2 + v**2
    zmat = np.column_stack([z, u, v, np.ones_like(u)])
    _, sv, vtz = np.linalg.svd(zmat, full_matrices=True)
    if zmat.shape[0] < 4 or sv[-1] < 1e-12 * sv[0]:  # exact fit: the null vector
        coef = vtz[-1]
    else:
        y = vtz.T @ np.diag(sv) @ vtz
        b_inv = np.array([[0, 0, 0, -0.5], [0, 1, 0, 0], [0, 0, 1, 0], [-0.5, 0, 0, 0]])
        vals, vecs = np.linalg.eig(y @ b_inv @ y)
        vals = vals.real
        ok = np.flatnonzero(vals > 0)
        coef = np.linalg.solve(y, vecs[:, ok[np.argmin(vals[ok])]].real)
    a, b, c, dd = coef
    disc = b**2 + c**2 - 4.0 * a * dd
    if disc <= 0:
        raise InputError("points: degenerate circle fit")
    curvature = 2.0 * abs(a) / math.sqrt(disc) / scale
    if abs(a) < 1e-14 * math.sqrt(disc):
        return 0.0, np.full(3, np.nan), normal
    cu, cv = -b / (2.0 * a) * scale, -c / (2.0 * a) * scale
    return curvature, centroid + cu * e1 + cv * e2, normal


def signed_circle_curvature(points, up) -> float:
    """Curvature [1/mm] of the circle fitted through ``points``; positive when the circle's centre
    lies on the side opposite to ``up`` (the beam bends away from ``up``, towards its bottom)."""
    kappa, centre, _ = circle_fit(points)
    if kappa == 0.0:
        return 0.0
    side = np.dot(centre - np.mean(points, axis=0), np.asarray(up, dtype=float))
    return -kappa if side > 0 else kappa


def beam_curvature(structure: BarHingeStructure, positions, stations=None) -> float:
    """Signed curvature [1/mm] of the beam through the middle stations (see the module docstring).

    Args:
        stations: station indices to fit (default :func:`middle_station_indices`).
    """
    pts = beam_stations(structure, positions)
    idx = middle_station_indices(pts.shape[0] - 1) if stations is None else np.asarray(stations)
    return signed_circle_curvature(pts[idx], beam_up_vector(structure, positions))


# --------------------------------------------------------------------------- surfaces
def quadratic_surface_curvatures(u, v, w) -> dict:
    """Least-squares quadratic w = a + b u + c v + (A u^2 + 2 B u v + C v^2)/2 through points (u, v,
    w) [mm] of a local frame, and its curvatures at u = v = 0.

    With the gradient p = (b, c), the first fundamental form I = [[1 + b^2, b c], [b c, 1 + c^2]]
    and the second II = [[A, B], [B, C]]/sqrt(1 + b^2 + c^2) (do Carmo 1976, Sec. 3-3), the
    principal curvatures are the eigenvalues of I^-1 II and the principal directions their
    eigenvectors (in (u, v) coordinates, mapped to the tangent vectors (1, 0, b) and (0, 1, c)).

    Returns:
        dict with "k1" <= "k2" [1/mm], "dir1", "dir2" (unit 3-vectors in the (u, v, w) frame),
        "ku", "kv" (normal curvatures along the u and v coordinate lines) [1/mm], "gaussian"
        [1/mm^2], "mean" [1/mm], "coefficients" (a, b, c, A, B, C), "rms_residual" [mm].
        Signs: positive when the surface curves towards +w (a bowl).
    """
    u, v, w = (np.asarray(a, dtype=float).ravel() for a in (u, v, w))
    if not (u.size == v.size == w.size) or u.size < 6:
        raise InputError("points: need at least 6 points (u, v, w) for a quadratic surface fit")
    design = np.column_stack([np.ones_like(u), u, v, 0.5 * u**2, u * v, 0.5 * v**2])
    coef, _, rank, _ = np.linalg.lstsq(design, w, rcond=None)
    if rank < 6:
        raise InputError("points: degenerate layout for a quadratic surface fit (rank < 6)")
    a, b, c, A, B, C = coef
    first = np.array([[1.0 + b * b, b * c], [b * c, 1.0 + c * c]])
    second = np.array([[A, B], [B, C]]) / math.sqrt(1.0 + b * b + c * c)
    # Symmetric form of I^-1 II: L^-1 II L^-T with I = L L^T (same eigenvalues).
    chol = np.linalg.cholesky(first)
    li = np.linalg.inv(chol)
    vals, vecs = np.linalg.eigh(li @ second @ li.T)
    dirs = []
    for k in range(2):
        duv = li.T @ vecs[:, k]
        t = np.array([duv[0], duv[1], b * duv[0] + c * duv[1]])
        dirs.append(t / np.linalg.norm(t))
    resid = w - design @ coef
    return {
        "k1": float(vals[0]),
        "k2": float(vals[1]),
        "dir1": dirs[0],
        "dir2": dirs[1],
        "ku": float(second[0, 0] / first[0, 0]),
        "kv": float(second[1, 1] / first[1, 1]),
        "gaussian": float(np.linalg.det(second) / np.linalg.det(first)),
        "mean": float(0.5 * (vals[0] + vals[1])),
        "coefficients": coef,
        "rms_residual": float(np.sqrt(np.mean(resid**2))),
    }


def junction_centre_points(structure: BarHingeStructure, positions=None) -> np.ndarray:
    """Junction centres (n, n, 3) [mm] of a gridshell: the mean of each junction square's four
    corners (the same station as the composite beam's); (J, 3) on a triangular grid (the mean of
    each hexagon's six vertices, lcefem.meshes.gridshell_tri)."""
    x = structure.nodes if positions is None else np.asarray(positions).reshape(-1, 3)
    return x[structure.node_sets["junction_corners"]].mean(axis=-2)


def centre_junction_point(structure: BarHingeStructure, positions=None) -> np.ndarray:
    """The centre junction's centre (3,) [mm] (:func:`junction_centre_points`)."""
    pts = junction_centre_points(structure, positions)
    if "centre_junction_index" in structure.info:
        return pts[structure.info["centre_junction_index"]]
    n = structure.info["ribbons"]
    return pts[n // 2, n // 2]


def normal_curvature_y(k0: float, k60: float, k120: float) -> float:
    """Normal curvature along y [1/mm] of the quadratic form whose normal curvatures along 0, 60 and
    120 deg are k0, k60, k120 (Euler: k(t) = kxx cos^2 t + 2 kxy cos t sin t + kyy sin^2 t, so
    k60 + k120 = kxx/2 + 3 kyy/2): kyy = (2 (k60 + k120) - k0)/3."""
    return (2.0 * (k60 + k120) - k0) / 3.0


def centre_frame(structure: BarHingeStructure, positions=None) -> tuple[np.ndarray, np.ndarray]:
    """(origin, rows e1, e2, e3) of the centre junction's frame: origin its centre, e3 its unit
    normal on the top strips' side, e1 its x edge direction (corner 0 -> 1) in the tangent plane."""
    x = structure.nodes if positions is None else np.asarray(positions).reshape(-1, 3)
    c = x[structure.node_sets["centre_junction"]]
    e3 = np.cross(c[1] - c[0], c[3] - c[0])
    e3 /= np.linalg.norm(e3)
    e1 = (c[1] - c[0]) + (c[2] - c[3])
    e1 -= np.dot(e1, e3) * e3
    e1 /= np.linalg.norm(e1)
    return c.mean(axis=0), np.vstack([e1, np.cross(e3, e1), e3])


def gridshell_curvatures(structure: BarHingeStructure, positions=None) -> dict:
    """The paper's two curvature measures at the centre junction of a gridshell [1/mm] (module
    docstring; sign: positive for a bowl, negative for a dome, as seed 001).

    Returns a dict with "circle_x", "circle_y" (circle through the two ends of the middle x / y
    ribbon and the centre junction's centre; on a triangular grid "circle_a", "circle_b",
    "circle_c" along its three middle ribbons, "circle_x" = "circle_a" and "circle_y" the y
    curvature of the quadratic form through the three, :func:`normal_curvature_y`; on a honeycomb
    the circles run through the centre junction and its two nearest junctions on the line along
    each direction, ``info["circle_junctions"]``), "quad_k1" <=
    "quad_k2", "quad_dir1", "quad_dir2" (principal directions in the global frame), "quad_kx",
    "quad_ky" (normal curvatures along the centre junction's x and y edges), "gaussian" [1/mm^2]
    and "rms_residual" [mm] of the fit.
    """
    x = structure.nodes if positions is None else np.asarray(positions).reshape(-1, 3)
    n = structure.info["ribbons"]
    # a honeycomb (lcefem.meshes.gridshell_hex) has a centre junction for every n
    if n % 2 == 0 and "circle_junctions" not in structure.info:
        raise InputError(
            f"ribbons = {n}: the centre-junction curvatures need an odd number of ribbons"
        )
    origin, frame = centre_frame(structure, x)
    up = frame[2]
    out = {}
    apex = centre_junction_point(structure, x)
    families = structure.info.get("families", ("x", "y"))
    circle = structure.info.get("circle_junctions")
    for direction in families:
        if circle is not None:  # a honeycomb: the junctions next to the centre on its line
            ends = junction_centre_points(structure, x)[list(circle[direction])]
        else:
            ends = x[structure.node_sets[f"ribbon_ends_{direction}"][n // 2]].mean(axis=1)
        out[f"circle_{direction}"] = -signed_circle_curvature(
            np.vstack([ends[0], apex, ends[1]]), up
        )
    if "y" not in families:  # three families at 0, 60, 120 deg
        out["circle_x"] = out["circle_a"]
        out["circle_y"] = normal_curvature_y(out["circle_a"], out["circle_b"], out["circle_c"])
    pts = junction_centre_points(structure, x).reshape(-1, 3) - origin
    local = pts @ frame.T
    if local.shape[0] >= 6:
        q = quadratic_surface_curvatures(local[:, 0], local[:, 1], local[:, 2])
        out.update(
            quad_k1=q["k1"],
            quad_k2=q["k2"],
            quad_dir1=q["dir1"] @ frame,
            quad_dir2=q["dir2"] @ frame,
            quad_kx=q["ku"],
            quad_ky=q["kv"],
            gaussian=q["gaussian"],
            rms_residual=q["rms_residual"],
        )
    return out
